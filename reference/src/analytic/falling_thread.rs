//! A reference for the round jet's fall (`jet` under `dimension = 3`): the slender-thread model
//! of an axisymmetric viscous or viscoelastic thread that leaves a round nozzle of diameter D at
//! U0 and falls under gravity, integrated in 1D until its leading end has fallen the nozzle
//! height. The 3D counterpart of the planar sheet ([`super::falling_sheet`]), and the equations
//! Matovich & Pearson 1969 wrote for it.
//!
//! **Model** (Matovich & Pearson 1969's long-wave equations of a stretched thread, made
//! transient as the sheet's: the thread is thin compared with its length, so across it the flow
//! is a uniform uniaxial extension and its surface is traction free). Along the thread, x
//! downward from the exit, the thread has cross-section A(x, t) and speed v(x, t):
//!
//! ```text
//! rho A (dv/dt) = d/dx (A (sigma_xx - sigma_rr)) + rho g A,     sigma_rr = 0 (free surface),
//! sigma_xx - sigma_rr = 3 eta_s e + tau_xx - tau_rr,   e = dv/dx,
//! ```
//!
//! Trouton 1906's uniaxial 3 eta_s for the solvent; the polymer's normal-stress difference from
//! its conformation tensor, which each material element carries through the uniaxial extension
//! kappa = diag(e, -e/2, -e/2) by the crate's own constitutive models in three dimensions
//! ([`viscosph::rheology`]: every model of King & Lind Table I, and Cross, whose viscosity
//! follows the extension rate). The leading end is free (zero tension); fluid leaves the exit at
//! U0 with the model's rest conformation, so the mass flux there is rho (pi D^2 / 4) U0.
//!
//! **Discretisation**: the sheet's (Lagrangian mass elements, forward Euler, the same step
//! limits); the two differ only in the cross-section (area instead of width per unit depth)
//! and the extension (uniaxial instead of planar). A Newtonian thread of viscosity eta is
//! therefore the sheet of viscosity 3 eta / 4 (a unit test checks it).
//!
//! **What it leaves out**: as the sheet, the head (a blob about D long where the model has a
//! free end) and the plate until the thread touches it. The SPH contact (first wall force: the
//! head within a kernel support of the plate's particles) comes a little before the model's
//! arrival.

use super::falling_sheet::{slender_arrival, SheetArrival};
use viscosph::scene::SceneConfig;

/// Elements per jet diameter that `viscosph run` and `viscosph exact falling-thread` use (the
/// sheet's resolution: the two discretisations are the same).
pub const ELEMENTS_PER_DIAMETER: usize = super::falling_sheet::ELEMENTS_PER_WIDTH;

/// The slender-thread arrival for the round jet of `cfg` (`jet_width` the nozzle's diameter,
/// `jet_velocity`, `nozzle_height`, `gravity`, `density` and the rheology), with
/// `per_diameter` elements per diameter at the exit: the time the free end has fallen the
/// nozzle height, its speed, the narrowest diameter (`min_width`) and the mass below the exit
/// \[kg\]. None if the thread has not arrived by `t_max` or its state stopped being finite.
pub fn arrival(cfg: &SceneConfig, per_diameter: usize, t_max: f64) -> Option<SheetArrival> {
    slender_arrival::<3>(cfg, per_diameter, t_max)
}

#[cfg(test)]
mod tests {
    use super::super::falling_sheet;
    use super::*;
    use viscosph::config::RheologyKind;
    use viscosph::scene::SceneKind;

    /// King & Lind's jet fluid through a round nozzle of their width.
    fn king_lind(rheology: RheologyKind, wi: f64) -> SceneConfig {
        let mut c = SceneConfig::for_scene(SceneKind::Jet);
        c.numerics.dimension = 3;
        c.fluid.rheology = rheology;
        c.fluid.relaxation_time = wi * 0.006 / 0.2;
        c
    }

