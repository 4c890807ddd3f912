//! The rate evaluation of the weakly compressible schemes: Fang 2006's WCSPH ([`super::wcsph`])
//! and Ren 2015's PDRI-SPH ([`super::pdri`]) discretise the same equations the same way (Fang
//! eqs. 23, 26, 27 are Ren eqs. 15, 13, 14; the artificial viscosity Fang eqs. 30-37 is Ren
//! eq. 19). They differ in the wall model and the artificial stress (values held by one
//! [`WcCore`]), and in the time integration and the density reinitialisation (in the schemes).
//!
//! One rate evaluation ([`WcCore::rates`]) runs:
//! 1. virtual velocities: each wall ([`crate::boundary::Boundary`]) fills its particles' (and
//!    says whether the continuity equation takes them or the wall's own velocity);
//! 2. fluid pass 1 (a gather): pair geometry cached for pass 2 ([`crate::operators::pairs`]),
//!    velocity gradient and continuity ([`crate::operators::kinematics`]), pressure from the
//!    equation of state, the stress ([`crate::operators::stress::assemble`]) and, for Ren's
//!    artificial stress, the sum of kernel Hessians;
//! 3. virtual stresses, filled by each wall, and their artificial stresses;
//! 4. fluid pass 2 (a gather over the cached pairs): momentum with artificial viscosity and
//!    artificial stress ([`crate::operators::artificial`]), plus Morris' viscous Laplacian when
//!    EVSS is on; the part exerted by virtual particles is the wall force.
//!
//! The passes read a neighbour's data from a packed record per particle and pass, filled
//! before each pass (passes.rs says how the hot loops are laid out, and why).
//!
//! Every pass is a gather over ascending neighbour indices, so results are bitwise independent of
//! the thread count. Every pair vector goes through the domain ([`crate::neighbors::Domain`]), so
//! the same code runs in periodic boxes.

use super::params::Params;
use crate::boundary::dummy::DummyWall;
use crate::boundary::ghost::{GhostWall, WallModel};
use crate::boundary::wall::Wall;
use crate::boundary::{self, Boundary, Model};
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::kernel::Kernel;
use crate::neighbors::{Grid, NeighborList};
use crate::operators::artificial::{self, ArtificialStress};
use crate::operators::kinematics::Kinematics;
use crate::operators::pairs::PairCache;
use crate::operators::stress::{self, MORRIS_ETA2};
use crate::particles::{assign_par, copy_par, Fluid};
use crate::profile::Profile;
use crate::rheology::{self, Evss, Rheology};
#[cfg(test)]
use crate::{Mat2, Vec2};
use rayon::prelude::*;

/// Neighbour-list skin as a fraction of h.
const SKIN: f64 = 0.25;
/// Smallest number of particles per parallel task: below it the work of a task costs less than
/// handing it to another thread. Light passes (a few flops per particle) take many more.
pub(crate) const MIN_TASK: usize = 64;
pub(crate) const MIN_TASK_LIGHT: usize = 1024;

/// One wall model per wall, as `wall_boundary` ([`Params::wall_boundary`]) resolves for the
/// wall's shape ([`boundary::resolve`]): `model` is the scheme's paper's (Fang's or Ren's
/// virtual particles), `auto`'s choice on straight walls; on curved ones Adami, Hu & Adams
/// 2012's dummy particles ([`DummyWall`]), which need no straight frame. A model the scheme or
/// shape cannot take is refused when the simulation is built, before this.
pub fn ghost_walls<K: Kernel>(
    kernel: K,
    model: WallModel,
    p: &Params,
    plates: &[Wall],
) -> Vec<Box<dyn Boundary>> {
    let paper = match model {
        WallModel::Fang => Model::Image,
        WallModel::Ren => Model::Ghost,
    };
    plates
        .iter()
        .map(|w| {
            let ghost =
                |m| Box::new(GhostWall::new(kernel, m, p.domain, p.dx)) as Box<dyn Boundary>;
            match boundary::resolve(p.wall_boundary, paper, w) {
                Ok(Model::Image) => ghost(WallModel::Fang),
                Ok(Model::Ghost) => ghost(WallModel::Ren),
                Ok(Model::Dummy) => Box::new(DummyWall::new(kernel, p.domain, p.dx, p.gravity)),
                Ok(Model::Mirror) | Err(_) => {
                    unreachable!("wall models are checked when a simulation is built")
                }
            }
        })
        .collect()
}

