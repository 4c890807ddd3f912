//! A reference for the jet's fall: the slender-sheet (thin-film) model of a planar viscous or
//! viscoelastic sheet that leaves a nozzle at U0 and falls under gravity, integrated in 1D until
//! its leading end has fallen the nozzle height. It gives the time the jet reaches the plate,
//! which King & Lind 2021 (section IV.D) report only qualitatively ("reaches the plate earlier
//! at higher Wi"), so that the SPH schemes' arrival times can be checked against a number.
//!
//! **Model** (the long-wave equations of a stretched viscous thread, Matovich & Pearson 1969,
//! in their planar form: the sheet is thin compared with its length, so across it the flow is a
//! uniform planar extension and its sides are traction free; the extensional viscosity is then
//! 4 eta, Trouton 1906's 3 eta being the uniaxial value). Along the sheet, x downward from the
//! exit, the sheet has width w(x, t) and speed v(x, t); per unit depth
//!
//! ```text
//! rho w (dv/dt) = d/dx (w sigma_xx) + rho g w,     sigma_yy = 0 (free sides),
//! sigma_xx - sigma_yy = 4 eta_s e + tau_xx - tau_yy,   e = dv/dx,
//! ```
//!
//! i.e. the tension T = w (4 eta_s e + tau_p,xx - tau_p,yy): Trouton's planar 4 eta_s for the
//! solvent, the polymer's normal-stress difference from its conformation tensor, which each
//! material element carries through the planar extension kappa = diag(e, -e) by the crate's
//! own constitutive models ([`viscosph::rheology`], every model of King & Lind Table I and Cross,
//! whose viscosity follows the extension rate through `solvent_viscosity`). The leading end is
//! free (T = 0); fluid leaves the exit at U0 with the model's rest conformation.
//!
//! **Discretisation**: Lagrangian mass elements (`rho D dx0` each, `dx0 = D / n`), nodes and
//! conformations moved by forward Euler at half the explicit viscous limit
//! `rho dx0^2 / (8 eta_max)`, a fiftieth of the relaxation time and a hundredth of dx0 at the
//! free-fall speed (steps far below what the conformation's own accuracy needs); an element is
//! added at the exit each time the last one has left a full length. Converged to 0.4 %
//! (Newtonian arrival 0.2237 / 0.2245 / 0.2249 s at dx0 = 1 / 0.5 / 0.25 mm for King & Lind's
//! jet; Oldroyd-B Wi = 5/3: 0.2027 / 0.2035 / 0.2039 s).
//!
//! **What it leaves out**: the head. A real (and an SPH) jet's leading end is a blunt, 2D blob
//! about D long, which the slender model replaces by a free end; and the sheet ignores the
//! plate until it touches it. The SPH "contact" (first wall force: the head within a kernel
//! support of the wall particles) comes a little (about 2 dx / v) before the model's arrival.

use viscosph::dim::{Const, Dim, Tensor};
use viscosph::rheology::{advance, AnyRheology, ConformationMethod, Rheology};
use viscosph::scene::SceneConfig;

/// Elements per jet width that `viscosph run` and `viscosph bench jet` use: within 0.4 % of
/// converged for King & Lind's jet, about 0.1 s to compute.
pub const ELEMENTS_PER_WIDTH: usize = 10;

/// What [`arrival`] (and the thread's [`super::falling_thread::arrival`]) found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheetArrival {
    /// Time at which the leading end has fallen the nozzle height \[s\].
    pub time: f64,
    /// Speed of the leading end then [m/s].
    pub tip_speed: f64,
    /// Narrowest width of the sheet (the thread: its narrowest diameter) then \[m\] (as a
    /// fraction of D: how thin the column gets, in particles across when multiplied by
    /// `particles_per_diameter`).
    pub min_width: f64,
    /// Mass below the exit then: per unit depth for the sheet \[kg/m\], the thread's \[kg\].
    /// Fluid enters at rho A0 U0 (A0 = D per unit depth, pi D^2 / 4 for the thread), so this is
    /// rho A0 U0 `time` to within one element.
    pub mass: f64,
}

/// The slender-sheet arrival time for the jet of `cfg` (`jet_width`, `jet_velocity`,
/// `nozzle_height`, `gravity`, `density` and the rheology), with `per_width` elements per jet
/// width at the exit. None if the sheet has not arrived by `t_max` (no gravity and no exit
/// speed, or a sheet held up) or its state stopped being finite.
pub fn arrival(cfg: &SceneConfig, per_width: usize, t_max: f64) -> Option<SheetArrival> {
    slender_arrival::<2>(cfg, per_width, t_max)
}

