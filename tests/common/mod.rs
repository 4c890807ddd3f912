//! Helpers shared by the integration tests: parameter values and a recorded run.
#![allow(dead_code)]

use viscosph::config::{SceneConfig, Value};
use viscosph::diagnostics::Outputs;
use viscosph::simulation::{SimError, Simulation};

pub fn r(x: f64) -> Value {
    Value::Real(x)
}
pub fn i(x: i64) -> Value {
    Value::Integer(x)
}
pub fn s(x: &str) -> Value {
    Value::Text(x.into())
}

/// Outputs every `dt` up to `t_end`, or the breakdown, and the simulation where it stopped.
pub fn series(
    c: &SceneConfig,
    t_end: f64,
    dt: f64,
) -> (Vec<(f64, Outputs)>, Option<SimError>, Simulation) {
    let mut sim = Simulation::new(c.clone()).unwrap();
    let (out, err) = sim.record(t_end, dt);
    (out, err, sim)
}