/// What one rate evaluation reports besides the per-particle rates.
#[derive(Debug, Clone, Copy)]
pub struct StageReport<const N: usize = 2> {
    /// Force of the virtual (wall) particles on the fluid \[N/m\].
    pub wall_on_fluid: Vector<N>,
    /// Largest acceleration magnitude.
    pub max_acc: f64,
}

impl<const N: usize> Default for StageReport<N> {
    fn default() -> Self {
        Self {
            wall_on_fluid: Vector::zeros(),
            max_acc: 0.0,
        }
    }
}

/// The shared machinery of the weakly compressible schemes for kernel `K` and rheology `R`:
/// neighbour lists, the walls' virtual particles, work arrays and the rate evaluation.
pub struct WcCore<K: Kernel<N>, R: Rheology, const N: usize = 2> {
    pub kernel: K,
    pub model: R,
    pub p: Params<N>,
    art: ArtificialStress,
    evss: Evss,
    /// One wall model per plate of the state, in the same order.
    walls: Vec<Box<dyn Boundary<N>>>,
    /// Virtual particle index range (after the fluid) of each wall.
    wall_ranges: Vec<std::ops::Range<usize>>,
    // Neighbour structures, rebuilt when particles (or walls) have moved more than half the skin.
    built_x: Vec<Vector<N>>,
    built_walls: Vec<f64>,
    /// Neighbours (fluid and virtual) of every fluid particle.
    nlist: NeighborList,
    /// Neighbours of every virtual particle (only for Ren's artificial stress).
    vlist: NeighborList,
    // Work arrays over all particles (fluid first, then virtual).
    all_x: Vec<Vector<N>>,
    all_v: Vec<Vector<N>>,
    /// Velocities of the virtual particles (alone, in the order of `all_v[nf..]`) in the
    /// continuity equation: `all_v`'s, or the wall's own velocity for a wall that asks for it
    /// ([`Boundary::continuity_at_wall_velocity`]).
    cont_v: Vec<Vector<N>>,
    all_rho: Vec<f64>,
    all_sigma: Vec<Tensor<N>>,
    all_art: Vec<Tensor<N>>,
    /// Sum over neighbours of the kernel Hessian (Ren eq. 20b), when needed.
    all_hess: Vec<Tensor<N>>,
    /// Viscosity of the Laplacian viscous term (read with EVSS only).
    all_mu: Vec<f64>,
    /// m / rho of every particle.
    all_vol: Vec<f64>,
    /// What the gather passes read of a neighbour, packed per particle (fluid first, then
    /// virtual): for pass 1 ([`passes::Rec`]) and for pass 2 ([`passes::Rec2`]).
    rec: Vec<passes::Rec<N>>,
    rec2: Vec<passes::Rec2<N>>,
    pairs: PairCache<N>,
    /// Polymer stress of fluid particles (empty for inelastic models); from pass 1 on, with EVSS,
    /// the elastic stress as it enters sigma (Phi and its trace term), which is what the wall's
    /// zero-normal-elastic-stress condition removes.
    tau_p: Vec<Tensor<N>>,
    // Fluid rates of the last evaluation.
    pub kappa: Vec<Tensor<N>>,
    pub drho: Vec<f64>,
    pub acc: Vec<Vector<N>>,
    wall_acc: Vec<Vector<N>>,
    /// With more than one wall: per fluid particle, the share of `wall_acc` (the acceleration
    /// the virtual particles give it) of each wall, wall by wall, so each wall's force is
    /// measured alone.
    wall_split: Vec<Vector<N>>,
    /// Per-pass timers (off unless profiling: see [`crate::profile`]).
    pub prof: Profile,
}

