//! The SPH operators the schemes are made of, each with its paper's equation: the pair geometry
//! cached once per evaluation ([`pairs`]), kinematics (velocity gradient and continuity,
//! [`kinematics`]), stress assembly with EVSS and Morris' viscous Laplacian ([`stress`]), and the
//! artificial terms against shocks and the tensile instability ([`artificial`]).
//!
//! They work per particle or per pair and are inlined into the schemes' gather loops, so a pass
//! over the neighbours computes several of them at once without a second sweep through memory.

pub mod artificial;
pub mod kinematics;
pub mod pairs;
pub mod stress;
