//! Rigid walls.

pub mod plate;
