//! Incompressible SPH of King & Lind 2021 (section III): Chorin's projection with a pressure
//! Poisson equation, log-conformation stresses at half steps, EVSS, Fickian shifting, mirror
//! walls and a normal-stress free-surface condition.
//!
//! The scheme is written once over the dimension N (`Isph<R, N>`, `Const<N>: Dim`): 2D runs the
//! closed forms it always had (bit for bit), 3D the same steps with 3x3 tensors, three velocity
//! components per particle in the implicit viscous system, div r = 3 under full support, the
//! surface tangent plane instead of the tangent line, mirrors across a plane of any inclination.
//!
//! [`Isph::step`] reads as the paper's steps 1-7 of section III.A, one file per step:
//! 1. advect `r* = r^n + dt u^n` (23) (Eulerian frame: particles stay): [`advection`];
//! 2. the walls' virtual particles ([`walls`]: any [`Boundary`] whose virtual particles each
//!    follow one fluid particle, King & Lind's mirrors by default), the neighbour lists and, in
//!    one pass over them, the pair cache, the Bonet & Lok correction matrices (22) and the free
//!    surface (36)-(39) ([`neighbours`]); the shifting velocity (40)-(44) ([`advection`], with
//!    the corrections [`crate::operators::shifting`] lists); Eulerian: `u_ps = -u^n`;
//! 3. the conformation tensor from n-1/2 to n+1/2 with the corrected velocity gradient (20) of
//!    u^n through the project's rheology (log-conformation by default) by the midpoint rule,
//!    plus the ALE term `dt u_ps . grad Psi` of (31): [`conformation`];
//! 4. the predictor (24): `u* = u^n + dt [u_ps . grad u^n + nu lap u + div Phi / rho]`
//!    ([`predictor`]), the solvent (and EVSS) viscosity by Morris' Laplacian (21), explicitly as
//!    in the paper or implicitly ([`viscous`], the default);
//! 5. the PPE (25) `lap p = (rho / dt) div u*` ([`pressure`]; the linear systems and their
//!    solver in [`ppe`]), free-surface rows from the conditions of [`free_surface`], mirrors
//!    Neumann with the hydrostatic offset;
//! 6. projection (26) `u^{n+1} = u* - dt grad p / rho + dt g`: [`projection`];
//! 7. advection (27) `r^{n+1} = r^n + dt/2 (u^n + u^{n+1} + 2 u_ps)`: [`advection`].
//!
//! The step itself is (28) with the limits this scheme needs besides ([`step_size`]).
//!
//! Choices where the paper is silent or where we depart from it, each for a stated reason and
//! with the measurement behind it, are documented in the file of the step they concern:
//! gravity in the corrector ([`projection`]); the implicit solvent viscosity, the EVSS floor
//! for a low solvent viscosity ([`viscous`]); second order in time, the Eulerian ALE term by
//! three stages ([`conformation`]); the time step ([`step_size`]); the free-surface pressure
//! and traction ([`free_surface`]); uncorrected gradients on the free surface
//! ([`neighbours`]); the density-invariant PPE source and the volume at W/dr = 40
//! ([`pressure`]); the frame-independent shifting and the plate contact ([`advection`]). What
//! concerns every step:
//! * **Momentum-conserving pair forms.** The divergence of Phi is the positive form (the paper's
//!   choice with a free surface; the closed channel takes the negative one, below), the
//!   Laplacian is Morris' with the uncorrected gradient (King's code; symmetric coefficients),
//!   and the projection uses the positive form
//!   `grad p_i = sum_j (p_i + p_j) grad W_ij V_j` (Cummins & Rudman 1999, Shao & Lo 2003) instead
//!   of the corrected difference form: every fluid-fluid pair then exchanges equal and opposite
//!   momentum, so the force of the wall is exactly what the mirrors exert and the momentum balance
//!   is exact (`State::wall_impulse`), as for the weakly compressible schemes. The one term that
//!   is not a force, the ALE remapping `u_ps . grad u` of (24), is accounted separately
//!   (`State::remap_impulse`).
//! * Kernel: the quintic spline, h = 1.3 dx (`smoothing_ratio` is ignored). No equation of state,
//!   sound speed, artificial viscosity or artificial stress: those parameters are ignored.
//!   `rho` of the particles stays rho0.
//! * **The closed periodic channel** (no free surface) differs in three places, each measured on
//!   King & Lind's unit channel at 30 across: the body force is in the predictor (with the
//!   corrector's g the implicit viscous step acts on u - g dt, and the Newtonian flow settled g dt
//!   = 0.067 U fast everywhere); the mirrors continue the wall curvature of the velocity (fitted
//!   for the velocity gradient, from the wall's momentum balance for the viscous term, [`viscous`])
//!   and the fitted slope of the shear stress ([`crate::boundary::wall_profile`]; Newtonian centre
//!   line 0.9994 U, flow rate 0.66663 U H, against 1.0016 U and 0.6688 U H without); and div Phi is
//!   the negative form of (20) with the Bonet & Lok correction, `sum_j (Phi_j - Phi_i) L_i grad
//!   W_ij V_j`, which is what King & Lind use "for closed domains" (their section III, after (20):
//!   "more accurate, and provides increased stability when large stress gradients are present";
//!   their (24) prints the positive form, the one of their free-surface runs). Its fluid pairs do
//!   not cancel, so the net stress force on the fluid is booked as the walls' (a periodic channel
//!   has no other boundary). Measured (Oldroyd-B, Re = 1, beta = 0.1, Lagrangian, t = 0..3): with
//!   the positive form the wall rows under the polymer's tension (tr A = 120 at Wi = 2) lost their
//!   lattice from t = 1.9, min det A fell to 0.87 (Oldroyd-B keeps det A >= 1 in shear) and the
//!   centre line left Waters & King by 0.49 U (Wi = 2, 30 across; 0.55 U at 15 across, Wi = 5
//!   likewise); with the negative form the largest deviation is 1.8 % (Wi = 2), 1.5 % (Wi = 1), det
//!   A >= 1 throughout, at the full step. The Lagrangian frame took a third of (28)'s step before,
//!   as a cure for that disorder; with the negative form the third changed nothing measurable (Wi =
//!   2: 1.83 % against 1.77 %; Wi = 1: 1.48 % against 1.45 %) and is gone.
//! * **Curved walls in a closed cell** (the cylinder array, King & Lind section IV.B), two
//!   changes from the plain projection, each measured on King & Lind's Newtonian cell (Eulerian
//!   frame, drag coefficient K = F / (eta0 ⟨u⟩) against the finite-element 92.83):
//!   - *The corrected difference form of the pressure gradient*,
//!     `-L_i sum_j (p_j - p_i) grad W_ij V_j / rho`, for every particle ([`projection`]). The
//!     positive form keeps `2 p_i grad C_i`, C the kernel sum; next to a circle the mirrors are
//!     no lattice and grad C is of order 0.1-0.4 / h, while the cell's pressure is set only up
//!     to a constant and swings by rho g L H / 2R (thousands of Pa) across the cylinder: a
//!     spurious force larger than the body force. What the difference form adds to the pair
//!     form is booked as the cylinder's force, so the momentum books stay exact.
//!   - *An incremental pressure correction* (Goda 1979; van Kan 1986): the predictor carries
//!     `-grad p^n / rho`, the PPE solves for the increment `p^{n+1} - p^n`. The plain
//!     projection's steady state slips along the wall by `dt grad_t p / rho`: u* is no slip,
//!     `u^{n+1} = u* - dt grad p / rho` is not, and a cylinder has a tangential pressure
//!     gradient at its wall (a fully developed channel has none). At 16 across K went from 81.5
//!     to 86.2 when the step was divided by four; with the increment it is 92.04 at the full
//!     step.
//!
//!   With the ring lattice round the cylinder (`scene::cylinder_array`) and no hydrostatic
//!   mirror offset in a closed cell (`walls`): K = 80.55, 92.04, 92.13, 92.80 at 8, 16, 24, 32
//!   particles across the diameter (t = 0.2 s; -13 %, -0.85 %, -0.75 %, -0.03 %); without the
//!   four, 23.7 and 63.6 at 8 and 16 (24 across neither steady nor symmetric). Straight walls
//!   alone (the channel, the drops) keep the positive form and the plain projection bit for bit.
//! * A pressure or viscous solve that does not converge stops the run with the solver's cause.
//! * **Inlet** (the jet's nozzle, [`crate::state::Inflow::holds`]): a buffer of particles held at
//!   the inflow velocity, in the spirit of the moving ghost particles King & Lind cite for their
//!   jet. A held particle moves with its prescribed velocity (no shifting) and keeps it through
//!   the step: the momentum the forces of the step would have given it is taken by the inlet
//!   (`Inflow::momentum`), so the momentum balance stays exact. In the implicit viscous solve
//!   held particles are Dirichlet rows (their velocity), so the column below hangs from a
//!   nozzle at the inflow velocity: as unknowns of the solve, reset only after it, they were
//!   dragged down by the column within the step (by about dt T / M, T the column's weight and
//!   M the nozzle's mass: a tenth to a quarter of U0 at the default step), and the column lost
//!   part of its hold (Newtonian jet, H = 12 D, 6 across: lowest point D/2 above the plate at
//!   0.1922 s before, 0.1956 s after; explicit viscous step 0.2157 s, WCSPH 0.2231 s;
//!   docs/methods.md, "Inlet under ISPH"). What the held particles exert on the free ones in
//!   the solve is the inlet's momentum, not the walls'. Velocity prescribed means a
//!   Neumann condition on the pressure: held particles are unknowns of the PPE with
//!   `lap p = 0` (the prescribed flow is divergence-free) and, where free fluid is within
//!   their kernel support, never Dirichlet, so the free fluid at the exit sees the pressure
//!   continued into the nozzle (the truncated Laplacian at the nozzle's sides and top is a
//!   zero normal gradient) instead of a free surface. Held particles out of reach of free fluid
//!   keep the free-surface p = 0 of their edges: that fixes the pressure level when the nozzle
//!   holds all the fluid (t = 0, or a closed valve after the jet has left).

