//! Rigid walls.

pub mod mirror;
pub mod plate;
