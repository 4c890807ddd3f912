//! Rigid walls: the plate geometry ([`plate`]) and the wall models that give the fluid something
//! to push against ([`ghost`]: Fang 2006's boundary + image particles and Ren 2015's wall + ghost
//! particles).
//!
//! A wall model is a [`Boundary`]: for the current fluid it places virtual particles near the
//! wall (appended after the fluid in the scheme's work arrays), then fills their velocities and
//! stresses from the fluid before each pass that reads them. The force the virtual particles
//! exert on the fluid is the wall's reaction; the scheme sums it in its momentum pass. The wall's
//! geometry and motion (a [`plate::Plate`]) live in the simulation state; a boundary holds only
//! what it rebuilds from the state (interpolation lists), so nothing is stored twice.

pub mod ghost;
pub mod mirror;
pub mod plate;
pub mod wall_profile;

use crate::neighbors::CellGrid;
use crate::particles::Fluid;
use crate::{Mat2, Vec2};
use plate::Plate;

/// A wall model acting on the fluid through virtual particles.
pub trait Boundary: Send + Sync {
    /// Grow `wall` to cover the fluid at `fluid_x`, append the positions of this wall's virtual
    /// particles to `out`, and rebuild whatever the fill steps need (`fluid_grid` bins `fluid_x`
    /// with cells of side `radius`, the search radius).
    fn place(
        &mut self,
        wall: &mut Plate,
        fluid_x: &[Vec2],
        fluid_grid: &CellGrid,
        radius: f64,
        out: &mut Vec<Vec2>,
    );

    /// Velocities of this wall's virtual particles (in the order of [`Boundary::place`]).
    fn fill_velocities(&self, wall: &Plate, fluid: &Fluid, out: &mut [Vec2]);

    /// Stresses of this wall's virtual particles from the fluid's total stresses `sigma` and
    /// elastic stresses `tau_p` (empty for inelastic models).
    fn fill_stresses(
        &self,
        wall: &Plate,
        fluid: &Fluid,
        sigma: &[Mat2],
        tau_p: &[Mat2],
        out: &mut [Mat2],
    );

    /// Positions of the virtual particles placed at the last [`Boundary::place`], for output.
    fn positions(&self, wall: &Plate) -> Vec<Vec2>;
}