pub mod advection;
pub mod conformation;
pub mod free_surface;
pub mod neighbours;
mod plate_load;
pub mod ppe;
pub mod predictor;
pub mod pressure;
pub mod projection;
pub mod step_size;
pub mod viscous;
pub mod walls;

use super::health;
use super::params::Params;
use super::wc::WcSpace;
use super::Scheme;
use crate::boundary::wall::Wall;
use crate::boundary::Boundary;
use crate::config::{ConformationMethod, IsphFrame, IsphFreeSurface, Numerics, ViscousStep};
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::kernel::{Kernel, QuinticSplineKernel};
use crate::neighbors::NeighborList;
use crate::operators::kinematics::corrected_velocity_gradients;
use crate::operators::pairs::PairCache;
use crate::operators::surface::{self, Surface};
use crate::profile::{Profile, Stamp};
use crate::rheology::{Evss, Rheology};
use crate::state::State;
use ppe::SolverOptions;
use rayon::prelude::*;
use std::sync::Mutex;
use std::time::Instant;
use walls::Virtual;

pub use viscous::{isph_evss_alpha, MIN_COMPACT_VISCOSITY_RATIO};

/// h / dx of King & Lind's quintic kernel.
pub const H_OVER_DX: f64 = 1.3;
/// Smallest number of particles per parallel task.
const MIN_TASK: usize = 64;

