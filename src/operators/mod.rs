//! SPH operators shared by the schemes: King & Lind 2021's corrected gradients, free-surface
//! detection and normals, and Fickian particle shifting.

pub mod correction;
pub mod fixtures;
pub mod shifting;
pub mod surface;
