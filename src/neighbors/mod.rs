//! Neighbour search: the domain (open or periodic), a uniform cell grid and compact (CSR)
//! neighbour lists built from it.

pub mod domain;
pub mod grid;

pub use domain::Domain;
pub use grid::{CellGrid, Grid, NeighborList};
