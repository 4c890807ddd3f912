//! FMI 3.0 Co-Simulation layer: the solver as `ViscoSPH-fmi3.fmu`, beside the FMI 2.0 one.
//!
//! No logic of its own: the same [`Instance`](crate::fmi2::instance::Instance) state machine
//! and variable table serve both standards (FMI 3.0's Co-Simulation states Instantiated,
//! Initialization Mode, Step Mode, Step Discarded, Terminated and the error state are FMI 2.0's
//! with other names), and the same variable list
//! ([`model_variables`](crate::fmi2::model_description::model_variables)) writes both model
//! descriptions:
//!
//! - [`model_description`] writes the FMI 3.0 `modelDescription.xml` (its
//!   `instantiationToken` is the FMI 2.0 GUID: one interface, two spellings);
//! - `exports` holds the `extern "C"` functions of `fmi3Functions.h`, exported from the same
//!   cdylib as the `fmi2*` ones;
//! - [`types`] are the C types of the FMI 3.0 headers.

pub(crate) mod exports;
pub mod model_description;
pub mod types;

pub use model_description::{model_description_xml, TIME_VR};
