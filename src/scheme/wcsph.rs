//! Weakly compressible SPH of Fang, Owens, Tacher & Parriaux 2006 (section 3).
//!
//! The rates (Fang eqs. 23, 26, 27 with the artificial viscosity 30-37 and an artificial stress)
//! come from the shared [`Core`] with Fang's walls (boundary and image
//! particles, eqs. 46-48). This file holds what is Fang's own: the predictor-corrector
//! (eqs. 49-50), the explicit midpoint rule, second order, and the time-step limits (51)-(53)
//! times `time_step_factor`, with the fastest particle's speed added to the sound speed.

use super::common::{Core, Params, WallModel};
use super::Scheme;
use crate::boundary::plate::Plate;
use crate::kernel::Kernel;
use crate::particles::Fluid;
use crate::rheology::Rheology;
use crate::simulation::State;
use crate::Vec2;

/// The WCSPH scheme for kernel `K` and rheology `R`.
pub struct Wcsph<K: Kernel, R: Rheology> {
    core: Core<K, R>,
    half: Fluid,
    next: Fluid,
}

impl<K: Kernel, R: Rheology> Wcsph<K, R> {
    pub fn new(kernel: K, model: R, p: Params, plate: Option<Plate>) -> Self {
        Self {
            core: Core::new(kernel, model, p, plate, WallModel::Fang),
            half: Fluid::default(),
            next: Fluid::default(),
        }
    }
}

impl<K: Kernel, R: Rheology> Scheme for Wcsph<K, R> {
    fn step(&mut self, st: &mut State, max_dt: f64) -> Result<f64, String> {
        let c = &mut self.core;
        c.refresh_neighbors(&st.fluid.x, &mut st.plate);
        let r0 = c.rates(&st.fluid);
        let dt_stable = c.stable_dt(&st.fluid, &r0, c.p.dt_factor, true);
        let dt = dt_stable.min(max_dt);
        if dt.is_nan() || dt <= 0.0 {
            return Err(format!("time step collapsed to {dt:e} s"));
        }
        // Predictor, eq. (49): X^{n+1/2} = X^n + F^n dt/2.
        let fl = &st.fluid;
        c.update(&mut self.half, fl, &fl.v, &fl.conf, 0.5 * dt);
        c.refresh_neighbors(&self.half.x, &mut st.plate);
        let r1 = c.rates(&self.half);
        // Corrector, eq. (50): X^{n+1} = X^n + F^{n+1/2} dt.
        c.update(&mut self.next, &st.fluid, &self.half.v, &self.half.conf, dt);
        std::mem::swap(&mut st.fluid, &mut self.next);
        // Force of the fluid on the plate is minus the force of the wall particles on the fluid;
        // integrating it with the corrector's own rates makes the momentum balance exact.
        st.wall_force = -r1.wall_on_fluid;
        st.wall_impulse += -r1.wall_on_fluid * dt;
        st.last_dt = dt_stable;
        st.void_fraction = c.check_health(&st.fluid, &st.plate)?;
        Ok(dt)
    }

    fn wall_positions(&self) -> Vec<Vec2> {
        self.core.wall_positions()
    }
}
