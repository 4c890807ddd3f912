//! The state of a simulation: everything that evolves. Serialisable and free of pointers, so a
//! saved state restores in another process (FMI get/set/serialize FMU state).

use crate::boundary::plate::Plate;
use crate::boundary::wall::Wall;
use crate::dim::Vector;
use crate::particles::Fluid;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// An inlet through which particles enter during a run (the jet's nozzle): the region where
/// particles are held at a prescribed state, and the momentum that holding and the entering
/// particles have given the fluid. Particles carry no inlet flag: whether one is in the inlet is a
/// matter of its position ([`Inflow::holds`]), so nothing breaks when they are reordered. What
/// has entered so far (rows, phase) is the scene's own bookkeeping ([`State::scene`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Inflow<const N: usize = 2> {
    /// Momentum the inlet has given the fluid since t = 0 [kg m/s per m depth]: the emitted
    /// particles' and every reset of the inlet particles' velocity to the prescribed one (by
    /// the scene before the step, and by a scheme that holds them through it).
    pub momentum: Vector<N>,
    /// The inlet's region: above the height `exit` \[m\] and within `half_width` \[m\] of the
    /// vertical x = 0 (see [`Inflow::holds`]).
    pub exit: f64,
    pub half_width: f64,
}

impl<const N: usize> Default for Inflow<N> {
    fn default() -> Self {
        Self {
            momentum: Vector::zeros(),
            exit: 0.0,
            half_width: 0.0,
        }
    }
}

impl<const N: usize> Inflow<N> {
    /// Whether a particle at `x` is held in the inlet (its velocity, density and conformation
    /// are prescribed there). A scheme that treats the inlet's pressure its own way (ISPH: a
    /// Neumann condition, as King & Lind's moving ghost particles impose) tells these particles
    /// apart by this test; the weakly compressible schemes need nothing (the inlet's density
    /// rho0 is zero pressure). The vertical is the last axis; in 3D the inlet is the round
    /// region within `half_width` of the vertical axis.
    #[inline]
    pub fn holds(&self, x: &Vector<N>) -> bool {
        let across = if N == 2 {
            x[0].abs()
        } else {
            x.rows(0, N - 1).norm()
        };
        x[N - 1] > self.exit && across < self.half_width
    }
}

/// The scene's own evolving data (the jet's inflow bookkeeping), encoded by the scene: the
/// state carries it (saved with it, restored, rewound) without knowing its type, so a scene
/// with data of its own needs no field here.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct SceneState(Vec<u8>);

impl SceneState {
    /// The encoding of `value`.
    pub fn encode<T: Serialize>(value: &T) -> Self {
        Self(bincode::serialize(value).expect("scene data serialises"))
    }

    /// The value encoded by [`SceneState::encode`]; None if there is none (or of another type).
    pub fn decode<T: DeserializeOwned>(&self) -> Option<T> {
        bincode::deserialize(&self.0).ok()
    }
}

