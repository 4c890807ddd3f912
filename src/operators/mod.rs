//! The SPH operators the schemes are made of, each with its paper's equation: the pair geometry
//! cached once per evaluation ([`pairs`]), kinematics (velocity gradient and continuity,
//! [`kinematics`]), stress assembly with EVSS and Morris' viscous Laplacian ([`stress`]), the
//! artificial terms against shocks and the tensile instability ([`artificial`]), and King & Lind
//! 2021's corrected gradients ([`correction`]), free-surface detection and normals ([`surface`])
//! and Fickian particle shifting ([`shifting`]).
//!
//! They work per particle or per pair and are inlined into the schemes' gather loops, so a pass
//! over the neighbours computes several of them at once without a second sweep through memory.

pub mod artificial;
pub mod correction;
pub mod kinematics;
pub mod pairs;
pub mod shifting;
pub mod stress;
pub mod sums;
pub mod surface;

/// The particle sets of the unit tests, from the reference crate (which the examples use): its
/// source compiled into the test build here, so that the sets' neighbour lists are this crate's
/// types (a dev-dependency on the reference crate would link a second copy of the library).
#[cfg(test)]
#[path = "../../reference/src/fixtures.rs"]
pub(crate) mod fixtures;
