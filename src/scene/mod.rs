//! Scenes: the initial state of a flow and what to measure in it.

pub mod drop;
