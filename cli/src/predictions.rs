//! The models outside the solver that a scene's summary may quote in `viscosph run`
//! (`viscosph::scene::Predictions`): the CLI links the reference solutions, the FMU does not.

use viscosph::scene::{Prediction, Predictions};
use viscosph::SceneConfig;
use viscosph_reference::analytic::falling_sheet;

/// The reference models the CLI has, by the quantity they predict.
pub struct ReferenceModels;

impl Predictions for ReferenceModels {
    fn predict(&self, cfg: &SceneConfig, quantity: &str) -> Option<Prediction> {
        match quantity {
            // When a falling jet reaches the plate: the slender-sheet model.
            "arrival_time" => falling_sheet::arrival(cfg, falling_sheet::ELEMENTS_PER_WIDTH, 10.0)
                .map(|a| Prediction {
                    model: "slender-sheet model",
                    value: a.time,
                }),
            _ => None,
        }
    }
}