/// Wall-clock time spent in the parts of the step (for `viscosph bench`), seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct IsphTimings {
    /// Whole steps.
    pub total: f64,
    /// Pressure Poisson equation: assembly, preconditioner and BiCGStab.
    pub pressure_solve: f64,
    /// Implicit viscous step: assembly, preconditioner and BiCGStab.
    pub viscous_solve: f64,
}

/// The ISPH scheme for rheology `R`.
pub struct Isph<R: Rheology, const N: usize = 2> {
    kernel: QuinticSplineKernel<N>,
    model: R,
    p: Params<N>,
    evss: Evss,
    method: ConformationMethod,
    frame: IsphFrame,
    viscous: ViscousStep,
    /// Weight of the new velocity in the implicit viscous step (theta method).
    theta: f64,
    /// Whether the domain has a free surface (every scene but the closed channel).
    free_surface: bool,
    dt_coef: f64,
    rho: f64,
    solver: SolverOptions,
    /// One wall model per plate of the state, in the state's order, read only through the
    /// [`Boundary`] trait (King & Lind's mirror particles: [`walls::mirror_walls`]).
    walls: Vec<Box<dyn Boundary<N>>>,
    /// Positions of fluid (r*) then virtual particles, of the last step.
    all_x: Vec<Vector<N>>,
    /// Kernel values of the last step's pairs (full layout).
    pairs: PairCache<N>,
    /// Kernel sum `sum_j V W_ij` of a particle inside an unbounded square (3D: cubic) lattice.
    c_lattice: f64,
    /// Its share below a straight surface row (near-surface density-invariant source).
    half_lattice: surface::HalfLattice,
    /// Free-surface pressure from King & Lind eq. (35a)'s solvent normal stress, with the
    /// projection's consistent ghost pressure (`isph_free_surface`; [`free_surface`], "Free-surface
    /// pressure"); p = 0 on the surface otherwise.
    normal_stress: bool,
    pub timings: IsphTimings,
    /// The per-pass timers (`viscosph run --profile`): behind a lock so the parts of a step,
    /// which borrow the scheme shared, can book their time.
    prof: Mutex<Profile>,
}

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// Whether a step splits the walls' force wall by wall (`walls` walls): in a closed cell
    /// (no free surface) with more than one wall. There every force the walls exert on the
    /// fluid is a pair force with a virtual particle, which belongs to one wall, or the
    /// momentum the implicit viscous solve changed, which is the virtual pairs' viscous force
    /// at the solved velocities, or (elastic fluid) the remainder of the difference form of
    /// div Phi over the fluid pairs, which is nonzero only where a particle's kernel support
    /// is cut by a wall and is booked to the particle's nearest wall (`predictor`). Not split
    /// with a free surface (the surface terms' net is removed from every particle).
    fn splits_wall_forces(&self, walls: usize) -> bool {
        walls > 1 && !self.free_surface
    }

    /// A clock reading if profiling is on ([`Profile::start`]).
    fn clock(&self) -> Option<Stamp> {
        self.prof.lock().expect("profile lock").start()
    }

    /// Book the time since `since` to the part `name` of the step, which runs on one thread
    /// where `serial` ([`Profile::lap`]); returns the start of the next part.
    fn lap(&self, since: Option<Stamp>, name: &'static str, serial: bool) -> Option<Stamp> {
        since.and_then(|t| {
            self.prof
                .lock()
                .expect("profile lock")
                .lap(Some(t), name, serial)
        })
    }

    /// Book a linear solve's time since `since` to `names[0]`, or to `names[1]` on one thread
    /// where ILU(0) preconditions it (its factorisation and triangular solves are sequential;
    /// an upper bound, its matrix-vector products run on all threads).
    fn lap_solve(
        &self,
        since: Option<Stamp>,
        opts: &SolverOptions,
        names: [&'static str; 2],
    ) -> Option<Stamp> {
        if opts.preconditioner == ppe::Preconditioner::Ilu0 {
            self.lap(since, names[1], true)
        } else {
            self.lap(since, names[0], false)
        }
    }

    /// The scheme for the numerics `cfg` of an effective configuration, the constants `p` (which
    /// say whether the scene has a free surface and what `auto` means for it) and the plates of
    /// the initial state.
    pub fn new(model: R, p: Params<N>, cfg: &Numerics, plates: &[Wall<N>]) -> Self {
        let kernel = QuinticSplineKernel::<N>::new(H_OVER_DX * p.dx);
        // The EVSS floor was measured on drops; the closed channel keeps the configured
        // alpha_V (King & Lind's beta = 0 channel uses alpha_V = 0.01).
        let free_surface = p.free_surface;
        let evss_alpha = if free_surface {
            isph_evss_alpha(&model, p.evss_alpha)
        } else {
            p.evss_alpha
        };
        let evss = Evss::new(&model, evss_alpha);
        let method = match cfg.conformation_method {
            ConformationMethod::Auto => ConformationMethod::Log,
            m => m,
        };
        let reach = kernel.radius();
        let c_lattice = pressure::lattice_concentration(&kernel, p.dx);
        let half_lattice = surface::HalfLattice::new(&kernel, p.dx);
        Self {
            kernel,
            model,
            evss,
            method,
            frame: cfg.isph_frame,
            viscous: cfg.isph_viscous_step,
            // With a free surface, Crank-Nicolson's undamped stiff modes ring: the Newtonian
            // K&L drop (W/dr = 40) lost 48 % of its volume by t* = 8 at theta = 1/2 and 4.1 %
            // at theta = 0.6, against 1.7 % with backward Euler.
            theta: if free_surface {
                1.0
            } else {
                viscous::VISCOUS_THETA_CLOSED
            },
            free_surface,
            dt_coef: step_size::DT_COEF_PER_FACTOR * cfg.time_step_factor,
            rho: p.eos.rho0,
            solver: SolverOptions::default(),
            walls: walls::mirror_walls(plates, reach),
            all_x: Vec::new(),
            pairs: PairCache::default(),
            c_lattice,
            half_lattice,
            normal_stress: free_surface
                && match cfg.isph_free_surface {
                    IsphFreeSurface::Auto => p.auto_free_surface == IsphFreeSurface::NormalStress,
                    IsphFreeSurface::ZeroPressure => false,
                    IsphFreeSurface::NormalStress => true,
                },
            timings: IsphTimings::default(),
            prof: Mutex::new(Profile::default()),
            p,
        }
    }
}