    #[test]
    fn an_inviscid_thread_falls_freely() {
        // As the sheet: a point mass, H = U0 t + g t^2 / 2.
        let a = falling_sheet::tests::falls_freely(king_lind(RheologyKind::Newtonian, 0.0), |c| {
            arrival(c, 10, 1.0).unwrap()
        });
        // Free fall stretches the thread: the exit's D at the top, thinner below.
        assert!(a.min_width < 0.006, "{a:?}");
    }

    #[test]
    fn the_mass_below_the_exit_is_the_nozzle_flux_times_the_time() {
        // Whatever the fluid does below, rho (pi D^2 / 4) U0 t has left the nozzle, to within
        // one element of the feed (rho A0 D / 12 at 12 per diameter: 1.2 % of the 0.2 s flux).
        for (model, wi) in [
            (RheologyKind::Newtonian, 0.0),
            (RheologyKind::OldroydB, 5.0 / 3.0),
            (RheologyKind::FeneP, 5.0 / 3.0),
        ] {
            let c = king_lind(model, wi);
            let a = arrival(&c, 12, 1.0).unwrap();
            let area = std::f64::consts::FRAC_PI_4 * 0.006 * 0.006;
            let flux = 1023.0 * area * 0.2 * a.time;
            let element = 1023.0 * area * 0.006 / 12.0;
            assert!(
                (a.mass - flux).abs() <= element,
                "{model:?}: {} kg below the exit, flux x time {flux} kg",
                a.mass
            );
        }
    }

    #[test]
    fn a_newtonian_thread_is_the_sheet_of_three_quarters_the_viscosity() {
        // Trouton: 3 eta uniaxial against 4 eta planar, the same equations otherwise (the
        // cross-section cancels from the momentum balance per element); the time steps differ
        // (they follow the viscosity), so the two agree to the discretisation.
        let thread = king_lind(RheologyKind::Newtonian, 0.0);
        let mut sheet = thread.clone();
        sheet.numerics.dimension = 2;
        sheet.fluid.viscosity = 0.75 * thread.fluid.viscosity;
        let (a, b) = (
            arrival(&thread, 12, 1.0).unwrap(),
            falling_sheet::arrival(&sheet, 12, 1.0).unwrap(),
        );
        assert!((a.time - b.time).abs() < 1e-3 * b.time, "{a:?} {b:?}");
        // A width per depth D w against a diameter: w / D = (d / D)^2 along the same stretch.
        assert!(
            (a.min_width / 0.006 - (b.min_width / 0.006).sqrt()).abs() < 1e-2,
            "{a:?} {b:?}"
        );
        // And with the same viscosity the thread, held by 3 eta instead of 4 eta, lands first.
        sheet.fluid.viscosity = thread.fluid.viscosity;
        let same = falling_sheet::arrival(&sheet, 12, 1.0).unwrap();
        assert!(a.time < same.time, "{a:?} {same:?}");
    }

    #[test]
    fn king_and_linds_thread_converges_and_elasticity_speeds_the_fall() {
        let newt = king_lind(RheologyKind::Newtonian, 0.0);
        let coarse = arrival(&newt, 6, 1.0).unwrap();
        let fine = arrival(&newt, 12, 1.0).unwrap();
        println!("Newtonian thread: {coarse:?} {fine:?}");
        assert!((coarse.time - fine.time).abs() < 0.005 * fine.time);
        // Between free fall (0.1024 s) and the sheet's 0.2249 s.
        assert!(fine.time > 0.15 && fine.time < 0.2249, "{fine:?}");
        falling_sheet::tests::elasticity_speeds_the_fall(fine, |wi| {
            arrival(&king_lind(RheologyKind::OldroydB, wi), 12, 1.0).unwrap()
        });
    }

    #[test]
    fn every_rheology_reaches_the_plate() {
        // The crate's constitutive models in three dimensions: every one of them falls.
        for (name, _) in viscosph::config::RHEOLOGIES {
            let model = RheologyKind::parse(name).expect("a model of the table");
            let a = arrival(&king_lind(model, 5.0 / 3.0), 6, 2.0);
            let a = a.unwrap_or_else(|| panic!("{model:?} did not arrive"));
            assert!(a.time > 0.1 && a.time < 2.0, "{model:?}: {a:?}");
        }
    }
}
