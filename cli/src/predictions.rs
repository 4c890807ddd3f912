//! The models outside the solver that a scene's summary may quote in `viscosph run`
//! (`viscosph::scene::Predictions`): the CLI links the reference solutions, the FMU does not.

use viscosph::scene::{Prediction, Predictions};
use viscosph::SceneConfig;
use viscosph_reference::analytic::{falling_sheet, falling_thread};

/// The reference models the CLI has, by the quantity they predict.
pub struct ReferenceModels;

impl Predictions for ReferenceModels {
    fn predict(&self, cfg: &SceneConfig, quantity: &str) -> Option<Prediction> {
        match quantity {
            // When a falling jet reaches the plate: the slender-thread model for the round
            // jet, the slender-sheet model for the planar one.
            "arrival_time" if cfg.numerics.dimension == 3 => {
                falling_thread::arrival(cfg, falling_thread::ELEMENTS_PER_DIAMETER, 10.0).map(|a| {
                    Prediction {
                        model: "slender-thread model",
                        value: a.time,
                    }
                })
            }
            "arrival_time" => falling_sheet::arrival(cfg, falling_sheet::ELEMENTS_PER_WIDTH, 10.0)
                .map(|a| Prediction {
                    model: "slender-sheet model",
                    value: a.time,
                }),
            _ => None,
        }
    }
}
