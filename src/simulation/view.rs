//! What a run shows besides its outputs, in either dimension: its particles in three
//! coordinates for files and pictures, the fluid's momentum and mass, the wall particles, the
//! pressure roughness and where the scheme's time went.

use super::run::Runs;
use super::Simulation;
use crate::diagnostics::pressure_roughness;
use crate::kernel::CubicSplineKernel;
use crate::scheme::Timings;
use crate::Vec2;

/// The particles of a run in three coordinates, whatever its dimension (a 2D run's at z = 0):
/// what files and pictures need ([`Simulation::particles`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Particles {
    /// The run's dimension (2 or 3).
    pub dimension: usize,
    /// Fluid positions \[m\] and velocities \[m/s\].
    pub x: Vec<[f64; 3]>,
    pub v: Vec<[f64; 3]>,
    /// Fluid densities \[kg/m^N\].
    pub rho: Vec<f64>,
    /// tr A of each fluid particle, for a model with a conformation tensor.
    pub trace: Option<Vec<f64>>,
    /// Positions of the wall particles built now \[m\].
    pub walls: Vec<[f64; 3]>,
    /// Every straight wall: a point of it (its origin), its downhill tangent t and its normal
    /// into the fluid n.
    pub plates: Vec<([f64; 3], [f64; 3], [f64; 3])>,
}

impl Simulation {
    /// Pressure roughness of the fluid now: RMS of p_i minus its SPH-smoothed value, over the
    /// dynamic pressure rho0 U^2 of the scene (see [`pressure_roughness`] and
    /// [`Scene::velocity_scale`](crate::scene::Scene::velocity_scale)).
    pub fn pressure_roughness(&self) -> f64 {
        let u = self.scene.velocity_scale(&self.eff);
        let scale = self.eff.fluid.density * u * u;
        on_run!(&self.run, r => {
            let (p, fluid) = (&r.params, &r.state.fluid);
            let kernel = CubicSplineKernel::new(self.eff.h());
            self.pool
                .install(|| pressure_roughness(fluid, &p.eos, &kernel, &p.domain, scale))
        })
    }

    /// Total momentum of a 2D run's fluid [kg m/s per m depth] (a 3D run's:
    /// [`Simulation::fluid_momentum_3d`]).
    ///
    /// # Panics
    /// In a 3D run.
    pub fn fluid_momentum(&self) -> Vec2 {
        match &self.run {
            Runs::D2(r) => r.fluid_momentum(),
            Runs::D3(_) => panic!("fluid_momentum(): a 3D run: use fluid_momentum_3d()"),
        }
    }

    /// Total momentum of a 3D run's fluid [kg m/s] (None in 2D).
    pub fn fluid_momentum_3d(&self) -> Option<crate::dim::Vector<3>> {
        match &self.run {
            Runs::D2(_) => None,
            Runs::D3(r) => Some(r.fluid_momentum()),
        }
    }

    /// Total fluid mass [kg, per m depth in 2D].
    pub fn fluid_mass(&self) -> f64 {
        on_run!(&self.run, r => r.state.fluid.mass * r.state.fluid.len() as f64)
    }

    /// Where the scheme's time went since the simulation was built or restored (empty for
    /// schemes that time nothing).
    pub fn scheme_timings(&self) -> Timings {
        on_run!(&self.run, r => r.scheme.timings())
    }

    /// Turn the per-pass timers of the steps on or off (see [`crate::profile`]); off by
    /// default, and nothing is timed while off.
    pub fn set_profiling(&mut self, on: bool) {
        on_run!(&mut self.run, r => r.set_profiling(on))
    }

    /// Where the time of the steps went since profiling was turned on: the scheme's passes and
    /// the work around them (the copy of the state kept for interpolation, the scene's hook),
    /// the whole steps as the total. Empty while profiling is off.
    pub fn timings(&self) -> Timings {
        on_run!(&self.run, r => r.timings())
    }

    /// Positions of the wall particles of a 2D run currently built (empty in 3D: see
    /// [`Simulation::particles`]).
    pub fn wall_positions(&self) -> Vec<Vec2> {
        match &self.run {
            Runs::D2(r) => r.scheme.wall_positions(&r.state),
            Runs::D3(_) => Vec::new(),
        }
    }

    /// The particles now in three coordinates (a 2D run's at z = 0), for files and pictures
    /// in either dimension (see [`Particles`]).
    pub fn particles(&self) -> Particles {
        fn xyz<const N: usize>(v: &crate::dim::Vector<N>) -> [f64; 3] {
            let mut p = [0.0; 3];
            p[..N].copy_from_slice(v.as_slice());
            p
        }
        on_run!(&self.run, r => {
            let f = &r.state.fluid;
            Particles {
                dimension: f.x.first().map_or(2, |x| x.len()),
                x: f.x.iter().map(xyz).collect(),
                v: f.v.iter().map(xyz).collect(),
                rho: f.rho.clone(),
                trace: (!f.conf.is_empty()).then(|| f.conf.iter().map(|a| a.trace()).collect()),
                walls: r.scheme.wall_positions(&r.state).iter().map(xyz).collect(),
                plates: r
                    .state
                    .walls
                    .iter()
                    .filter_map(|w| w.plate())
                    .map(|p| (xyz(&p.point(0.0, 0.0)), xyz(&p.t), xyz(&p.n)))
                    .collect(),
            }
        })
    }
}
