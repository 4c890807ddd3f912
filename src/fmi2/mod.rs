//! FMI 2.0 Co-Simulation layer: the solver as `ViscoSPH.fmu` (issue 3).
//!
//! A thin translator over the same [`Simulation`](crate::simulation::Simulation) and the same
//! parameter validation ([`SceneConfig::set`](crate::scene::SceneConfig::set) /
//! [`validate`](crate::scene::SceneConfig::validate)) the CLI uses:
//!
//! - [`model_description`] generates `modelDescription.xml` from the parameter and output
//!   tables, and the GUID that ties the XML to the binary;
//! - [`instance`] is the Co-Simulation state machine (safe Rust, unit-tested in-process; its
//!   variables and FMU states in their own files);
//! - `exports` holds the 44 `extern "C"` functions of `fmi2Functions.h`: pointer checks,
//!   `catch_unwind`, and a call into [`instance::Instance`] (the FMU-state and the unsupported
//!   ones in their own files);
//! - [`types`] are the C types of the FMI 2.0 headers.
//!
//! The FMI 3.0 layer (`crate::fmi3`) is a second thin C API over the same [`instance`]: it
//! creates an instance that words its messages in FMI 3.0 ([`instance::Api`]) and forwards to
//! the entry points here wherever the two standards' functions coincide.
//!
//! No global mutable state: everything lives in the instance, so several instances in one
//! process, on several threads, are independent (FMI 2.0 section 2.1.5,
//! `canBeInstantiatedOnlyOncePerProcess = false`). The working directory is never changed.

pub(crate) mod exports;
pub mod instance;
pub mod model_description;
pub mod types;

pub use model_description::{guid, model_description_xml, MODEL_IDENTIFIER};
