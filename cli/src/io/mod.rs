//! Output files a person can look at: CSV time series, VTK particle snapshots for ParaView, PNG plots.

pub mod csv;
pub mod plot;
pub mod vtk;