/// The inlet's held particles of one step (module documentation, "Inlet"): their velocity is
/// prescribed (the scene has just put it back). None without an inlet.
struct Held {
    flags: Vec<bool>,
    /// Number of free (not held) fluid particles, at least 1.
    free: usize,
}

impl Held {
    fn of<const N: usize>(st: &State<N>) -> Self {
        let flags: Vec<bool> = match &st.inflow {
            Some(inl) => st.fluid.x.iter().map(|x| inl.holds(x)).collect(),
            None => Vec::new(),
        };
        let holds = |i: usize| flags.get(i).copied().unwrap_or(false);
        let free = (0..st.fluid.len()).filter(|&i| !holds(i)).count().max(1);
        Self { flags, free }
    }

    /// Whether fluid particle i is held at the inflow velocity.
    #[inline]
    pub fn holds(&self, i: usize) -> bool {
        self.flags.get(i).copied().unwrap_or(false)
    }

    /// The mean of per-particle values over the free (not held) particles, summed in index
    /// order: what a term that is not a pair force leaves as a net force on the fluid, removed
    /// because a free surface exerts none.
    pub fn mean_over_free<'a, const N: usize>(
        &self,
        v: impl Iterator<Item = &'a Vector<N>>,
    ) -> Vector<N> {
        v.fold(Vector::<N>::zeros(), |a, f| a + f) / self.free as f64
    }
}