impl<K: Kernel<N>, R: Rheology, const N: usize> WcCore<K, R, N>
where
    Const<N>: Dim + WcSpace<N>,
{
    /// `walls` holds one wall model per plate of the state, in the state's order.
    pub fn new(kernel: K, model: R, p: Params<N>, walls: Vec<Box<dyn Boundary<N>>>) -> Self {
        let art = ArtificialStress::new(&kernel, p.art_kind, p.art_coef, p.dx);
        let evss = Evss::new(&model, p.evss_alpha);
        Self {
            kernel,
            model,
            p,
            art,
            evss,
            walls,
            wall_ranges: Vec::new(),
            built_x: Vec::new(),
            built_walls: Vec::new(),
            nlist: NeighborList::default(),
            vlist: NeighborList::default(),
            all_x: Vec::new(),
            all_v: Vec::new(),
            cont_v: Vec::new(),
            all_rho: Vec::new(),
            all_sigma: Vec::new(),
            all_art: Vec::new(),
            all_hess: Vec::new(),
            all_mu: Vec::new(),
            all_vol: Vec::new(),
            rec: Vec::new(),
            rec2: Vec::new(),
            pairs: PairCache::default(),
            tau_p: Vec::new(),
            kappa: Vec::new(),
            drho: Vec::new(),
            acc: Vec::new(),
            wall_acc: Vec::new(),
            wall_split: Vec::new(),
            prof: Profile::default(),
        }
    }

    /// Force of each wall's virtual particles on the fluid at the last rate evaluation, whose
    /// total (all walls) was `total` [N/m]. With one wall it is the total itself; with more, each
    /// wall's share summed over the particles in index order (the shares add up to the total to
    /// round-off: the total sums every particle's virtual neighbours in one run).
    pub fn wall_on_fluid_per_wall(&self, total: Vector<N>, mass: f64) -> Vec<Vector<N>> {
        let nw = self.walls.len();
        if nw <= 1 {
            return vec![total; nw];
        }
        let mut out = vec![Vector::zeros(); nw];
        for chunk in self.wall_split.chunks(nw) {
            for (o, a) in out.iter_mut().zip(chunk) {
                *o += a * mass;
            }
        }
        out
    }

    /// Force of wall `wall`'s virtual particles on each fluid particle at the last rate
    /// evaluation [N/m]: the terms whose sum over the particles is that wall's share of
    /// [`StageReport::wall_on_fluid`] (see [`WcCore::wall_on_fluid_per_wall`]).
    pub fn wall_on_particles(&self, wall: usize, mass: f64) -> Vec<Vector<N>> {
        let nw = self.walls.len();
        if nw <= 1 {
            return self
                .wall_acc
                .par_iter()
                .with_min_len(MIN_TASK_LIGHT)
                .map(|a| a * mass)
                .collect();
        }
        self.wall_split
            .par_chunks(nw)
            .with_min_len(MIN_TASK_LIGHT)
            .map(|chunk| chunk[wall] * mass)
            .collect()
    }

    /// Minus [`WcCore::wall_on_particles`], written into `out` (its earlier contents dropped,
    /// its allocation kept): the load of each fluid particle on wall `wall` [N/m], built in one
    /// pass at every step without a new vector.
    pub fn wall_load_into(&self, wall: usize, mass: f64, out: &mut Vec<Vector<N>>) {
        out.clear();
        let nw = self.walls.len();
        if nw <= 1 {
            out.par_extend(
                self.wall_acc
                    .par_iter()
                    .with_min_len(MIN_TASK_LIGHT)
                    .map(|a| -(a * mass)),
            );
        } else {
            out.par_extend(
                self.wall_split
                    .par_chunks(nw)
                    .with_min_len(MIN_TASK_LIGHT)
                    .map(|chunk| -(chunk[wall] * mass)),
            );
        }
    }

    /// Whether the viscous force goes through Morris' Laplacian (EVSS, or chosen).
    fn laplacian(&self) -> bool {
        self.evss.is_on() || self.p.viscous_laplacian
    }

    fn search_radius(&self) -> f64 {
        self.kernel.radius() + SKIN * self.kernel.h()
    }

    /// Rebuild the neighbour lists (and grow the walls) if any particle or wall moved more than
    /// half the skin since the last build.
    pub fn refresh_neighbors(&mut self, x: &[Vector<N>], plates: &mut [Wall<N>]) {
        let half_skin = 0.5 * SKIN * self.kernel.h();
        let half_skin2 = half_skin * half_skin;
        let dom = self.p.domain;
        let t = self.prof.start();
        let stale = self.built_x.len() != x.len()
            || self.built_walls.len() != plates.len()
            || plates
                .iter()
                .zip(&self.built_walls)
                .any(|(pl, d)| (pl.displacement() - d).abs() > half_skin)
            || x.par_iter()
                .zip(self.built_x.par_iter())
                .with_min_len(MIN_TASK_LIGHT)
                .any(|(a, b)| dom.delta(a, b).norm_squared() > half_skin2);
        if !stale {
            self.prof.lap(t, "neighbours: staleness check", false);
            return;
        }
        let t = self.prof.lap(t, "neighbours: staleness check", false);
        let radius = self.search_radius();
        let nf = x.len();
        self.all_x.clear();
        self.all_x.extend_from_slice(x);
        self.wall_ranges.clear();
        if !self.walls.is_empty() {
            // Walls interpolate from fluid only.
            let fluid_grid = Grid::build(x, radius, &dom);
            for (wall, plate) in self.walls.iter_mut().zip(plates.iter_mut()) {
                let start = self.all_x.len();
                wall.place(plate, x, &fluid_grid, radius, &mut self.all_x);
                self.wall_ranges.push(start..self.all_x.len());
            }
        }
        let t = self.prof.lap(t, "neighbours: wall particles", true);
        let grid = Grid::build(&self.all_x, radius, &dom);
        let t = self.prof.lap(t, "neighbours: grid", false);
        self.nlist = NeighborList::build(&grid, &self.all_x, x, radius, &dom);
        self.vlist = if self.art.needs_hessian() {
            NeighborList::build(&grid, &self.all_x, &self.all_x[nf..], radius, &dom)
        } else {
            NeighborList::default()
        };
        let t = self.prof.lap(t, "neighbours: lists", false);
        assign_par(&mut self.built_x, x);
        self.built_walls = plates.iter().map(|p| p.displacement()).collect();
        let n = self.all_x.len();
        let rho0 = self.p.eos.rho0;
        self.all_v.resize(n, Vector::zeros());
        self.all_rho.resize(n, rho0);
        self.all_rho[nf..].fill(rho0);
        self.all_sigma.resize(n, Tensor::zeros());
        self.all_art.resize(n, Tensor::zeros());
        self.all_hess.resize(n, Tensor::zeros());
        // Virtual particles carry the viscosity of a fluid at rest (read by the Laplacian only,
        // that is with EVSS, which acts only on elastic models, whose solvent viscosity does not
        // depend on the shear rate).
        let mu = self
            .evss
            .viscous_viscosity(self.model.solvent_viscosity(&Tensor::<N>::zeros()));
        self.all_mu.resize(n, mu);
        self.all_mu[nf..].fill(mu);
        self.prof.lap(t, "neighbours: work arrays", false);
    }

    /// Fluid neighbours (and virtual ones, index >= number of fluid particles) of fluid particle
    /// `i` as of the last rebuild, ascending; a superset of those inside the support.
    #[inline]
    pub fn neighbors_of(&self, i: usize) -> &[u32] {
        self.nlist.of(i)
    }

    /// Hessian sums of the virtual particles (Ren eq. 20b), from `vlist`.
    fn virtual_hessians(&mut self, nf: usize) {
        if !self.art.needs_hessian() || self.all_x.len() == nf {
            return;
        }
        let (kernel, ax, vlist, dom) = (&self.kernel, &self.all_x, &self.vlist, &self.p.domain);
        let r2max = kernel.radius().powi(2);
        self.all_hess[nf..]
            .par_iter_mut()
            .with_min_len(MIN_TASK)
            .enumerate()
            .for_each(|(k, h)| {
                let xi = ax[nf + k];
                let mut sum = Tensor::zeros();
                for &j in vlist.of(k) {
                    let ju = j as usize;
                    if ju == nf + k {
                        continue;
                    }
                    let xij = dom.delta(&xi, &ax[ju]);
                    let r2 = xij.norm_squared();
                    if r2 < r2max {
                        sum += artificial::kernel_hessian(kernel, &xij, r2);
                    }
                }
                *h = sum;
            });
    }

    /// One rate evaluation at fluid state `fl` with the walls `plates`: fills kappa, drho, acc
    /// (and the wall part).
    pub fn rates(&mut self, fl: &Fluid<N>, plates: &[Wall<N>]) -> StageReport<N> {
        let nf = fl.len();
        let t = self.prof.start();
        copy_par(&mut self.all_x[..nf], &fl.x);
        for (((wall, plate), range), built) in self
            .walls
            .iter()
            .zip(plates)
            .zip(&self.wall_ranges)
            .zip(&self.built_walls)
        {
            if plate.displacement() != *built {
                // A moving plate: its virtual particles follow it at every evaluation, not only
                // when the lists are rebuilt (the lists, built with a skin, stay valid until it
                // has moved half the skin).
                self.all_x[range.clone()].copy_from_slice(&wall.positions(plate));
            }
        }
        copy_par(&mut self.all_v[..nf], &fl.v);
        copy_par(&mut self.all_rho[..nf], &fl.rho);
        // Virtual particles keep rho0 (their volumes are set anew here: a rebuild may have
        // moved them to other indices), fluid volumes follow the densities.
        let mass = fl.mass;
        self.all_vol.resize(self.all_rho.len(), 0.0);
        self.all_vol[nf..].fill(mass / self.p.eos.rho0);
        self.all_vol[..nf]
            .par_iter_mut()
            .zip(fl.rho.par_iter())
            .with_min_len(MIN_TASK_LIGHT)
            .for_each(|(v, r)| *v = mass / r);
        let t = self.prof.lap(t, "rates: fluid to work arrays", false);
        self.cont_v.resize(self.all_v.len() - nf, Vector::zeros());
        for ((wall, plate), range) in self.walls.iter().zip(plates).zip(&self.wall_ranges) {
            wall.fill_velocities(plate, fl, &mut self.all_v[range.clone()]);
            let cont = &mut self.cont_v[range.start - nf..range.end - nf];
            if wall.continuity_at_wall_velocity() {
                cont.fill(plate.wall_velocity());
            } else {
                cont.copy_from_slice(&self.all_v[range.clone()]);
            }
        }
        let t = self.prof.lap(t, "rates: walls' velocities", true);
        self.virtual_hessians(nf);
        if R::ELASTIC {
            let model = &self.model;
            self.tau_p.resize(nf, Tensor::zeros());
            self.tau_p
                .par_iter_mut()
                .zip(fl.conf.par_iter())
                .with_min_len(MIN_TASK_LIGHT)
                .for_each(|(t, a)| *t = model.polymer_stress(a));
        }
        let t = self
            .prof
            .lap(t, "rates: wall Hessians, polymer stress", false);
        Const::<N>::pass1(self, fl);
        let t = self.prof.lap(t, "pass 1", false);
        if R::ELASTIC && self.evss.is_on() {
            let evss = self.evss;
            self.tau_p
                .par_iter_mut()
                .zip(self.kappa.par_iter())
                .with_min_len(MIN_TASK_LIGHT)
                .for_each(|(t, k)| *t = stress::evss_elastic_part(&evss, t, k));
        }
        {
            let (fsig, vsig) = self.all_sigma.split_at_mut(nf);
            for ((wall, plate), range) in self.walls.iter().zip(plates).zip(&self.wall_ranges) {
                let out = &mut vsig[range.start - nf..range.end - nf];
                wall.fill_stresses(plate, fl, fsig, &self.tau_p, out);
            }
        }
        let t = self.prof.lap(t, "rates: wall stresses", true);
        {
            let (art, rho0) = (&self.art, self.p.eos.rho0);
            let (vsig, vhess) = (&self.all_sigma[nf..], &self.all_hess[nf..]);
            self.all_art[nf..]
                .par_iter_mut()
                .with_min_len(MIN_TASK)
                .enumerate()
                .for_each(|(k, a)| *a = art.of_particle(&vsig[k], rho0, &vhess[k]));
        }
        Const::<N>::pass2(self, fl);
        let t = self.prof.lap(t, "pass 2", false);
        let report = self.stage_report(fl.mass);
        self.prof.lap(t, "rates: wall force sum, max |a|", true);
        report
    }

    /// The time-step limits of Fang 2006 eqs. (51)-(53), each times `factor`: sound (with the
    /// fastest particle's speed added when `with_flow_speed`), force and viscous diffusion, plus
    /// the relaxation time for the explicit conformation update. The viscous limit counts the
    /// EVSS added viscosity, which the Laplacian carries on top of the physical one.
    pub fn stable_dt(
        &self,
        fl: &Fluid<N>,
        report: &StageReport<N>,
        factor: f64,
        with_flow_speed: bool,
    ) -> f64 {
        let h = self.kernel.h();
        let vmax = if with_flow_speed {
            // The largest squared speed, one square root: sqrt is correctly rounded and
            // monotone, so this is bitwise the largest of the norms, without a root per particle.
            // The largest of a set does not depend on the order it is taken in: in parallel.
            fl.v.par_iter()
                .with_min_len(MIN_TASK_LIGHT)
                .map(|v| v.norm_squared())
                .reduce(|| 0.0f64, f64::max)
                .sqrt()
        } else {
            0.0
        };
        let nu = (self.model.max_viscosity() + self.evss.added_viscosity()) / self.p.eos.rho0;
        let mut dt = h / (self.p.eos.c + vmax); // eq. (51)
        if report.max_acc > 0.0 {
            dt = dt.min((h / report.max_acc).sqrt()); // eq. (52)
        }
        dt = dt.min(0.5 * h * h / nu); // eq. (53)
        dt *= factor;
        if R::ELASTIC {
            dt = dt.min(factor * self.model.relaxation_time());
        }
        dt
    }

    /// One explicit update `out = base + dt * rates` of every evolved field, with the rates of
    /// the last [`WcCore::rates`] call: positions with the velocities `vel`, velocities with the
    /// accelerations, densities with the continuity rates, and the conformation tensor by
    /// [`rheology::advance`] from `base` with the rate evaluated at `conf_eval` and the last
    /// velocity gradients.
    ///
    /// Both predictor-correctors are made of such updates: Fang's (eqs. 49-50) is
    /// `X^{n+1/2} = X^n + dt/2 F(X^n)`, `X^{n+1} = X^n + dt F(X^{n+1/2})`; Ren's (eqs. 25a-25b,
    /// see [`super::pdri`]) is `X~ = X^n + dt G(X^n)`, `X^{n+1} = (X^n + dt/2 G(X^n)) + dt/2 G(X~)`.
    pub fn update(
        &self,
        out: &mut Fluid<N>,
        base: &Fluid<N>,
        vel: &[Vector<N>],
        conf_eval: &[Tensor<N>],
        dt: f64,
    ) {
        out.mass = base.mass;
        add_scaled(&mut out.x, &base.x, vel, dt);
        if self.p.domain.is_periodic() {
            let dom = self.p.domain;
            out.x
                .par_iter_mut()
                .with_min_len(MIN_TASK_LIGHT)
                .for_each(|x| *x = dom.wrap(*x));
        }
        add_scaled(&mut out.v, &base.v, &self.acc, dt);
        add_scaled(&mut out.rho, &base.rho, &self.drho, dt);
        out.conf.clear();
        if R::ELASTIC {
            let (model, method) = (&self.model, self.p.method);
            out.conf.par_extend(
                base.conf
                    .par_iter()
                    .zip(conf_eval.par_iter().zip(self.kappa.par_iter()))
                    .with_min_len(MIN_TASK)
                    .map(|(a, (e, k))| rheology::advance(method, model, a, e, k, dt)),
            );
        }
    }

    /// The report of a rate evaluation whose pass 2 has filled the accelerations, particles of
    /// mass `mass`: the largest squared acceleration on all threads (a maximum does not depend
    /// on the order), then one square root (bitwise the largest norm, sqrt being correctly
    /// rounded and monotone); the wall force summed in index order on one thread (a sum's
    /// rounding depends on its order; two additions per particle).
    fn stage_report(&self, mass: f64) -> StageReport<N> {
        let max_acc = self
            .acc
            .par_iter()
            .with_min_len(MIN_TASK_LIGHT)
            .map(|a| a.norm_squared())
            .reduce(|| 0.0f64, f64::max);
        let mut report = StageReport {
            max_acc: max_acc.sqrt(),
            ..Default::default()
        };
        for aw in &self.wall_acc {
            report.wall_on_fluid += aw * mass;
        }
        report
    }

    /// Positions of the virtual particles of the walls `plates`.
    pub fn wall_positions(&self, plates: &[Wall<N>]) -> Vec<Vector<N>> {
        self.walls
            .iter()
            .zip(plates)
            .flat_map(|(w, p)| w.positions(p))
            .collect()
    }
}

