//! The `viscosph` command line's shared parts: the run loop with its progress bar ([`run`]), the
//! benchmarks ([`mod@bench`]) and the files a person looks at ([`io`]: CSV, VTK, PNG). They live
//! outside the solver library so that the FMU's cdylib links none of clap, plotters or indicatif.

pub mod bench;
pub mod docs_tables;
pub mod exact;
pub mod io;
pub mod predictions;
pub mod run;
