//! ViscoSPH: transient viscoelastic and shear-thinning free-surface flows by Smoothed Particle
//! Hydrodynamics, in 2D.
//!
//! Three seed schemes (Fang 2006 WCSPH, Ren 2015 PDRI-SPH, King & Lind 2021 ISPH), the
//! constitutive models of King & Lind's Table I plus the Cross model, a drop impacting a possibly
//! inclined plate, and FMI 2.0 and FMI 3.0 Co-Simulation layers over the same
//! [`simulation::Simulation`].
//! Papers are cited by authors, year and equation number (e.g. "Fang 2006 eq. (38)"); the full
//! citations are in `docs/references.md`.

pub mod boundary;
pub mod budget;
pub mod choice;
pub mod config;
pub mod diagnostics;
pub mod dim;
pub mod eos;
pub mod fmi2;
pub mod fmi3;
pub mod geometry;
pub mod health;
pub mod kernel;
pub mod neighbors;
pub mod operators;
pub mod particles;
pub mod profile;
pub mod rheology;
pub mod scene;
pub mod scheme;
pub mod simulation;
pub mod state;

// The unit tests compile the reference crate's fixtures (`operators::fixtures`), written against
// `viscosph::` paths; this names the crate itself so those paths resolve here too.
#[cfg(test)]
extern crate self as viscosph;

/// 2D vector: [`dim::Vector`] in two dimensions.
pub type Vec2 = dim::Vector<2>;
/// 2x2 tensor: velocity gradients, stresses and conformation tensors ([`dim::Tensor`] in two
/// dimensions).
pub type Mat2 = dim::Tensor<2>;

pub use scene::{Outputs, SceneConfig, OUTPUTS};
pub use simulation::{SimError, Simulation};
pub use state::State;
