//! The plate the drop and the jet fall onto: its inclination, the inputs that move it and the
//! range of motion a run is set up for.

use super::{enumeration, real, Kind};

pub const PLATE_COUPLINGS: &[(&str, &str)] = &[
    (
        "velocity",
        "the plate moves at plate_velocity, held over each communication step (plate_position is not read)",
    ),
    (
        "position",
        "over each communication step from t to t + h the plate moves at the constant velocity that brings it to plate_position + plate_velocity h at t + h: the master's position and velocity at t, extrapolated, so a Jacobi master does not drift (set plate_velocity = 0 to reach plate_position itself)",
    ),
];

crate::choice_enum!(
    /// How the plate inputs move the plate.
    PlateCoupling, PLATE_COUPLINGS, Velocity = "velocity", Position = "position");

crate::params! {
    /// The plate (the first wall of the scenes that have one). Only a scene with a free-standing
    /// plate lets `plate_velocity` and `plate_position` move it (`Scene::has_moving_plate`).
    pub struct PlateParams {
        plate_inclination: f64 = Kind::Real { default: 0.0, min: 0.0, max: 90.0, min_open: false, max_open: true }, vr 4, unit "deg";
            "Angle of the plate to the horizontal; the plate runs downhill towards +x",
        plate_velocity: f64 = real(0.0, -1000.0, 1000.0), vr 60, unit "m/s", input;
            "Input: velocity of the plate along its normal, positive away from the fluid; the plate moves rigidly and the walls follow. A co-simulation master may change it at every communication point; this is its start value. Its magnitude may not exceed max_plate_speed",
        max_plate_speed: f64 = real(1.0, 0.0, 1000.0), vr 64, unit "m/s";
            "Largest plate speed (either way along the normal) the plate inputs may drive in this run; the automatic sound speed covers the plate moving into the fluid at it. An input asking for more is refused by name (the FMU: fmi2Discard). The default covers a plate driven into the default drop at its impact speed; 0 = a fixed plate",
        plate_coupling: PlateCoupling = enumeration::<PlateCoupling>("PlateCoupling", "velocity"), vr 65, unit "";
            "How the inputs move the plate: velocity = at plate_velocity; position = to plate_position + plate_velocity h at the end of each communication step of length h (no drift under a Jacobi master)",
        plate_position: f64 = real(0.0, -1000.0, 1000.0), vr 66, unit "m", input;
            "Input, read when plate_coupling = position: where the plate is to be along its normal (its displacement away from the fluid since t = 0, as the output plate_displacement) at the communication point, extrapolated over the step with plate_velocity",
        depth: f64 = real(0.0, 0.0, 1000.0), vr 71, unit "m";
            "2D only: the length across the plane of the flow that the *_total outputs count (a 2D force per unit depth times depth); 0 = the scene's reference length (the drop: its diameter, a cylinder of fluid as long as it is wide). Not read in 3D, where forces are totals already",
    }
}