/// The slender fall in N dimensions: the planar sheet (N = 2, cross-section the width per
/// unit depth, planar extension diag(e, -e), Trouton ratio 4) or the axisymmetric thread
/// (N = 3, cross-section the area, uniaxial extension diag(e, -e/2, -e/2), Trouton ratio 3):
/// the same Lagrangian elements, only the cross-section and the extension differ.
pub(crate) fn slender_arrival<const N: usize>(
    cfg: &SceneConfig,
    per_width: usize,
    t_max: f64,
) -> Option<SheetArrival>
where
    Const<N>: Dim,
{
    let model = AnyRheology::from_config(cfg).ok()?;
    viscosph::dispatch_rheology!(&model, m => arrival_with::<N, _>(m, cfg, per_width, t_max))
}

/// The cross-section of a slender jet of width (diameter) d in N dimensions: d per unit depth
/// for the sheet, pi d^2 / 4 for the thread; `inverse`: the width of a cross-section d.
fn section<const N: usize>(d: f64, inverse: bool) -> f64 {
    let quarter_pi = std::f64::consts::FRAC_PI_4;
    match (N == 2, inverse) {
        (true, _) => d,
        (false, false) => quarter_pi * d * d,
        (false, true) => (d / quarter_pi).sqrt(),
    }
}

