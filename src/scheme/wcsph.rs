//! Weakly compressible SPH of Fang, Owens, Tacher & Parriaux 2006 (section 3).
//!
//! The rates (Fang eqs. 23, 26, 27 with the artificial viscosity 30-37 and an artificial stress)
//! come from the shared [`WcCore`] with Fang's walls (boundary and image
//! particles, eqs. 46-48). This file holds what is Fang's own: the predictor-corrector
//! (eqs. 49-50), the explicit midpoint rule, second order, and the time-step limits (51)-(53)
//! times `time_step_factor`, with the fastest particle's speed added to the sound speed.
//!
//! **Impenetrable plate, a departure from Fang.** Fang's walls keep fluid out through pressure
//! alone: boundary and image particles take the fluid's stress by interpolation and linear
//! extrapolation (eqs. 46-48), and "pressures on both real and virtual particles increase when
//! real particles move towards the wall". Where the fluid near the plate is in tension that
//! mechanism pulls instead of pushing: in Fang's Oldroyd-B drop at 80 particles per diameter
//! (5024 particles; Fang ran 7845) a particle 13 mm from the impact point, at 986 kg/m^3
//! (-2 kPa), crept from one spacing above the plate to half a spacing below it between t = 34 and
//! 45 ms (t* = 1.7-2.2), with the full and with half the time step. At 20-40 particles per
//! diameter the closest particle stays 0.65 spacings above the plate. Capping the images'
//! tension instead (the plate pushes, never pulls) stopped the penetration but changed the
//! physics: the 32 per diameter drop then spread to W* = 2.84 instead of 2.19 and did not
//! retract, so the images' tension is part of what arrests the spreading and is kept. What is
//! added is the kinematic condition itself: after each step a particle below the plate line is
//! mirrored above it and loses the velocity component into the plate, and that momentum is
//! counted in the wall force, so the momentum balance stays exact. It never acts where Fang's
//! walls hold (the test resolutions, every drop up to 40 per diameter: bitwise the same
//! results); the 80 per diameter Oldroyd-B drop needs it (`State::wall_reflections`, reported
//! by `viscosph run` and `viscosph bench drop`: 5008 times in 30341 steps). What it does not
//! cure: a particle put back is still pulled by images extrapolated from its own tension, and
//! when the drop recedes (t* = 3-6) a few such particles stay behind on the plate line just
//! beyond the fluid, so that run's `drop_width` sits at W* = 2.005-2.010 from t* = 3.5 to 6.5.
//! (Resetting their density to rho0 as well changed nothing.)

use super::health::check_health;
use super::params::Params;
use super::wc::{ghost_walls, WcCore, WcSpace};
use super::{Scheme, Timings};
use crate::boundary::ghost::{keep_out_of_walls, WallModel};
use crate::boundary::wall::Wall;
use crate::boundary::Boundary;
use crate::dim::{Const, Dim, Vector};
use crate::kernel::Kernel;
use crate::particles::Fluid;
use crate::rheology::Rheology;
use crate::state::State;

/// The WCSPH scheme for kernel `K` and rheology `R` in N space dimensions (`Wcsph<K, R>`: two).
pub struct Wcsph<K: Kernel<N>, R: Rheology, const N: usize = 2> {
    core: WcCore<K, R, N>,
    half: Fluid<N>,
    next: Fluid<N>,
}

impl<K: Kernel, R: Rheology> Wcsph<K, R> {
    /// The scheme for the walls `plates` of the initial state, each with Fang's boundary and
    /// image particles.
    pub fn new(kernel: K, model: R, p: Params, plates: &[Wall]) -> Self {
        let walls = ghost_walls(kernel, WallModel::Fang, &p, plates);
        Self::with_walls(kernel, model, p, walls)
    }
}