/// `out = base + rate * dt`, element by element, in parallel.
fn add_scaled<T>(out: &mut Vec<T>, base: &[T], rate: &[T], dt: f64)
where
    T: Copy + Send + Sync + std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>,
{
    out.clear();
    out.par_extend(
        base.par_iter()
            .zip(rate.par_iter())
            .with_min_len(MIN_TASK_LIGHT)
            .map(|(&b, &r)| b + r * dt),
    );
}

/// A square lattice block of n x n particles at spacing `dx` from the origin, with density
/// `rho(x)`, velocity `v(x)` and the conformation tensor at rest (for unit tests).
#[cfg(test)]
pub(crate) fn lattice_block(
    n: i64,
    dx: f64,
    rho: impl Fn(Vec2) -> f64,
    v: impl Fn(Vec2) -> Vec2,
) -> Fluid {
    let mut f = Fluid {
        mass: 1000.0 * dx * dx,
        ..Default::default()
    };
    for j in 0..n {
        for i in 0..n {
            let x = Vec2::new(i as f64 * dx, j as f64 * dx);
            f.x.push(x);
            f.v.push(v(x));
            f.rho.push(rho(x));
            f.conf.push(Mat2::identity());
        }
    }
    f
}

mod particle;
mod passes;
mod space;

use particle::{book_particle, particle_stress};

pub use space::WcSpace;

#[cfg(test)]
mod tests;