fn arrival_with<const N: usize, R: Rheology>(
    model: &R,
    cfg: &SceneConfig,
    per_width: usize,
    t_max: f64,
) -> Option<SheetArrival>
where
    Const<N>: Dim,
{
    let (rho, d, u0, g, h) = (
        cfg.fluid.density,
        cfg.jet.jet_width,
        cfg.jet.jet_velocity,
        cfg.fluid.gravity,
        cfg.jet.nozzle_height,
    );
    let dx0 = d / per_width.max(1) as f64;
    let dm = rho * section::<N>(d, false) * dx0;
    let mut dt = 0.5 * rho * dx0 * dx0 / (8.0 * model.max_viscosity().max(1e-12));
    if R::ELASTIC {
        dt = dt.min(model.relaxation_time() / 50.0);
    }
    // And a hundredth of an element length at the free-fall speed (a nearly inviscid sheet).
    dt = dt.min(0.01 * dx0 / (u0 * u0 + 2.0 * g.abs() * h).sqrt().max(1e-12));
    // Nodes from the leading end (index 0) up into the nozzle; x downward from the exit. The
    // nozzle holds a few elements moving at U0 so that one always straddles the exit.
    let held = 4;
    let mut x: Vec<f64> = (0..=held).map(|k| -(k as f64) * dx0).collect();
    let mut v = vec![u0; x.len()];
    // The conformation tensor of each element.
    let mut el = vec![model.rest_conformation::<N>(); held];
    let mut tension = vec![0.0; el.len()];
    // The extension along the axis at unit rate: the other N - 1 directions contract, sharing
    // it (incompressible). The solvent's axial minus lateral stress is then
    // 2 eta (1 + 1/(N - 1)) e: Trouton's 4 eta e (planar) and 3 eta e (uniaxial).
    let lateral = -1.0 / (N as f64 - 1.0);
    let trouton = 2.0 * (1.0 - lateral);
    let mut t = 0.0;
    while t < t_max {
        // Tension of each element (between node e below and e + 1 above).
        tension.resize(el.len(), 0.0);
        for (e, a) in el.iter_mut().enumerate() {
            let l = x[e] - x[e + 1];
            let w = dm / (rho * l);
            let rate = (v[e] - v[e + 1]) / l;
            let kappa = Tensor::<N>::from_fn(|i, j| match (i, j) {
                (0, 0) => rate,
                (i, j) if i == j => lateral * rate,
                _ => 0.0,
            });
            let mut s = trouton * model.solvent_viscosity(&kappa) * rate;
            if R::ELASTIC {
                let tau = model.polymer_stress(a);
                s += tau[(0, 0)] - tau[(1, 1)];
                *a = advance(ConformationMethod::Direct, model, a, a, &kappa, dt);
            }
            tension[e] = w * s;
        }
        // Nodes below the exit are free: gravity and the pull of the elements either side.
        for k in 0..x.len() {
            if x[k] > 0.0 {
                let above = tension.get(k).copied().unwrap_or(0.0);
                let below = if k > 0 { tension[k - 1] } else { 0.0 };
                let mass = if k == 0 { 0.5 * dm } else { dm };
                v[k] += dt * (g + (below - above) / mass);
            } else {
                v[k] = u0;
            }
            x[k] += dt * v[k];
        }
        t += dt;
        if !x[0].is_finite() || !v[0].is_finite() {
            return None;
        }
        // Feed the exit: a new element once the top one has moved a full length down.
        let top = *x.last().expect("nodes");
        if top > -(held as f64 - 1.0) * dx0 {
            x.push(top - dx0);
            v.push(u0);
            el.push(model.rest_conformation());
        }
        if x[0] >= h {
            let below_exit = |e: usize| x[e + 1] > 0.0;
            let min_width = (0..el.len())
                .filter(|&e| below_exit(e))
                .map(|e| section::<N>(dm / (rho * (x[e] - x[e + 1])), true))
                .fold(d, f64::min);
            // Whole elements below the exit, and the part of the one straddling it.
            let mass = (0..el.len())
                .map(|e| {
                    let (lo, hi) = (x[e], x[e + 1]);
                    dm * ((lo.max(0.0) - hi.max(0.0)) / (lo - hi)).clamp(0.0, 1.0)
                })
                .sum();
            return Some(SheetArrival {
                time: t,
                tip_speed: v[0],
                min_width,
                mass,
            });
        }
    }
    None
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use viscosph::config::RheologyKind;
    use viscosph::scene::SceneKind;

    fn king_lind(rheology: RheologyKind, wi: f64) -> SceneConfig {
        {
            let mut c = SceneConfig::for_scene(SceneKind::Jet);
            c.fluid.rheology = rheology;
            c.fluid.relaxation_time = wi * 0.006 / 0.2;
            c
        }
    }

    #[test]
    fn an_inviscid_limit_falls_freely() {
        falls_freely(king_lind(RheologyKind::Newtonian, 0.0), |c| {
            arrival(c, 10, 1.0).unwrap()
        });
    }

    /// A nearly inviscid sheet or thread (King & Lind's jet `c` with eta = 1e-6 Pa s) falls
    /// like a point mass: H = U0 t + g t^2 / 2. Returns the arrival.
    pub(crate) fn falls_freely(
        mut c: SceneConfig,
        arrive: impl Fn(&SceneConfig) -> SheetArrival,
    ) -> SheetArrival {
        c.fluid.viscosity = 1e-6;
        let a = arrive(&c);
        let (u0, g, h): (f64, f64, f64) = (0.2, 9.81, 0.072);
        let free = (-u0 + (u0 * u0 + 2.0 * g * h).sqrt()) / g;
        assert!((a.time - free).abs() < 1e-3 * free, "{} vs {free}", a.time);
        assert!((a.tip_speed - (u0 + g * free)).abs() < 1e-2, "{a:?}");
        a
    }

    #[test]
    fn king_and_linds_jet_converges_and_elasticity_speeds_the_fall() {
        let newt = king_lind(RheologyKind::Newtonian, 0.0);
        let coarse = arrival(&newt, 6, 1.0).unwrap();
        let fine = arrival(&newt, 12, 1.0).unwrap();
        println!("Newtonian: {coarse:?} {fine:?}");
        // Held back by 4 eta: about twice the free-fall time 0.1024 s.
        assert!(fine.time > 0.2 && fine.time < 0.25, "{fine:?}");
        assert!((coarse.time - fine.time).abs() < 0.005 * fine.time);
        elasticity_speeds_the_fall(fine, |wi| {
            arrival(&king_lind(RheologyKind::OldroydB, wi), 12, 1.0).unwrap()
        });
    }

    /// The polymer resists only once stretched (over lambda): the higher Wi, the earlier and
    /// the thinner, from the Newtonian fall `newtonian` on (King & Lind IV.D's trend), for the
    /// Oldroyd-B falls `at(Wi)` of the sheet or the thread.
    pub(crate) fn elasticity_speeds_the_fall(
        newtonian: SheetArrival,
        at: impl Fn(f64) -> SheetArrival,
    ) {
        let mut last = newtonian;
        for wi in [1.0 / 3.0, 5.0 / 3.0, 10.0 / 3.0, 20.0 / 3.0] {
            let a = at(wi);
            println!("Oldroyd-B Wi = {wi:.3}: {a:?}");
            assert!(
                a.time < last.time && a.min_width < last.min_width,
                "{a:?} {last:?}"
            );
            last = a;
        }
    }
}
