//! FMI 2.0 Co-Simulation layer (see issue 3).
