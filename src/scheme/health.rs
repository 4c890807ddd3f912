//! Health of a state after a step: what makes a run stop with a message instead of returning
//! garbage. Every scheme checks its particles ([`check_particles`]: non-finite values, particles
//! through a wall or out of the domain); the weakly compressible ones also the density against
//! rho0 and fracture by the tensile instability ([`check_health`]). The incompressible scheme has
//! no density to check and reports its void fraction without acting on it.

use super::params::Params;
use super::wc::WcSpace;
use crate::boundary::plate::Plate;
use crate::boundary::wall::Wall;
use crate::config::ArtificialStressKind;
use crate::dim::Const;
use crate::eos::Eos;
use crate::geometry::{Shape, Side};
use crate::particles::Fluid;
use crate::rheology::Rheology;
use crate::state::State;
use crate::Vec2;
use rayon::prelude::*;

/// A particle this far below a plate (in particle spacings) has gone through it.
pub const PENETRATION_DEPTH: f64 = 0.5;
/// Relative density deviation that stops a run.
const MAX_DENSITY_DEVIATION: f64 = 0.3;
/// Smallest number of particles per parallel task of this light pass.
const MIN_TASK_LIGHT: usize = 1024;

/// Health of a weakly compressible state after a step: the void fraction, or the cause of a
/// breakdown.
pub fn check_health<R: Rheology, const N: usize>(
    p: &Params<N>,
    st: &State<N>,
) -> Result<f64, String>
where
    Const<N>: WcSpace<N>,
{
    let fl = &st.fluid;
    check_particles(
        fl,
        &st.walls,
        p.dx,
        p.domain_radius,
        R::ELASTIC,
        Some(&p.eos),
    )?;
    // A dimension without a void fraction (3D so far) reports none and is not checked.
    let Some(voids) = Const::<N>::void_fraction(fl, st.plate, &st.walls, p.dx) else {
        return Ok(0.0);
    };
    if p.fracture_void_fraction > 0.0 && voids > p.fracture_void_fraction {
        let knob = match p.art_kind {
            ArtificialStressKind::Fang => "artificial_stress_epsilon",
            ArtificialStressKind::Ren => "artificial_stress_b",
        };
        return Err(format!(
            "fracture by the tensile instability: holes make up {:.1} % of the fluid's area \
             (limit {:.1} %); raise {knob}",
            100.0 * voids,
            100.0 * p.fracture_void_fraction
        ));
    }
    Ok(voids)
}

/// The checks every scheme makes on its particles after a step, in this order: finite
/// positions, velocities, densities and (when `elastic`) conformation tensors on every particle
/// (the first offender named); then particle by particle the density against `eos`'s rho0 (a
/// weakly compressible scheme; None: not checked), the domain (`|x| <= domain_radius`) and every
/// plate (no particle more than [`PENETRATION_DEPTH`] spacings `dx` below it).
pub fn check_particles<const N: usize>(
    fl: &Fluid<N>,
    walls: &[Wall<N>],
    dx: f64,
    domain_radius: f64,
    elastic: bool,
    eos: Option<&Eos>,
) -> Result<(), String> {
    let bad = (0..fl.len())
        .into_par_iter()
        .with_min_len(MIN_TASK_LIGHT)
        .find_first(|&i| {
            !(fl.x[i].iter().all(|x| x.is_finite())
                && fl.v[i].iter().all(|x| x.is_finite())
                && fl.rho.get(i).is_none_or(|r| r.is_finite())
                && (!elastic
                    || fl
                        .conf
                        .get(i)
                        .is_none_or(|a| a.iter().all(|x| x.is_finite()))))
        });
    if let Some(i) = bad {
        return Err(format!(
            "non-finite value (NaN or Inf) on fluid particle {i}"
        ));
    }
    // Particle by particle in parallel; the first offender by index, as a sequential loop
    // would find it, whatever the thread count.
    let fault = |i: usize| -> Option<String> {
        if let Some(eos) = eos {
            let dev = fl.rho[i] / eos.rho0 - 1.0;
            if dev.abs() > MAX_DENSITY_DEVIATION {
                // The density variation is about (v / c)^2: name the sound speed that keeps it
                // near 1 % for the fastest particle now (10 v), and never less than twice the
                // current one.
                let vmax = fl.v.iter().fold(0.0f64, |m, v| m.max(v.norm()));
                let advice = (10.0 * vmax).max(2.0 * eos.c);
                return Some(format!(
                    "density of particle {i} is {:.1} % off the reference density (limit {:.0} \
                     %): the flow is too fast for the sound speed c = {} m/s (fastest particle \
                     {:.3} m/s); set sound_speed to at least {:.0} m/s",
                    100.0 * dev,
                    100.0 * MAX_DENSITY_DEVIATION,
                    eos.c,
                    vmax,
                    advice.ceil()
                ));
            }
        }
        if fl.x[i].norm() > domain_radius {
            return Some(format!(
                "particle {i} escaped the domain (|x| = {:.3e} m)",
                fl.x[i].norm()
            ));
        }
        for pl in walls {
            if pl.signed_distance(&fl.x[i]) < -PENETRATION_DEPTH * dx {
                return Some(format!("particle {i} went through the plate"));
            }
        }
        None
    };
    if let Some(e) = (0..fl.len())
        .into_par_iter()
        .with_min_len(MIN_TASK_LIGHT)
        .find_map_first(fault)
    {
        return Err(e);
    }
    Ok(())
}