impl<K: Kernel<N>, R: Rheology, const N: usize> Wcsph<K, R, N>
where
    Const<N>: Dim + WcSpace<N>,
{
    /// The scheme with the wall models `walls`, one per wall of the state, in its order (any
    /// dimension: the caller chooses the models).
    pub fn with_walls(
        kernel: K,
        model: R,
        p: crate::scheme::params::Params<N>,
        walls: Vec<Box<dyn Boundary<N>>>,
    ) -> Self {
        Self {
            core: WcCore::new(kernel, model, p, walls),
            half: Fluid::default(),
            next: Fluid::default(),
        }
    }
}

impl<K: Kernel<N>, R: Rheology, const N: usize> Scheme<N> for Wcsph<K, R, N>
where
    Const<N>: Dim + WcSpace<N>,
{
    fn step(&mut self, st: &mut State<N>, max_dt: f64) -> Result<f64, String> {
        let c = &mut self.core;
        let start = c.prof.start();
        c.refresh_neighbors(&st.fluid.x, &mut st.walls);
        let r0 = c.rates(&st.fluid, &st.walls);
        let t = c.prof.start();
        let dt_stable = c.stable_dt(&st.fluid, &r0, c.p.dt_factor, true);
        let dt = dt_stable.min(max_dt);
        if dt.is_nan() || dt <= 0.0 {
            return Err(format!("time step collapsed to {dt:e} s"));
        }
        // Predictor, eq. (49): X^{n+1/2} = X^n + F^n dt/2.
        let t = c.prof.lap(t, "time step", false);
        let fl = &st.fluid;
        c.update(&mut self.half, fl, &fl.v, &fl.conf, 0.5 * dt);
        c.prof.lap(t, "update", false);
        c.refresh_neighbors(&self.half.x, &mut st.walls);
        let r1 = c.rates(&self.half, &st.walls);
        // Corrector, eq. (50): X^{n+1} = X^n + F^{n+1/2} dt.
        let t = c.prof.start();
        c.update(&mut self.next, &st.fluid, &self.half.v, &self.half.conf, dt);
        std::mem::swap(&mut st.fluid, &mut self.next);
        let t = c.prof.lap(t, "update", false);
        let mut contact = Vector::zeros();
        // Each wall's share summed over the particles in index order (a sum's rounding depends
        // on its order): one thread, with more than one wall only.
        let mut per_wall = c.wall_on_fluid_per_wall(r1.wall_on_fluid, st.fluid.mass);
        let t = c.prof.lap(t, "wall forces per wall", true);
        // The plate's load by particle: minus the corrector's force of its virtual particles
        // on each, and the momentum its contact gives a particle over the step.
        let plate = st.plate;
        let mut load = std::mem::take(&mut st.plate_load);
        match plate {
            Some(k) => c.wall_load_into(k, st.fluid.mass, &mut load),
            None => load.clear(),
        }
        let (momenta, on_plate, reflections) = keep_out_of_walls(&mut st.fluid, &st.walls, plate);
        for (i, m) in on_plate {
            load[i] -= m / dt;
        }
        for (on_fluid, m) in per_wall.iter_mut().zip(&momenta) {
            contact += m;
            // The force of the fluid on this wall alone.
            *on_fluid = -*on_fluid - m / dt;
        }
        st.wall_reflections += reflections;
        st.book_wall_forces(per_wall, dt);
        st.plate_load = load;
        // Force of the fluid on the plate is minus the force of the wall particles on the fluid
        // (and minus the contact momentum over the step); integrating it with the corrector's
        // own rates makes the momentum balance exact.
        st.wall_force = -r1.wall_on_fluid - contact / dt;
        st.wall_impulse += -r1.wall_on_fluid * dt - contact;
        st.last_dt = dt_stable;
        let t = c.prof.lap(t, "wall forces and contact", false);
        st.void_fraction = check_health::<R, _>(&c.p, st)?;
        c.prof.lap(t, "health check", false);
        c.prof.step(start);
        Ok(dt)
    }

    fn set_profiling(&mut self, on: bool) {
        self.core.prof.enable(on);
    }

    fn timings(&self) -> Timings {
        self.core.prof.timings()
    }

    fn wall_positions(&self, st: &State<N>) -> Vec<Vector<N>> {
        self.core.wall_positions(&st.walls)
    }
}