/// Everything that evolves, in N space dimensions (`State` alone: two). Forces and impulses
/// are per unit depth in 2D \[N/m\], \[N s/m\], plain in 3D \[N\], \[N s\].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State<const N: usize = 2> {
    pub time: f64,
    pub step: u64,
    pub fluid: Fluid<N>,
    /// The rigid walls (none for the elliptical drop), each with its own motion
    /// ([`crate::boundary::plate::Motion`]).
    pub walls: Vec<Wall<N>>,
    /// Which of `walls` is "the plate" the shared outputs refer to (its frame, displacement
    /// and force; see [`crate::scene::Scene::plate_wall`]), if any.
    #[serde(default)]
    pub plate: Option<usize>,
    /// Force of the fluid on the walls at the last step's corrector stage [N/m], global frame.
    pub wall_force: Vector<N>,
    /// Time integral of that force since t = 0 [N s/m], global frame.
    pub wall_impulse: Vector<N>,
    /// The force of the fluid on each wall alone (in the order of `walls`) at the last step,
    /// measured as `wall_force` is \[N/m\]: the cylinder's drag and lift apart from the channel
    /// walls' shear. Empty when the scheme does not split it (the incompressible scheme with
    /// more than one wall: its implicit steps move momentum between fluid and all walls at
    /// once).
    #[serde(default)]
    pub wall_forces: Vec<Vector<N>>,
    /// The plate's part of `wall_force` by fluid particle (in the order of `fluid`, whose
    /// positions are those after the step) \[N/m\], global frame: the load along the plate
    /// (`scene::drop`'s pressure and shear bins). Empty when there is no plate, or under the
    /// incompressible scheme with more than one wall (`scheme::isph`'s `plate_load`: with one
    /// wall it books the plate's pair forces, its share of the implicit viscous solve and the
    /// contact particle by particle).
    #[serde(default)]
    pub plate_load: Vec<Vector<N>>,
    /// Time integral of each wall's force since t = 0 \[N s/m\] (as `wall_forces`).
    #[serde(default)]
    pub wall_impulses: Vec<Vector<N>>,
    /// Stable time step at the last step \[s\] (the step actually taken may be shorter, to land
    /// on a communication point).
    pub last_dt: f64,
    /// Void fraction after the last step (see [`crate::health`]).
    pub void_fraction: f64,
    /// How many times a fluid particle was put back above the plate by the impenetrability
    /// condition of Fang's walls (see [`crate::scheme::wcsph`]).
    pub wall_reflections: u64,
    /// The inlet, for scenes with inflow (the jet); None otherwise.
    pub inflow: Option<Inflow<N>>,
    /// The scene's own data (see [`SceneState`]).
    pub scene: SceneState,
    /// Incompressible scheme (isph): the pressure of every fluid particle at the last step, the
    /// warm start of the next pressure solve (so a restored state continues bitwise); empty for
    /// the weakly compressible schemes, whose pressure follows from the density.
    #[serde(default)]
    pub pressure: Vec<f64>,
    /// Incompressible scheme: momentum the ALE remapping term u_ps . grad u of King & Lind 2021
    /// eq. (24) has added since t = 0 [N s/m] (shifting moves particles, not momentum between
    /// them, so this is the one part of the momentum change that is neither gravity nor wall).
    #[serde(default = "Vector::zeros")]
    pub remap_impulse: Vector<N>,
    /// Incompressible scheme: linear-solver iterations since t = 0 (pressure, viscous).
    #[serde(default)]
    pub solver_iterations: [u64; 2],
}

impl<const N: usize> State<N> {
    /// The initial state of a fluid and its walls, `plate` naming the plate among them.
    pub fn new(fluid: Fluid<N>, walls: Vec<Wall<N>>, plate: Option<usize>) -> Self {
        debug_assert!(plate.is_none_or(|k| k < walls.len()));
        Self {
            time: 0.0,
            step: 0,
            fluid,
            walls,
            plate,
            wall_force: Vector::zeros(),
            wall_impulse: Vector::zeros(),
            wall_forces: Vec::new(),
            plate_load: Vec::new(),
            wall_impulses: Vec::new(),
            last_dt: 0.0,
            void_fraction: 0.0,
            wall_reflections: 0,
            inflow: None,
            scene: SceneState::default(),
            pressure: Vec::new(),
            remap_impulse: Vector::zeros(),
            solver_iterations: [0, 0],
        }
    }

    /// The wall the scene named its plate, if any (a straight wall).
    pub fn plate(&self) -> Option<&Plate<N>> {
        self.plate
            .and_then(|k| self.walls.get(k))
            .and_then(Wall::plate)
    }

    /// Book each wall's force at the last step, `forces` [N/m] over the step `dt` (one per
    /// wall; empty: not split).
    pub fn book_wall_forces(&mut self, forces: Vec<Vector<N>>, dt: f64) {
        if self.wall_impulses.len() != forces.len() {
            self.wall_impulses = vec![Vector::zeros(); forces.len()];
        }
        for (i, f) in self.wall_impulses.iter_mut().zip(&forces) {
            *i += f * dt;
        }
        self.wall_forces = forces;
    }

    /// The plate, mutably.
    pub fn plate_mut(&mut self) -> Option<&mut Plate<N>> {
        self.plate
            .and_then(|k| self.walls.get_mut(k))
            .and_then(Wall::plate_mut)
    }
}