/// What the parts of one step share once step 2 has run.
struct Context<const N: usize> {
    /// Number of fluid particles (the virtual ones follow in the lists).
    pub n: usize,
    pub dt: f64,
    /// Mass of every particle.
    pub mass: f64,
    /// Volume m / rho0 of every particle.
    pub vol: f64,
    /// Largest fluid speed at the start of the step.
    pub umax: f64,
    pub lagrangian: bool,
    pub held: Held,
    /// Fluid positions r* of step 1.
    pub xs: Vec<Vector<N>>,
    /// The walls' virtual particles.
    pub virt: Virtual<N>,
    /// Neighbour lists of the fluid particles over fluid and virtual particles.
    pub nl: NeighborList,
    /// Bonet & Lok correction matrices (22), the identity on the free surface.
    pub l: Vec<Tensor<N>>,
    /// With the normal-stress surface condition, every particle's own correction matrix, the
    /// free surface's included (empty otherwise; [`free_surface`], "Free-surface pressure").
    pub l_own: Vec<Tensor<N>>,
    /// Free surface and normals (36)-(39), with a free surface.
    pub surf: Option<Surface<N>>,
    /// Corrections to the virtual particles' no-slip velocities (the closed channel's wall
    /// curvature of u^n; zeros with a free surface).
    pub u_curv: Vec<Vector<N>>,
}

