//! The state of a simulation: everything that evolves. Serialisable and free of pointers, so a
//! saved state restores in another process (FMI get/set/serialize FMU state).

use crate::boundary::plate::Plate;
use crate::particles::Fluid;
use crate::{Mat2, Vec2};
use serde::{Deserialize, Serialize};

/// The continuous inputs a co-simulation master may change between communication points. They
/// are held constant over a communication step (FMI 2.0 co-simulation without input derivatives).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Inputs {
    /// Velocity of the plate along its normal, positive away from the fluid [m/s].
    pub plate_velocity: f64,
    /// Jet scene: speed of the fluid leaving the nozzle, vertically down [m/s].
    pub jet_velocity: f64,
}

/// Bookkeeping of an inlet through which particles enter during a run (the jet's nozzle): what
/// has entered so far, in a form that makes the mass exact to the lattice. Particles themselves
/// carry no inlet flag: whether one is still in the inlet is a matter of its position (the scene
/// knows the inlet's region), so nothing breaks when the particles are reordered.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Inflow {
    /// Inflow velocity in force since the last update [m/s] (the `jet_velocity` input).
    pub velocity: f64,
    /// Length of fluid that has entered since the last row was emitted, in [0, dx) [m].
    pub phase: f64,
    /// Time of the last update [s].
    pub updated: f64,
    /// Rows emitted since t = 0.
    pub rows: u64,
    /// Particles emitted since t = 0.
    pub particles: u64,
    /// Momentum the inlet has given the fluid since t = 0 [kg m/s per m depth]: the emitted
    /// particles' and every reset of the inlet particles' velocity to the prescribed one.
    pub momentum: Vec2,
    /// Conformation tensor of the fluid entering (the model's at rest; unused without one).
    pub conformation: Mat2,
    /// The inlet's region: above the height `exit` [m] and within `half_width` [m] of the
    /// vertical x = 0 (see [`Inflow::holds`]).
    pub exit: f64,
    pub half_width: f64,
}

impl Inflow {
    /// Whether a particle at `x` is held in the inlet (its velocity, density and conformation
    /// are prescribed there). A scheme that treats the inlet's pressure its own way (ISPH: a
    /// Neumann condition, as King & Lind's moving ghost particles impose) tells these particles
    /// apart by this test; the weakly compressible schemes need nothing (the inlet's density
    /// rho0 is zero pressure).
    #[inline]
    pub fn holds(&self, x: &Vec2) -> bool {
        x.y > self.exit && x.x.abs() < self.half_width
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State {
    pub time: f64,
    pub step: u64,
    pub fluid: Fluid,
    /// The rigid walls: the drop's plate (none for the elliptical drop).
    pub walls: Vec<Plate>,
    /// The inputs in force.
    pub inputs: Inputs,
    /// Force of the fluid on the walls at the last step's corrector stage [N/m], global frame.
    pub wall_force: Vec2,
    /// Time integral of that force since t = 0 [N s/m], global frame.
    pub wall_impulse: Vec2,
    /// Stable time step at the last step [s] (the step actually taken may be shorter, to land
    /// on a communication point).
    pub last_dt: f64,
    /// Void fraction after the last step (see [`crate::health`]).
    pub void_fraction: f64,
    /// How many times a fluid particle was put back above the plate by the impenetrability
    /// condition of Fang's walls (see [`crate::scheme::wcsph`]).
    pub wall_reflections: u64,
    /// The inlet's bookkeeping, for scenes with inflow (the jet); None otherwise.
    pub inflow: Option<Inflow>,
    /// Incompressible scheme (isph): the pressure of every fluid particle at the last step, the
    /// warm start of the next pressure solve (so a restored state continues bitwise); empty for
    /// the weakly compressible schemes, whose pressure follows from the density.
    #[serde(default)]
    pub pressure: Vec<f64>,
    /// Incompressible scheme: momentum the ALE remapping term u_ps . grad u of King & Lind 2021
    /// eq. (24) has added since t = 0 [N s/m] (shifting moves particles, not momentum between
    /// them, so this is the one part of the momentum change that is neither gravity nor wall).
    #[serde(default)]
    pub remap_impulse: Vec2,
    /// Incompressible scheme: linear-solver iterations since t = 0 (pressure, viscous).
    #[serde(default)]
    pub solver_iterations: [u64; 2],
}

impl State {
    /// The initial state of a fluid and its walls.
    pub fn new(fluid: Fluid, walls: Vec<Plate>) -> Self {
        Self {
            time: 0.0,
            step: 0,
            fluid,
            walls,
            inputs: Inputs::default(),
            wall_force: Vec2::zeros(),
            wall_impulse: Vec2::zeros(),
            last_dt: 0.0,
            void_fraction: 0.0,
            wall_reflections: 0,
            inflow: None,
            pressure: Vec::new(),
            remap_impulse: Vec2::zeros(),
            solver_iterations: [0, 0],
        }
    }

    /// Put `inputs` in force: the plate (the first wall) takes the input velocity.
    pub fn apply_inputs(&mut self, inputs: Inputs) {
        self.inputs = inputs;
        if let Some(plate) = self.walls.first_mut() {
            plate.velocity = inputs.plate_velocity;
        }
    }

    /// The plate (the first wall), if there is one.
    pub fn plate(&self) -> Option<&Plate> {
        self.walls.first()
    }
}
