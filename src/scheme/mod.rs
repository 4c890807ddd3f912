//! SPH schemes. A scheme advances a [`State`] by one time step.
//!
//! [`wcsph`] (Fang 2006) and [`pdri`] (Ren 2015) share their rate evaluation, walls and health
//! check through [`common`]; each keeps its own time integration.

pub mod artificial;
pub mod common;
pub mod pdri;
pub mod ppe;
pub mod wcsph;

use crate::simulation::State;

/// One SPH scheme instantiated for a concrete kernel and rheology.
pub trait Scheme: Send {
    /// Advance `state` by one step of at most `max_dt`; returns the step taken, or the cause of
    /// a numerical breakdown.
    fn step(&mut self, state: &mut State, max_dt: f64) -> Result<f64, String>;
    /// Positions of the virtual (wall) particles currently built, for output.
    fn wall_positions(&self) -> Vec<crate::Vec2>;
}