impl<const N: usize> Context<N> {
    /// The fluid particle whose values list entry `j` carries: j itself, or a virtual
    /// particle's parent.
    #[inline]
    pub fn source(&self, j: usize) -> usize {
        if j < self.n {
            j
        } else {
            self.virt.parent[j - self.n] as usize
        }
    }

    /// Adds the pair force `a` of list entry `j` to the fluid pairs' sum `f` or, for a virtual
    /// particle, to the virtual pairs' sum `fw` and to its wall's entry of `by_wall` (empty
    /// where the step does not split the walls' force).
    #[inline]
    pub fn add_pair(
        &self,
        j: usize,
        a: Vector<N>,
        f: &mut Vector<N>,
        fw: &mut Vector<N>,
        by_wall: &mut [Vector<N>],
    ) {
        if j < self.n {
            *f += a;
        } else {
            *fw += a;
            if !by_wall.is_empty() {
                by_wall[self.virt.wall_of(j - self.n)] += a;
            }
        }
    }

    /// A fluid velocity field extended over the virtual particles (no slip, with this step's
    /// corrections).
    pub fn extend(&self, u: &[Vector<N>]) -> Vec<Vector<N>> {
        self.virt.extend_velocity(u, &self.u_curv)
    }
}

/// The fields of step 3 the later steps read.
struct Fields<const N: usize> {
    /// u^n over fluid and virtual particles.
    pub u_n: Vec<Vector<N>>,
    /// Corrected velocity gradient of u^n.
    pub kappa: Vec<Tensor<N>>,
    /// Shifting (ALE) velocity.
    pub u_ps: Vec<Vector<N>>,
    /// Viscosity of the Laplacian term.
    pub mu: Vec<f64>,
    /// The stress Phi of the polymer (with EVSS) of the fluid and of the virtual particles
    /// (empty for inelastic models).
    pub phi: Vec<Tensor<N>>,
    pub phi_virtual: Vec<Tensor<N>>,
}

/// What a step accounts for as it goes.
#[derive(Debug)]
struct Books<const N: usize> {
    /// Force of the walls on the fluid: the virtual particles' share of the pair forces of the
    /// predictor and the projection, and the momentum the implicit viscous solve changed.
    pub wall_on_fluid: Vector<N>,
    /// `wall_on_fluid` wall by wall (in the state's order) where the step splits it
    /// ([`Isph::splits_wall_forces`]); empty otherwise.
    pub per_wall: Vec<Vector<N>>,
    /// `sum m u_ps . grad u`, the ALE remapping of (24): not a force (`State::remap_impulse`).
    pub remap_force: Vector<N>,
    /// Momentum the inlet takes from its particles to hold them at the inflow velocity.
    pub held_momentum: Vector<N>,
    /// BiCGStab iterations of the pressure and the viscous solves.
    pub iterations: [u64; 2],
    /// Seconds in the pressure and the viscous solves.
    pub pressure_time: f64,
    pub viscous_time: f64,
    /// The plate's force on each fluid particle, where the step books it ([`plate_load`]).
    pub plate: plate_load::PlateBook<N>,
}

