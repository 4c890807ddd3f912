//! References for the viscosph solver, kept out of the solver library (and so out of the FMU):
//!
//! * [`analytic`]: exact and semi-analytic solutions the scenes are checked against: the plane
//!   channel's transient start-up (Waters & King 1970) and steady profiles of every model of
//!   King & Lind 2021 Table I, and the slender falling-sheet model of the jet's arrival.
//! * [`fixtures`]: particle sets (a jittered lattice disc, a mirrored periodic channel) for the
//!   solver's unit tests and the linear-solver examples.
//!
//! Everything here uses the library's public API only ([`viscosph::rheology::advance`],
//! [`viscosph::SceneConfig::for_scene`], the neighbour search), so it checks the code the FMU runs.

pub mod analytic;
pub mod fixtures;