/// Void fraction of the fluid (see [`crate::health`]) on cells of two particle spacings, in the
/// plate's frame when there is a plate. A solid the fluid flows around (a cylinder of `walls`)
/// is not a hole: its disc and the spacing around it count as filled.
pub fn fluid_void_fraction(fl: &Fluid, plate: Option<&Plate>, walls: &[Wall], dx: f64) -> f64 {
    let mut x = std::borrow::Cow::Borrowed(&fl.x);
    for w in walls {
        if let Wall::Circle(c) = w {
            if c.ball.fluid == Side::Outside {
                let (o, r) = (c.ball.centre, c.ball.radius);
                let k = (r / dx).ceil() as i64;
                for j in -k..=k {
                    for i in -k..=k {
                        let p = o + Vec2::new(i as f64, j as f64) * dx;
                        // The solid and the spacing next to it that the wall's virtual
                        // particles own.
                        if w.signed_distance(&p) < dx {
                            x.to_mut().push(p);
                        }
                    }
                }
            }
        }
    }
    let pts: Vec<(f64, f64)> = match plate {
        Some(pl) => x
            .par_iter()
            .with_min_len(MIN_TASK_LIGHT)
            .map(|x| (pl.s(x), pl.d(x)))
            .collect(),
        None => x
            .par_iter()
            .with_min_len(MIN_TASK_LIGHT)
            .map(|x| (x.x, x.y))
            .collect(),
    };
    crate::health::void_fraction(&pts, 2.0 * dx, plate.is_some())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::EquationOfState;
    use crate::{Mat2, Vec2};

    /// A 10 x 10 lattice of spacing `dx` above a level plate, at rest and at rho0.
    fn lattice(dx: f64) -> (Fluid, Vec<Wall>) {
        let mut fl = Fluid {
            mass: 1000.0 * dx * dx,
            ..Default::default()
        };
        for q in 0..100 {
            fl.x.push(Vec2::new(
                (q % 10) as f64 * dx,
                (q / 10) as f64 * dx + 0.5 * dx,
            ));
            fl.v.push(Vec2::zeros());
            fl.rho.push(1000.0);
            fl.conf.push(Mat2::identity());
        }
        (fl, vec![Plate::new(0.0, dx).into()])
    }

    /// The particle checks run in parallel: with offenders scattered over a fluid large enough
    /// to be split between threads, the first by index is named, on one thread and on four.
    #[test]
    fn the_first_offender_is_named_whatever_the_threads() {
        let dx = 0.01;
        let mut fl = Fluid {
            mass: 0.1,
            ..Default::default()
        };
        for q in 0..20_000 {
            fl.x.push(Vec2::new((q % 100) as f64 * dx, (q / 100) as f64 * dx));
            fl.v.push(Vec2::zeros());
            fl.rho.push(1000.0);
        }
        for (i, x) in [(17_001, 9.0), (9_500, 8.0), (15_000, 7.0)] {
            fl.x[i].x = x;
        }
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let e = pool
                .install(|| check_particles(&fl, &[], dx, 5.0, false, None))
                .unwrap_err();
            assert!(e.contains("particle 9500 escaped"), "{threads}: {e}");
        }
    }

    /// Every scheme's checks, in their order: a healthy state passes; a non-finite value names
    /// its particle before anything else; a particle half a spacing below the plate line is
    /// through it, one just above that is not; the domain; the density only when asked for.
    #[test]
    fn particle_checks_name_the_first_cause() {
        let dx = 0.01;
        let eos = Eos {
            kind: EquationOfState::Linear,
            rho0: 1000.0,
            c: 10.0,
        };
        let check = |fl: &Fluid, walls: &[Wall], eos: Option<&Eos>| {
            check_particles(fl, walls, dx, 1.0, true, eos)
        };
        let (fl, walls) = lattice(dx);
        assert_eq!(check(&fl, &walls, Some(&eos)), Ok(()));

        let mut bad = fl.clone();
        bad.x[7].y = -0.6 * dx;
        bad.conf[42][(0, 1)] = f64::NAN;
        let e = check(&bad, &walls, None).unwrap_err();
        assert!(e.contains("non-finite") && e.contains("particle 42"), "{e}");

        let mut through = fl.clone();
        through.x[7].y = -0.49 * dx;
        assert_eq!(check(&through, &walls, None), Ok(()));
        through.x[7].y = -0.51 * dx;
        let e = check(&through, &walls, None).unwrap_err();
        assert!(e.contains("particle 7 went through the plate"), "{e}");

        let mut far = fl.clone();
        far.x[3].x = 2.0;
        let e = check(&far, &walls, None).unwrap_err();
        assert!(e.contains("particle 3 escaped the domain"), "{e}");

        let mut dense = fl.clone();
        dense.rho[5] = 1400.0;
        assert_eq!(check(&dense, &walls, None), Ok(()));
        let e = check(&dense, &walls, Some(&eos)).unwrap_err();
        assert!(e.contains("density of particle 5"), "{e}");
    }
}