impl<const N: usize> Default for Books<N> {
    fn default() -> Self {
        Self {
            wall_on_fluid: Vector::zeros(),
            per_wall: Vec::new(),
            remap_force: Vector::zeros(),
            held_momentum: Vector::zeros(),
            iterations: [0; 2],
            pressure_time: 0.0,
            viscous_time: 0.0,
            plate: Default::default(),
        }
    }
}

impl<R: Rheology, const N: usize> Scheme<N> for Isph<R, N>
where
    Const<N>: Dim + WcSpace<N>,
{
    fn step(&mut self, st: &mut State<N>, max_dt: f64) -> Result<f64, String> {
        let t_start = Instant::now();
        let t = self.clock();
        // The step, eq. (28) with this scheme's further limits.
        let size = self.step_size(st, max_dt)?;
        let dt = size.dt;
        let n = st.fluid.len();
        let vol = st.fluid.mass / self.rho;
        let lagrangian = self.frame == IsphFrame::Lagrangian;
        let held = Held::of(st);
        let t = self.lap(t, "time step, inlet", true);

        // Step 1, eq. (23): r* = r^n + dt u^n.
        let xs = self.predict_positions(&st.fluid, dt, lagrangian);
        self.lap(t, "advection r*", false);

        // Step 2: the walls' virtual particles, the lists, the pair cache, the correction (22)
        // and the free surface (36)-(39); then the shifting velocity (40)-(44).
        let nb = self.neighbourhood(st, xs, vol, lagrangian)?;
        let ctx = Context {
            n,
            dt,
            mass: st.fluid.mass,
            vol,
            umax: size.umax,
            lagrangian,
            held,
            xs: nb.xs,
            virt: nb.virt,
            nl: nb.nl,
            l: nb.l,
            l_own: nb.l_own,
            surf: nb.surf,
            u_curv: nb.u_curv,
        };
        let t = self.clock();
        let u_ps = self.shifting_velocity(&st.fluid, &ctx, nb.grad_c, nb.grad_c_q);
        let t = self.lap(t, "shifting velocity", true);

        // Step 3: the conformation tensor to n + 1/2 (section III.B, eqs. (29)-(33)) with the
        // corrected velocity gradient (20), (22) of u^n, and the stress Phi (6) it gives.
        let u_n = ctx.extend(&st.fluid.v);
        let kappa = corrected_velocity_gradients(n, &u_n, vol, &ctx.nl, &self.pairs, &ctx.l);
        let t = self.lap(t, "velocity gradient", false);
        // With the normal-stress surface condition the surface rows stretch the polymer by
        // their own corrected gradient ([`conformation`], "The surface rows' stretching").
        let kappa_own = self.surface_own_gradient(&kappa, &u_n, &ctx);
        let kappa_conf = kappa_own.as_deref().unwrap_or(&kappa);
        let conf = self.conformation(&st.fluid.conf, kappa_conf, &u_ps, &ctx)?;
        let (phi, phi_virtual) = self.polymer_stress(st, &ctx, &conf, &kappa);
        let t = self.lap(t, "conformation, polymer stress", false);
        let mu = kappa
            .par_iter()
            .with_min_len(MIN_TASK)
            .map(|k| self.laplacian_viscosity(k))
            .collect();
        let f = Fields {
            u_n,
            kappa,
            u_ps,
            mu,
            phi,
            phi_virtual,
        };
        let mut books = Books {
            per_wall: if self.splits_wall_forces(st.walls.len()) {
                vec![Vector::<N>::zeros(); st.walls.len()]
            } else {
                Vec::new()
            },
            plate: plate_load::PlateBook::of(st),
            ..Default::default()
        };

        self.lap(t, "viscosity, books", true);

        // Step 4: the predictor u* (24), the solvent viscosity (21) explicit or implicit.
        let u_star = self.predictor(st, &ctx, &f, &mut books)?;

        // Step 5: the PPE (25) with the free-surface condition (35a).
        let pressure = self.pressure(st, &ctx, &f, &u_star, &mut books)?;

        // Step 6: the projection (26), u^{n+1} = u* - dt grad p / rho + dt g.
        let t = self.clock();
        let u_new = self.projection(&st.fluid, &ctx, &u_star, &pressure, &mut books);
        let t = self.lap(t, "projection", false);

        // Step 7: advection (27), then the plate contact and the books.
        let (contacts, plate_contact) =
            self.advect(st, &ctx, &f.u_ps, u_new, conf, books.held_momentum);
        let t = self.lap(t, "advection, wall contact", true);
        let contact = contacts.iter().fold(Vector::<N>::zeros(), |a, m| a + m);
        for (fw, m) in books.per_wall.iter_mut().zip(&contacts) {
            *fw += m / dt;
        }
        st.wall_force = -books.wall_on_fluid - contact / dt;
        st.wall_impulse += -books.wall_on_fluid * dt - contact;
        // One wall takes all the walls' force; with more, each wall's share of the pair forces
        // and of the implicit viscous solve where the step splits them
        // ([`Isph::splits_wall_forces`]), not split otherwise.
        let per_wall = if st.walls.len() == 1 {
            vec![st.wall_force]
        } else {
            books.per_wall.iter().map(|f| -f).collect()
        };
        st.book_wall_forces(per_wall, dt);
        st.plate_load = std::mem::take(&mut books.plate).into_load(&plate_contact, dt);
        st.remap_impulse += books.remap_force * dt;
        st.pressure = if self.incremental(&ctx) {
            let p_n = self.previous_pressure(st, &ctx);
            p_n.iter().zip(&pressure.p).map(|(a, b)| a + b).collect()
        } else {
            pressure.p
        };
        st.solver_iterations[0] += books.iterations[0];
        st.solver_iterations[1] += books.iterations[1];
        st.last_dt = size.stable;
        let t = self.lap(t, "wall forces, pressure", true);
        // No density to check, and no tensile instability to act on: the void fraction is
        // reported, not acted on.
        health::check_particles(
            &st.fluid,
            &st.walls,
            self.p.dx,
            self.p.domain_radius,
            R::ELASTIC,
            None,
        )?;
        // The void fraction of the weakly compressible schemes' health check (none in 3D yet).
        st.void_fraction =
            Const::<N>::void_fraction(&st.fluid, st.plate, &st.walls, self.p.dx).unwrap_or(0.0);
        self.lap(t, "health check", false);
        self.timings.pressure_solve += books.pressure_time;
        self.timings.viscous_solve += books.viscous_time;
        self.timings.total += t_start.elapsed().as_secs_f64();
        Ok(dt)
    }

    fn timings(&self) -> super::Timings {
        let prof = self.prof.lock().expect("profile lock");
        if prof.start().is_some() {
            return prof.timings();
        }
        // Profiling off: the solves' wall time, which the scheme always keeps (`bench isph`).
        let mut t = super::Timings {
            total: self.timings.total,
            ..Default::default()
        };
        t.add("pressure solve", false, self.timings.pressure_solve, 0.0);
        t.add("viscous solve", false, self.timings.viscous_solve, 0.0);
        t
    }

    fn set_profiling(&mut self, on: bool) {
        self.prof.lock().expect("profile lock").enable(on);
    }

    fn wall_positions(&self, st: &State<N>) -> Vec<Vector<N>> {
        self.walls
            .iter()
            .zip(&st.walls)
            .flat_map(|(w, p)| w.positions(p))
            .collect()
    }
}
