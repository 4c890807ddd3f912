//! How a run of a scene is reported: what its time plot shows ([`TimePlot`]), and the models
//! outside the solver a scene's summary may quote ([`Predictions`]). The CLI draws and prints
//! what the scene describes here; it knows no scene.

use super::{Outputs, SceneConfig};

/// One panel of a [`TimePlot`]: a quantity of the outputs against time.
pub struct TimePlotPanel {
    pub title: String,
    pub y_label: String,
    /// The plotted value of a record of outputs.
    pub value: Box<dyn Fn(&Outputs) -> f64>,
}

/// What a plot of a run's outputs against time shows: t / `time_unit` on the x axis.
pub struct TimePlot {
    pub time_unit: f64,
    pub x_label: String,
    pub panels: Vec<TimePlotPanel>,
}

/// The default [`TimePlot`]: width W* = W / D and height H* = H / D against t* = t / `ts`, for
/// a scene whose reference length is D (Fang 2006's figures).
pub fn extent_plot(cfg: &SceneConfig, d: f64, ts: f64) -> TimePlot {
    TimePlot {
        time_unit: ts,
        x_label: format!("t* = t V / D [-]   (D/V = {})", time_text(ts)),
        panels: vec![
            TimePlotPanel {
                title: format!("width W* = W / D (D = {} mm)", 1e3 * d),
                y_label: "W* [-]".to_string(),
                value: Box::new(move |o| o.shared.drop_width / d),
            },
            TimePlotPanel {
                title: format!("height H* = H / D ({} scheme)", cfg.scheme),
                y_label: "H* [-]".to_string(),
                value: Box::new(move |o| o.shared.drop_height / d),
            },
        ],
    }
}

/// A time with a unit a person reads: ms below a second.
pub fn time_text(t: f64) -> String {
    if t < 1.0 {
        format!("{:.1} ms", 1e3 * t)
    } else {
        format!("{t:.3} s")
    }
}

/// A value predicted by a model outside the solver, with the model's name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prediction {
    /// e.g. "slender-sheet model".
    pub model: &'static str,
    pub value: f64,
}

/// Models outside the solver that a scene's summary may quote (the solver links none: the
/// reference solutions live beside it and the caller passes them in). A scene asks for a
/// quantity by name (the jet: "arrival_time", when the fluid reaches the plate \[s\]); the
/// implementation answers for the quantities and configurations its models cover.
pub trait Predictions {
    fn predict(&self, cfg: &SceneConfig, quantity: &str) -> Option<Prediction>;
}

/// No model at all.
pub struct NoPredictions;

impl Predictions for NoPredictions {
    fn predict(&self, _cfg: &SceneConfig, _quantity: &str) -> Option<Prediction> {
        None
    }
}
