//! The plate the drop and the jet fall onto: its inclination and the input that moves it.

use super::{real, Kind};

crate::params! {
    /// The plate (the first wall of the scenes that have one). Only a scene with a free-standing
    /// plate lets `plate_velocity` move it (`Scene::has_moving_plate`).
    pub struct PlateParams {
        plate_inclination: f64 = Kind::Real { default: 0.0, min: 0.0, max: 90.0, min_open: false, max_open: true }, vr 4, unit "deg";
            "Angle of the plate to the horizontal; the plate runs downhill towards +x",
        plate_velocity: f64 = real(0.0, -1000.0, 1000.0), vr 60, unit "m/s", input;
            "Input: velocity of the plate along its normal, positive away from the fluid; the plate moves rigidly and the walls follow. A co-simulation master may change it at every communication point; this is its start value",
    }
}
