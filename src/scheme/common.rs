//! What the weakly compressible schemes share: the constants resolved from the configuration,
//! the neighbour structures, the virtual wall particles and the rate evaluation (continuity,
//! velocity gradient, stresses, momentum), the integration helpers and the health check.
//!
//! Fang 2006 WCSPH ([`super::wcsph`]) and Ren 2015 PDRI-SPH ([`super::pdri`]) discretise the same
//! equations the same way (Fang eqs. 23, 26, 27 are Ren eqs. 15, 13, 14; the artificial viscosity
//! Fang eqs. 30-37 is Ren eq. 19): they differ in the wall model, the artificial stress, the time
//! integration and the periodic density reinitialisation. The first two are values of
//! [`WallModel`] and [`ArtificialStress`] held by one [`Core`]; the last two live in the schemes.
//!
//! One rate evaluation ([`Core::rates`]) runs:
//! 1. virtual velocities: wall particles at rest, image/ghost velocities extrapolated from the
//!    interior point P (Fang eq. 47, Ren eq. 23b);
//! 2. fluid pass 1 (a gather): velocity gradient, continuity, pressure from the equation of state,
//!    the stress sigma = -p I + viscous + polymer, the kernel values of every pair (cached for
//!    pass 2) and, for Ren's artificial stress, the sum of kernel Hessians;
//! 3. virtual stresses: the wall particle's by interpolation of the fluid's (Fang eq. 46 or Ren
//!    eq. 23a), image/ghost stresses extrapolated (Fang eq. 48, Ren eq. 23b);
//! 4. fluid pass 2 (a gather over the cached pairs): momentum with artificial viscosity and
//!    artificial stress, plus Morris' viscous Laplacian when EVSS is on; the part exerted by
//!    virtual particles is the wall force.
//!
//! Every pass is a gather over ascending neighbour indices, so results are bitwise independent of
//! the thread count.
//!
//! **EVSS** (King & Lind eqs. 6-8, `evss_alpha` > 0). With Fang's nested summation the solvent
//! stress goes through the same first-derivative operator as the polymer stress, and the split
//! Phi + (beta + alpha_V) eta0 2D = tau_p + beta eta0 2D would be an identity. So with EVSS on,
//! the viscous part (solvent + added) goes through Morris' Laplacian instead, and the
//! first-derivative operator sees Phi. Weakly compressible flow has div(2D) = lap v + grad div v
//! where King & Lind's incompressible scheme has lap v, so what the Laplacian lacks stays with the
//! first-derivative operator (see pass 1); a unit test checks that the split leaves the viscous
//! force of smooth flows, sheared or compressed, unchanged to 0.6 %. The two operators still
//! differ in the dissipation they add at the particle scale (King & Lind section IV.A: the nested
//! one reaches neighbours of neighbours). Measured on Fang's UCM drop (beta = 0, lambda = 0.02 s,
//! 316 to 1976 particles): it runs to t* = 8 without EVSS and with evss_alpha = 0.01 or 0.1 (King
//! & Lind's values), but evss_alpha >= 0.5 orders the particles into chains that the void-fraction
//! check reports as fracture by t* = 2, under both schemes and both artificial stresses.

use super::artificial;
use crate::boundary::plate::{Plate, IMAGE_ROWS, PER_COLUMN};
use crate::config::{ArtificialStressKind, ConformationMethod, EquationOfState, SceneConfig};
use crate::kernel::Kernel;
use crate::neighbors::{CellGrid, NeighborList};
use crate::particles::Fluid;
use crate::rheology::{self, Evss, Rheology};
use crate::{Mat2, Vec2};
use rayon::prelude::*;

/// Neighbour-list skin as a fraction of h.
const SKIN: f64 = 0.25;
/// A particle this far below the plate (in particle spacings) has gone through it.
const PENETRATION_DEPTH: f64 = 0.5;
/// Relative density deviation that stops a run.
const MAX_DENSITY_DEVIATION: f64 = 0.3;
/// Smallest number of particles (or wall columns) per parallel task: below it the work of a task
/// costs less than handing it to another thread. Light passes (a few flops per particle) take
/// many more.
const MIN_TASK: usize = 64;
const MIN_TASK_LIGHT: usize = 1024;
/// Morris' regularisation of the viscous Laplacian, eta^2 = 0.01 h^2 (Morris, Fox & Zhu 1997).
const MORRIS_ETA2: f64 = 0.01;

/// Constants of the schemes, resolved once from the configuration.
#[derive(Debug, Clone)]
pub struct Params {
    pub rho0: f64,
    pub c: f64,
    pub alpha: f64,
    pub beta: f64,
    /// Which artificial stress, and its coefficient (Fang's epsilon or Ren's b).
    pub art_kind: ArtificialStressKind,
    pub art_coef: f64,
    pub gravity: Vec2,
    pub eos: EquationOfState,
    pub dt_factor: f64,
    pub method: ConformationMethod,
    /// EVSS alpha_V / (1 - beta) (King & Lind eqs. 6-8); 0 = off.
    pub evss_alpha: f64,
    /// PDRI: steps between density reinitialisations (0 = never).
    pub reinit_interval: u64,
    /// Void fraction beyond which the fluid counts as torn (0 = never check).
    pub fracture_void_fraction: f64,
    pub dx: f64,
    /// Largest distance from the origin a particle may reach.
    pub domain_radius: f64,
}

impl Params {
    pub fn from_config(cfg: &SceneConfig) -> Self {
        let dx = cfg.dx();
        Self {
            rho0: cfg.density,
            c: cfg.sound_speed,
            alpha: cfg.artificial_viscosity_alpha,
            beta: cfg.artificial_viscosity_beta,
            art_kind: cfg.artificial_stress_kind,
            art_coef: match cfg.artificial_stress_kind {
                ArtificialStressKind::Fang => cfg.artificial_stress_epsilon,
                ArtificialStressKind::Ren => cfg.artificial_stress_b,
            },
            gravity: Vec2::new(0.0, -cfg.gravity),
            eos: cfg.equation_of_state,
            dt_factor: cfg.time_step_factor,
            method: cfg.conformation_method,
            evss_alpha: cfg.evss_alpha,
            reinit_interval: cfg.density_reinit_interval.max(0) as u64,
            fracture_void_fraction: cfg.fracture_void_fraction,
            dx,
            domain_radius: 1000.0 * cfg.drop_diameter + 10.0 * cfg.drop_height,
        }
    }

    /// Pressure from density: Fang 2006 eq. (10), p = c^2 (rho - rho0), or Tait's equation
    /// p = rho0 c^2 / 7 ((rho/rho0)^7 - 1) (Monaghan 1994, which Ren 2015 section 4.1 follows).
    ///
    /// Ren 2015 eq. (8) as printed, p = c^2 rho^2 / (2 rho0), has the same sound speed at rho0 but
    /// a background pressure c^2 rho0 / 2 there (9.8e8 Pa for the elliptical drop's c = 1400 m/s)
    /// that the symmetric momentum form (eq. 14) turns into an outward push on every free-surface
    /// particle; it contradicts Ren's own zero-pressure free-surface condition (section 3.5), so
    /// the 'tait' choice stands for Ren's stiff equation of state.
    #[inline]
    pub fn pressure(&self, rho: f64) -> f64 {
        match self.eos {
            EquationOfState::Linear => self.c * self.c * (rho - self.rho0),
            EquationOfState::Tait => {
                self.rho0 * self.c * self.c / 7.0 * ((rho / self.rho0).powi(7) - 1.0)
            }
        }
    }

    /// The density at which [`Params::pressure`] gives `p` (inverse equation of state), for
    /// scenes that start with a pressure field.
    pub fn density_for_pressure(&self, p: f64) -> f64 {
        match self.eos {
            EquationOfState::Linear => self.rho0 + p / (self.c * self.c),
            EquationOfState::Tait => {
                self.rho0 * (1.0 + 7.0 * p / (self.rho0 * self.c * self.c)).powf(1.0 / 7.0)
            }
        }
    }
}

/// Intervals of the table of Ren's f^n over r in [0, 2h].
const REN_TABLE: usize = 4096;

/// The artificial stress against the tensile instability, resolved once: Fang 2006 eqs. (38)-(44)
/// or Ren 2015 eqs. (20a)-(20b). Both add f_ij^n (R_i + R_j) to the pair term of the momentum
/// equation with f_ij = W_ij / W(d0) (Fang eq. 39, Ren eq. 20a); they differ in R and in n.
///
/// Fang's n = 4 costs two multiplications. Ren's n = W(0)/W(d0) (1.8 for h = 1.5 d0) is not an
/// integer, and `powf` on every pair took a fifth of a PDRI step; f^n depends on r only, so it is
/// tabulated over r and interpolated linearly (error below 5e-7; f^n is 1 at r = d0).
/// (Over r^2 it would save the square root, but W is not smooth in r^2 at r = 0.)
#[derive(Debug, Clone)]
pub struct ArtificialStress {
    kind: ArtificialStressKind,
    /// Fang's epsilon or Ren's b.
    coef: f64,
    /// The exponent n: 4 for Fang (section 3.2), W(0)/W(d0) for Ren (eq. 20a).
    n: f64,
    /// 1 / W(d0).
    inv_w_d0: f64,
    /// Ren: f^n at r = k 2h / REN_TABLE, k = 0..=REN_TABLE, and the index scale.
    table: Vec<f64>,
    per_r: f64,
}

impl ArtificialStress {
    pub fn new<K: Kernel>(kernel: &K, p: &Params) -> Self {
        let w_d0 = kernel.w(p.dx);
        let n = match p.art_kind {
            ArtificialStressKind::Fang => 4.0,
            ArtificialStressKind::Ren => kernel.w(0.0) / w_d0,
        };
        let radius = kernel.radius();
        let table = if p.art_kind == ArtificialStressKind::Ren {
            (0..=REN_TABLE)
                .map(|k| (kernel.w(radius * k as f64 / REN_TABLE as f64) / w_d0).powf(n))
                .collect()
        } else {
            Vec::new()
        };
        Self {
            kind: p.art_kind,
            coef: p.art_coef,
            n,
            inv_w_d0: 1.0 / w_d0,
            table,
            per_r: REN_TABLE as f64 / radius,
        }
    }

    /// Whether the term is there at all.
    #[inline]
    pub fn is_on(&self) -> bool {
        self.coef > 0.0
    }

    /// Whether R needs the sum of kernel Hessians over the neighbours (Ren eq. 20b).
    #[inline]
    pub fn needs_hessian(&self) -> bool {
        self.is_on() && self.kind == ArtificialStressKind::Ren
    }

    /// The exponent n.
    pub fn exponent(&self) -> f64 {
        self.n
    }

    /// R of one particle from its total stress, density and (Ren) Hessian sum.
    #[inline]
    pub fn of_particle(&self, sigma: &Mat2, rho: f64, hess: &Mat2) -> Mat2 {
        match self.kind {
            ArtificialStressKind::Fang => artificial::fang_stress(self.coef, sigma, rho),
            ArtificialStressKind::Ren => artificial::ren_stress(self.coef, sigma, rho, hess),
        }
    }

    /// f_ij^n for a pair with kernel value `w` at squared distance `r2` (inside the support).
    #[inline]
    pub fn pair_factor(&self, w: f64, r2: f64) -> f64 {
        match self.kind {
            ArtificialStressKind::Fang => {
                let f = w * self.inv_w_d0;
                let f2 = f * f;
                f2 * f2
            }
            ArtificialStressKind::Ren => {
                let x = r2.sqrt() * self.per_r;
                let k = (x as usize).min(REN_TABLE - 1);
                let t = x - k as f64;
                self.table[k] + (self.table[k + 1] - self.table[k]) * t
            }
        }
    }
}

/// How the virtual particles of a plate take their values from the fluid.
///
/// Both papers put one row of particles on the wall and image/ghost rows below it, at rest and at
/// the reference density; a column's wall particle and its interior point P (Fang) or F (Ren) at
/// d = d0 take values interpolated from nearby fluid particles, and the particles below the wall
/// extrapolate linearly, L_G = L_F + (1 + d_G/d_F)(L_W - L_F) (Fang eqs. 47-48, Ren eq. 23b),
/// for the velocity (L_W = 0, no slip) and the stress (L_W from the wall particle). They differ in
/// the interpolation weights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallModel {
    /// Fang 2006 eq. (46): normalised SPH interpolation, weights (m_j/rho_j) W_ij.
    Fang,
    /// Ren 2015 eq. (23a): weights 2h - r_ij.
    Ren,
}

impl WallModel {
    /// Normalised interpolation weights of the fluid neighbours of point `q` (fluid particles
    /// only, as both papers say): calls `f(j, w_j)` with sum_j w_j = 1, and returns false when no
    /// fluid is within reach.
    #[inline]
    pub fn interpolate<K: Kernel>(
        self,
        kernel: &K,
        fluid: &Fluid,
        list: &[u32],
        q: &Vec2,
        mut f: impl FnMut(usize, f64),
    ) -> bool {
        let radius = kernel.radius();
        let r2max = radius * radius;
        let weight = |j: usize, r2: f64| match self {
            WallModel::Fang => fluid.mass / fluid.rho[j] * kernel.w(r2.sqrt()),
            WallModel::Ren => radius - r2.sqrt(),
        };
        let mut den = 0.0;
        for &j in list {
            let j = j as usize;
            let r2 = (fluid.x[j] - q).norm_squared();
            if r2 < r2max {
                den += weight(j, r2);
            }
        }
        if den <= 0.0 {
            return false;
        }
        let inv = 1.0 / den;
        for &j in list {
            let j = j as usize;
            let r2 = (fluid.x[j] - q).norm_squared();
            if r2 < r2max {
                f(j, weight(j, r2) * inv);
            }
        }
        true
    }
}

/// Extrapolation factor 1 + d_I/d_P of image/ghost row m (d_I = m dx, d_P = dx; Fang eqs. 47-48,
/// Ren eq. 23b with d_F = d0).
#[inline]
fn image_factor(row: usize) -> f64 {
    1.0 + row as f64
}

/// What one rate evaluation reports besides the per-particle rates.
#[derive(Debug, Clone, Copy, Default)]
pub struct StageReport {
    /// Force of the virtual (wall) particles on the fluid \[N/m\].
    pub wall_on_fluid: Vec2,
    /// Largest acceleration magnitude.
    pub max_acc: f64,
}

/// The shared machinery of the weakly compressible schemes for kernel `K` and rheology `R`:
/// neighbour lists, virtual particles, work arrays and the rate evaluation.
pub struct Core<K: Kernel, R: Rheology> {
    pub kernel: K,
    pub model: R,
    pub p: Params,
    art: ArtificialStress,
    walls: WallModel,
    evss: Evss,
    // Neighbour structures, rebuilt when particles have moved more than half the skin.
    built_x: Vec<Vec2>,
    /// Neighbours (fluid and virtual) of every fluid particle.
    nlist: NeighborList,
    /// Neighbours of every virtual particle (only for Ren's artificial stress).
    vlist: NeighborList,
    /// Fluid neighbours of each column's wall particle (2c) and interior point P (2c+1).
    clist: NeighborList,
    plate: Option<Plate>,
    // Work arrays over all particles (fluid first, then virtual).
    all_x: Vec<Vec2>,
    all_v: Vec<Vec2>,
    all_rho: Vec<f64>,
    all_sigma: Vec<Mat2>,
    all_art: Vec<Mat2>,
    /// Sum over neighbours of the kernel Hessian (Ren eq. 20b), when needed.
    all_hess: Vec<Mat2>,
    /// Viscosity of the Laplacian viscous term (read with EVSS only).
    all_mu: Vec<f64>,
    /// m / rho of every particle.
    all_vol: Vec<f64>,
    /// sigma / rho^2 of every particle (Fang 2006 eq. 27).
    all_sr2: Vec<Mat2>,
    // Kernel values of the pairs inside the support, aligned with `nlist` (SPHinXsys's habit of
    // caching W and grad W once per stage): neighbour index, grad_i W_ij, W_ij; `pair_len[i]` of
    // particle i's slots are used.
    pair_j: Vec<u32>,
    pair_grad: Vec<Vec2>,
    pair_w: Vec<f64>,
    pair_len: Vec<u32>,
    /// Polymer stress of fluid particles (empty for inelastic models); from pass 1 on, with EVSS,
    /// the elastic stress as it enters sigma (Phi and its trace term), which is what the wall's
    /// zero-normal-elastic-stress condition removes.
    tau_p: Vec<Mat2>,
    // Fluid rates of the last evaluation.
    pub kappa: Vec<Mat2>,
    pub drho: Vec<f64>,
    pub acc: Vec<Vec2>,
    wall_acc: Vec<Vec2>,
}

impl<K: Kernel, R: Rheology> Core<K, R> {
    pub fn new(kernel: K, model: R, p: Params, plate: Option<Plate>, walls: WallModel) -> Self {
        let art = ArtificialStress::new(&kernel, &p);
        let evss = Evss::new(&model, p.evss_alpha);
        Self {
            kernel,
            model,
            p,
            art,
            walls,
            evss,
            built_x: Vec::new(),
            nlist: NeighborList::default(),
            vlist: NeighborList::default(),
            clist: NeighborList::default(),
            plate,
            all_x: Vec::new(),
            all_v: Vec::new(),
            all_rho: Vec::new(),
            all_sigma: Vec::new(),
            all_art: Vec::new(),
            all_hess: Vec::new(),
            all_mu: Vec::new(),
            all_vol: Vec::new(),
            all_sr2: Vec::new(),
            pair_j: Vec::new(),
            pair_grad: Vec::new(),
            pair_w: Vec::new(),
            pair_len: Vec::new(),
            tau_p: Vec::new(),
            kappa: Vec::new(),
            drho: Vec::new(),
            acc: Vec::new(),
            wall_acc: Vec::new(),
        }
    }

    fn search_radius(&self) -> f64 {
        self.kernel.radius() + SKIN * self.kernel.h()
    }

    /// Rebuild the neighbour lists (and grow the plate) if any particle moved more than half the
    /// skin since the last build.
    pub fn refresh_neighbors(&mut self, x: &[Vec2], st_plate: &mut Option<Plate>) {
        let half_skin2 = (0.5 * SKIN * self.kernel.h()).powi(2);
        let stale = self.built_x.len() != x.len()
            || x.par_iter()
                .zip(self.built_x.par_iter())
                .with_min_len(MIN_TASK_LIGHT)
                .any(|(a, b)| (a - b).norm_squared() > half_skin2);
        if !stale {
            return;
        }
        let radius = self.search_radius();
        if let Some(plate) = st_plate.as_mut() {
            let (lo, hi) = x
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    let s = plate.s(p);
                    (lo.min(s), hi.max(s))
                });
            if lo.is_finite() {
                plate.cover(lo - 3.0 * radius, hi + 3.0 * radius);
            }
            self.plate = Some(plate.clone());
        }
        let nf = x.len();
        self.all_x.clear();
        self.all_x.extend_from_slice(x);
        let mut queries = Vec::new();
        if let Some(plate) = &self.plate {
            self.all_x.extend(plate.virtual_positions());
            for c in 0..plate.columns() {
                queries.push(plate.point(plate.column_s(c), 0.0));
                queries.push(plate.interior_point(c));
            }
        }
        let grid = CellGrid::build(&self.all_x, radius);
        self.nlist = NeighborList::build(&grid, &self.all_x, x, radius);
        self.vlist = if self.art.needs_hessian() {
            NeighborList::build(&grid, &self.all_x, &self.all_x[nf..], radius)
        } else {
            NeighborList::default()
        };
        // Columns see fluid only.
        let fluid_grid = CellGrid::build(x, radius);
        self.clist = NeighborList::build(&fluid_grid, x, &queries, radius);
        self.built_x = x.to_vec();
        let n = self.all_x.len();
        self.all_v.resize(n, Vec2::zeros());
        self.all_rho.resize(n, self.p.rho0);
        self.all_rho[nf..].fill(self.p.rho0);
        self.all_vol.clear();
        self.all_sigma.resize(n, Mat2::zeros());
        self.all_art.resize(n, Mat2::zeros());
        self.all_hess.resize(n, Mat2::zeros());
        // Virtual particles carry the viscosity of a fluid at rest (read by the Laplacian only,
        // that is with EVSS, which acts only on elastic models, whose solvent viscosity does not
        // depend on the shear rate).
        let mu = self
            .evss
            .viscous_viscosity(self.model.solvent_viscosity(&Mat2::zeros()));
        self.all_mu.resize(n, mu);
        self.all_mu[nf..].fill(mu);
    }

    /// Fluid neighbours (and virtual ones, index >= number of fluid particles) of fluid particle
    /// `i` as of the last rebuild, ascending; a superset of those inside the support.
    #[inline]
    pub fn neighbors_of(&self, i: usize) -> &[u32] {
        self.nlist.of(i)
    }

    /// Step 1: virtual velocities.
    fn virtual_velocities(&mut self, fluid: &Fluid) {
        let Some(plate) = &self.plate else { return };
        let nf = fluid.len();
        let (kernel, clist, walls) = (&self.kernel, &self.clist, self.walls);
        self.all_v[nf..]
            .par_chunks_mut(PER_COLUMN)
            .with_min_len(MIN_TASK / 4)
            .enumerate()
            .for_each(|(c, out)| {
                let q = plate.interior_point(c);
                let mut vp = Vec2::zeros();
                walls.interpolate(kernel, fluid, clist.of(2 * c + 1), &q, |j, w| {
                    vp += fluid.v[j] * w
                });
                out[0] = Vec2::zeros(); // the wall particle moves with the (fixed) wall
                for (row, o) in out.iter_mut().enumerate().skip(1) {
                    // Fang eq. (47), Ren eq. (23b), with v_W = 0
                    *o = vp - vp * image_factor(row);
                }
            });
    }

    /// Step 3: virtual stresses and their artificial stresses.
    fn virtual_stresses(&mut self, fluid: &Fluid) {
        let Some(plate) = &self.plate else { return };
        let nf = fluid.len();
        let n = plate.n;
        let nn = n * n.transpose();
        let (kernel, clist, rho0, walls, art) = (
            &self.kernel,
            &self.clist,
            self.p.rho0,
            self.walls,
            &self.art,
        );
        let (fsig, vsig) = self.all_sigma.split_at_mut(nf);
        let fsig = &*fsig;
        let tau_p = &self.tau_p;
        let vhess = &self.all_hess[nf..];
        let vart = &mut self.all_art[nf..];
        vsig.par_chunks_mut(PER_COLUMN)
            .zip(vart.par_chunks_mut(PER_COLUMN))
            .zip(vhess.par_chunks(PER_COLUMN))
            .with_min_len(MIN_TASK / 4)
            .enumerate()
            .for_each(|(c, ((sig, art_out), hess))| {
                let qb = plate.point(plate.column_s(c), 0.0);
                let mut sb = Mat2::zeros();
                let mut snn = 0.0;
                walls.interpolate(kernel, fluid, clist.of(2 * c), &qb, |j, w| {
                    sb += fsig[j] * w;
                    if R::ELASTIC {
                        snn += n.dot(&(tau_p[j] * n)) * w;
                    }
                });
                // Fang 3.3: the wall-normal component of the elastic stress is zero on the wall
                // (Ren's Cross fluid has none; kept for elastic models under both wall models).
                sb -= nn * snn;
                let qp = plate.interior_point(c);
                let mut sp = Mat2::zeros();
                if !walls.interpolate(kernel, fluid, clist.of(2 * c + 1), &qp, |j, w| {
                    sp += fsig[j] * w
                }) {
                    sp = sb;
                }
                sig[0] = sb;
                for (row, s) in sig.iter_mut().enumerate().take(IMAGE_ROWS + 1).skip(1) {
                    *s = sp + (sb - sp) * image_factor(row); // Fang (48), Ren (23b)
                }
                for k in 0..PER_COLUMN {
                    art_out[k] = art.of_particle(&sig[k], rho0, &hess[k]);
                }
            });
    }

    /// Hessian sums of the virtual particles (Ren eq. 20b), from `vlist`.
    fn virtual_hessians(&mut self, nf: usize) {
        if !self.art.needs_hessian() || self.plate.is_none() {
            return;
        }
        let (kernel, ax, vlist) = (&self.kernel, &self.all_x, &self.vlist);
        let r2max = kernel.radius().powi(2);
        self.all_hess[nf..]
            .par_iter_mut()
            .with_min_len(MIN_TASK)
            .enumerate()
            .for_each(|(k, h)| {
                let xi = ax[nf + k];
                let mut sum = Mat2::zeros();
                for &j in vlist.of(k) {
                    let ju = j as usize;
                    if ju == nf + k {
                        continue;
                    }
                    let xij = xi - ax[ju];
                    let r2 = xij.norm_squared();
                    if r2 < r2max {
                        sum += artificial::kernel_hessian(kernel, &xij, r2);
                    }
                }
                *h = sum;
            });
    }

    /// One rate evaluation at fluid state `fl`: fills kappa, drho, acc (and the wall part).
    pub fn rates(&mut self, fl: &Fluid) -> StageReport {
        let nf = fl.len();
        let mass = fl.mass;
        self.all_x[..nf].copy_from_slice(&fl.x);
        self.all_v[..nf].copy_from_slice(&fl.v);
        self.all_rho[..nf].copy_from_slice(&fl.rho);
        // Virtual particles keep rho0, so only fluid volumes change.
        self.all_vol.resize(self.all_rho.len(), mass / self.p.rho0);
        for (v, r) in self.all_vol[..nf].iter_mut().zip(&fl.rho) {
            *v = mass / r;
        }
        self.virtual_velocities(fl);
        self.virtual_hessians(nf);
        if R::ELASTIC {
            let model = &self.model;
            self.tau_p.resize(nf, Mat2::zeros());
            self.tau_p
                .par_iter_mut()
                .zip(fl.conf.par_iter())
                .with_min_len(MIN_TASK_LIGHT)
                .for_each(|(t, a)| *t = model.polymer_stress(a));
        }

        // Pass 1 (a gather): velocity gradient (Fang eq. 23), continuity (eq. 26), stresses, and
        // the kernel values of every pair inside the support, cached for pass 2.
        let npairs = self.nlist.pairs();
        self.pair_j.resize(npairs, 0);
        self.pair_grad.resize(npairs, Vec2::zeros());
        self.pair_w.resize(npairs, 0.0);
        self.pair_len.resize(nf, 0);
        self.kappa.resize(nf, Mat2::zeros());
        self.drho.resize(nf, 0.0);
        {
            let (kernel, model, p, art, evss) =
                (&self.kernel, &self.model, &self.p, &self.art, self.evss);
            let (ax, av, avol, tau_p) = (&self.all_x, &self.all_v, &self.all_vol, &self.tau_p);
            let nlist = &self.nlist;
            let r2max = kernel.radius().powi(2);
            let need_hess = art.needs_hessian();
            let js = nlist.split_mut(&mut self.pair_j);
            let gs = nlist.split_mut(&mut self.pair_grad);
            let ws = nlist.split_mut(&mut self.pair_w);
            (
                js,
                gs,
                ws,
                &mut self.pair_len[..],
                &mut self.kappa[..],
                &mut self.drho[..],
                &mut self.all_sigma[..nf],
                &mut self.all_art[..nf],
                &mut self.all_hess[..nf],
                &mut self.all_mu[..nf],
            )
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .enumerate()
                .for_each(
                    |(i, (js, gs, ws, len, kappa_i, drho_i, sigma_i, art_i, hess_i, mu_i))| {
                        let (xi, vi) = (ax[i], av[i]);
                        let mut kappa = Mat2::zeros();
                        let mut drho = 0.0;
                        let mut hess = Mat2::zeros();
                        let mut k = 0;
                        for &j in nlist.of(i) {
                            let ju = j as usize;
                            if ju == i {
                                continue;
                            }
                            let xij = xi - ax[ju];
                            let r2 = xij.norm_squared();
                            if r2 >= r2max {
                                continue;
                            }
                            let r = r2.sqrt();
                            let (w, dw_r) = kernel.w_and_dw_over_r(r);
                            let grad = xij * dw_r;
                            js[k] = j;
                            gs[k] = grad;
                            ws[k] = w;
                            k += 1;
                            let vij = vi - av[ju];
                            kappa -= (vij * grad.transpose()) * avol[ju];
                            drho += vij.dot(&grad);
                            if need_hess {
                                hess += artificial::kernel_hessian(kernel, &xij, r2);
                            }
                        }
                        *len = k as u32;
                        *kappa_i = kappa;
                        *drho_i = drho * mass;
                        *hess_i = hess;
                        let eta = model.solvent_viscosity(&kappa);
                        let mut sigma = Mat2::identity() * (-p.pressure(fl.rho[i]));
                        *mu_i = evss.viscous_viscosity(eta);
                        if evss.is_on() {
                            // King & Lind eqs. (6)-(8), weakly compressible: the Laplacian of
                            // pass 2 carries (eta_s + alpha_V eta0) lap v, and since
                            // div(2D) = lap v + grad(div v) here, the first-derivative operator
                            // keeps what the Laplacian lacks: the solvent's eta_s (div v) I, and
                            // Phi with the added viscosity taken out of the deviatoric rate of
                            // strain only, tau_p - alpha_V eta0 (2D - (div v) I).
                            let div = kappa.trace();
                            sigma += Mat2::identity() * (eta * div);
                            if R::ELASTIC {
                                sigma += evss.phi(&tau_p[i], &kappa)
                                    + Mat2::identity() * (evss.added_viscosity() * div);
                            }
                        } else {
                            // Fang eq. (8), Ren eq. (16): eta (kappa + kappa^T) in the stress.
                            sigma += (kappa + kappa.transpose()) * eta;
                            if R::ELASTIC {
                                sigma += tau_p[i];
                            }
                        }
                        *sigma_i = sigma;
                        *art_i = art.of_particle(&sigma, fl.rho[i], &hess);
                    },
                );
        }
        if R::ELASTIC && self.evss.is_on() {
            let evss = self.evss;
            self.tau_p
                .par_iter_mut()
                .zip(self.kappa.par_iter())
                .with_min_len(MIN_TASK_LIGHT)
                .for_each(|(t, k)| {
                    *t = evss.phi(t, k) + Mat2::identity() * (evss.added_viscosity() * k.trace())
                });
        }
        self.virtual_stresses(fl);
        self.all_sr2.resize(self.all_sigma.len(), Mat2::zeros());
        self.all_sr2
            .par_iter_mut()
            .zip(self.all_sigma.par_iter().zip(self.all_rho.par_iter()))
            .with_min_len(MIN_TASK_LIGHT)
            .for_each(|(o, (sg, r))| *o = sg / (r * r));

        // Pass 2 (a gather over the cached pairs): momentum (Fang eq. 27, Ren eq. 21) with
        // artificial viscosity (Fang eqs. 30-37, Ren eq. 19) and artificial stress (Fang eq. 38,
        // Ren eq. 20a); with EVSS, Morris' viscous Laplacian.
        self.acc.resize(nf, Vec2::zeros());
        self.wall_acc.resize(nf, Vec2::zeros());
        {
            let p = &self.p;
            let (ax, av, arho, asr2, aart, amu) = (
                &self.all_x,
                &self.all_v,
                &self.all_rho,
                &self.all_sr2,
                &self.all_art,
                &self.all_mu,
            );
            let (pj, pg, pw, plen) = (&self.pair_j, &self.pair_grad, &self.pair_w, &self.pair_len);
            let nlist = &self.nlist;
            let h = self.kernel.h();
            let art = &self.art;
            let use_art = art.is_on();
            let morris = self.evss.is_on();
            let eta2 = MORRIS_ETA2 * h * h;
            (&mut self.acc[..], &mut self.wall_acc[..])
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .enumerate()
                .for_each(|(i, (acc_i, wall_i))| {
                    let (xi, vi, rhoi, si, ri) = (ax[i], av[i], arho[i], asr2[i], aart[i]);
                    let start = nlist.offset(i);
                    let end = start + plen[i] as usize;
                    let mut a = Vec2::zeros();
                    let mut aw = Vec2::zeros();
                    for k in start..end {
                        let j = pj[k] as usize;
                        let mut t = si + asr2[j];
                        let xij = xi - ax[j];
                        let vij = vi - av[j];
                        let r2 = xij.norm_squared();
                        let pi = artificial::viscosity(
                            p.alpha,
                            p.beta,
                            h,
                            p.c,
                            0.5 * (rhoi + arho[j]),
                            &vij,
                            &xij,
                            r2,
                        );
                        t[(0, 0)] -= pi;
                        t[(1, 1)] -= pi;
                        if use_art {
                            let rsum = ri + aart[j];
                            if rsum != Mat2::zeros() {
                                t += rsum * art.pair_factor(pw[k], r2);
                            }
                        }
                        let mut contrib = t * pg[k];
                        if morris {
                            // Morris, Fox & Zhu 1997: sum_j m_j (mu_i + mu_j) x_ij . grad W_ij
                            // / (rho_i rho_j (r^2 + 0.01 h^2)) v_ij.
                            contrib += vij
                                * ((amu[i] + amu[j]) * xij.dot(&pg[k])
                                    / (rhoi * arho[j] * (r2 + eta2)));
                        }
                        if j < nf {
                            a += contrib;
                        } else {
                            aw += contrib;
                        }
                    }
                    *wall_i = aw * mass;
                    *acc_i = (a + aw) * mass + p.gravity;
                });
        }
        // Sequential, fixed-order reductions.
        let mut report = StageReport::default();
        for (a, aw) in self.acc.iter().zip(&self.wall_acc) {
            report.max_acc = report.max_acc.max(a.norm());
            report.wall_on_fluid += aw * mass;
        }
        report
    }

    /// The time-step limits of Fang 2006 eqs. (51)-(53), each times `factor`: sound (with the
    /// fastest particle's speed added when `with_flow_speed`), force and viscous diffusion, plus
    /// the relaxation time for the explicit conformation update. The viscous limit counts the
    /// EVSS added viscosity, which the Laplacian carries on top of the physical one.
    pub fn stable_dt(
        &self,
        fl: &Fluid,
        report: &StageReport,
        factor: f64,
        with_flow_speed: bool,
    ) -> f64 {
        let h = self.kernel.h();
        let vmax = if with_flow_speed {
            fl.v.iter().fold(0.0f64, |m, v| m.max(v.norm()))
        } else {
            0.0
        };
        let nu = (self.model.max_viscosity() + self.evss.added_viscosity()) / self.p.rho0;
        let mut dt = h / (self.p.c + vmax); // eq. (51)
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

    /// Health of a state after a step: the void fraction, or the cause of a breakdown.
    pub fn check_health(&self, fl: &Fluid, plate: &Option<Plate>) -> Result<f64, String> {
        let p = &self.p;
        let bad = (0..fl.len())
            .into_par_iter()
            .with_min_len(MIN_TASK_LIGHT)
            .find_first(|&i| {
                !(fl.x[i].iter().all(|x| x.is_finite())
                    && fl.v[i].iter().all(|x| x.is_finite())
                    && fl.rho[i].is_finite()
                    && (!R::ELASTIC || fl.conf[i].iter().all(|x| x.is_finite())))
            });
        if let Some(i) = bad {
            return Err(format!(
                "non-finite value (NaN or Inf) on fluid particle {i}"
            ));
        }
        for i in 0..fl.len() {
            let dev = fl.rho[i] / p.rho0 - 1.0;
            if dev.abs() > MAX_DENSITY_DEVIATION {
                return Err(format!(
                    "density of particle {i} is {:.1} % off the reference density (limit {:.0} %): \
                     the flow is too fast for the sound speed",
                    100.0 * dev,
                    100.0 * MAX_DENSITY_DEVIATION
                ));
            }
            if fl.x[i].norm() > p.domain_radius {
                return Err(format!(
                    "particle {i} escaped the domain (|x| = {:.3e} m)",
                    fl.x[i].norm()
                ));
            }
            if let Some(pl) = plate {
                if pl.d(&fl.x[i]) < -PENETRATION_DEPTH * p.dx {
                    return Err(format!("particle {i} went through the plate"));
                }
            }
        }
        let voids = fluid_void_fraction(fl, plate, p.dx);
        if p.fracture_void_fraction > 0.0 && voids > p.fracture_void_fraction {
            let knob = match p.art_kind {
                ArtificialStressKind::Fang => "artificial_stress_epsilon",
                ArtificialStressKind::Ren => "artificial_stress_b",
            };
            return Err(format!(
                "fracture by the tensile instability: holes make up {:.1} % of the fluid's area \
                 (limit {:.1} %); raise {knob}",
                100.0 * voids,
                100.0 * p.fracture_void_fraction
            ));
        }
        Ok(voids)
    }

    /// One explicit update `out = base + dt * rates` of every evolved field, with the rates of
    /// the last [`Core::rates`] call: positions with the velocities `vel`, velocities with the
    /// accelerations, densities with the continuity rates, and the conformation tensor by
    /// [`rheology::advance`] from `base` with the rate evaluated at `conf_eval` and the last
    /// velocity gradients.
    ///
    /// Both predictor-correctors are made of such updates: Fang's (eqs. 49-50) is
    /// `X^{n+1/2} = X^n + dt/2 F(X^n)`, `X^{n+1} = X^n + dt F(X^{n+1/2})`; Ren's (eqs. 25a-25b,
    /// see [`super::pdri`]) is `X~ = X^n + dt G(X^n)`, `X^{n+1} = (X^n + dt/2 G(X^n)) + dt/2 G(X~)`.
    pub fn update(&self, out: &mut Fluid, base: &Fluid, vel: &[Vec2], conf_eval: &[Mat2], dt: f64) {
        out.mass = base.mass;
        add_scaled(&mut out.x, &base.x, vel, dt);
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

    /// Positions of the virtual particles currently built.
    pub fn wall_positions(&self) -> Vec<Vec2> {
        self.plate
            .as_ref()
            .map(|p| p.virtual_positions())
            .unwrap_or_default()
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

/// The plate's impenetrability, kinematically: a fluid particle found below the plate line
/// (d < 0) is mirrored back above it, and the part of its velocity that runs into the plate is
/// removed (an inelastic contact). Returns the momentum the plate gave the fluid this way
/// \[kg m/s per m\] and the number of particles put back. Sequential, in particle order, so the
/// sum is the same on any number of threads. Used by Fang's scheme (see [`super::wcsph`]).
pub fn keep_above_plate(fl: &mut Fluid, plate: &Option<Plate>) -> (Vec2, u64) {
    let Some(pl) = plate else {
        return (Vec2::zeros(), 0);
    };
    let mut momentum = Vec2::zeros();
    let mut count = 0;
    for (x, v) in fl.x.iter_mut().zip(fl.v.iter_mut()) {
        let d = pl.d(x);
        if d < 0.0 {
            *x -= pl.n * (2.0 * d);
            let vn = v.dot(&pl.n);
            if vn < 0.0 {
                *v -= pl.n * vn;
                momentum -= pl.n * (vn * fl.mass);
            }
            count += 1;
        }
    }
    (momentum, count)
}

/// Void fraction of the fluid (see [`crate::health`]) on cells of two particle spacings, in the
/// plate's frame when there is a plate.
pub fn fluid_void_fraction(fl: &Fluid, plate: &Option<Plate>, dx: f64) -> f64 {
    let pts: Vec<(f64, f64)> = match plate {
        Some(pl) => fl.x.iter().map(|x| (pl.s(x), pl.d(x))).collect(),
        None => fl.x.iter().map(|x| (x.x, x.y)).collect(),
    };
    crate::health::void_fraction(&pts, 2.0 * dx, plate.is_some())
}

/// Pressure roughness of a fluid state: the RMS over fluid particles of p_i minus its
/// SPH-smoothed value p~_i = sum_j V_j p_j W_ij / sum_j V_j W_ij (fluid neighbours, Shepard
/// normalised so a uniform field is smooth everywhere, the free surface included), divided by
/// `scale` \[Pa\]. It measures the particle-to-particle pressure noise that Ren 2015 Figs. 3 and 9
/// show and that periodic density reinitialisation removes.
pub fn pressure_roughness<K: Kernel>(fl: &Fluid, p: &Params, kernel: &K, scale: f64) -> f64 {
    let n = fl.len();
    if n == 0 {
        return 0.0;
    }
    let radius = kernel.radius();
    let grid = CellGrid::build(&fl.x, radius);
    let list = NeighborList::build(&grid, &fl.x, &fl.x, radius);
    let pres: Vec<f64> = fl.rho.iter().map(|&r| p.pressure(r)).collect();
    let dev2: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| {
            let (mut num, mut den) = (0.0, 0.0);
            for &j in list.of(i) {
                let j = j as usize;
                let w = fl.mass / fl.rho[j] * kernel.w((fl.x[i] - fl.x[j]).norm());
                num += w * pres[j];
                den += w;
            }
            let d = pres[i] - num / den;
            d * d
        })
        .collect();
    (dev2.iter().sum::<f64>() / n as f64).sqrt() / scale
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::CubicSpline;
    use crate::rheology::OldroydB;

    #[test]
    fn particles_below_the_plate_are_mirrored_and_stopped() {
        // A 30 degree plate; one particle above it, one below moving into it, one below moving
        // away from it.
        let plate = Some(Plate::new(30.0, 0.01));
        let pl = plate.as_ref().unwrap();
        let mut fl = Fluid {
            mass: 0.1,
            x: vec![
                pl.point(0.0, 0.004),
                pl.point(0.01, -0.003),
                pl.point(0.02, -0.001),
            ],
            v: vec![pl.t - pl.n, pl.t * 2.0 - pl.n * 3.0, pl.t + pl.n * 0.5],
            rho: vec![1000.0; 3],
            ..Default::default()
        };
        let before = fl.clone();
        let (momentum, count) = keep_above_plate(&mut fl, &plate);
        assert_eq!(count, 2);
        assert_eq!((fl.x[0], fl.v[0]), (before.x[0], before.v[0]));
        assert!((pl.d(&fl.x[1]) - 0.003).abs() < 1e-15 && (pl.s(&fl.x[1]) - 0.01).abs() < 1e-15);
        assert!((pl.d(&fl.x[2]) - 0.001).abs() < 1e-15);
        // Into the plate: the normal velocity is removed, the tangential one kept.
        assert!(fl.v[1].dot(&pl.n).abs() < 1e-15 && (fl.v[1].dot(&pl.t) - 2.0).abs() < 1e-14);
        assert_eq!(fl.v[2], before.v[2]);
        // The momentum handed to the fluid is what its velocities gained.
        let gained = (fl.v[1] - before.v[1]) * fl.mass;
        assert!((momentum - gained).norm() < 1e-15 && (momentum - pl.n * 0.3).norm() < 1e-14);
        assert_eq!(keep_above_plate(&mut fl, &None), (Vec2::zeros(), 0));
    }

    fn params(dx: f64, evss_alpha: f64) -> Params {
        let cfg = SceneConfig {
            artificial_viscosity_alpha: 0.0,
            artificial_viscosity_beta: 0.0,
            artificial_stress_epsilon: 0.0,
            gravity: 0.0,
            evss_alpha,
            ..Default::default()
        };
        let mut p = Params::from_config(&cfg);
        p.dx = dx;
        p
    }

    /// Interior accelerations of a block under a smooth velocity field, with EVSS off and on.
    fn interior_acc(v: impl Fn(Vec2) -> Vec2 + Copy) -> (Vec<Vec2>, Vec<Vec2>) {
        let (n, dx) = (40, 0.01);
        let f = lattice_block(n, dx, |_| 1000.0, v);
        let model = OldroydB::new(4.0, 0.1, 0.02);
        let run = |alpha| {
            let mut core = Core::new(
                CubicSpline::new(1.5 * dx),
                model.clone(),
                params(dx, alpha),
                None,
                WallModel::Fang,
            );
            core.refresh_neighbors(&f.x, &mut None);
            core.rates(&f);
            let margin = 6;
            (0..f.len())
                .filter(|&k| {
                    let (i, j) = ((k as i64) % n, (k as i64) / n);
                    i >= margin && j >= margin && i < n - margin && j < n - margin
                })
                .map(|k| core.acc[k])
                .collect::<Vec<_>>()
        };
        (run(0.0), run(1.0))
    }

    #[test]
    fn ren_pair_factor_table_matches_the_power() {
        let dx = 0.01;
        let kernel = CubicSpline::new(1.5 * dx);
        let mut p = params(dx, 0.0);
        p.art_kind = ArtificialStressKind::Ren;
        p.art_coef = 0.8;
        let art = ArtificialStress::new(&kernel, &p);
        // n = W(0)/W(d0) = 1.8 exactly for h = 1.5 d0 (Fang 2006 section 3.2 quotes the ratio).
        assert!((art.exponent() - 1.8).abs() < 1e-12);
        for k in 0..30011 {
            let r = kernel.radius() * k as f64 / 30011.0;
            let w = kernel.w(r);
            let exact = (w / kernel.w(dx)).powf(1.8);
            let table = art.pair_factor(w, r * r);
            assert!((table - exact).abs() < 5e-7, "r = {r}: {table} vs {exact}");
        }
    }

    #[test]
    fn evss_leaves_the_viscous_force_of_a_smooth_flow_unchanged() {
        // A shear wave and a compressing (divergent) flow: with EVSS the viscous force is split
        // between the nested first-derivative operator and Morris' Laplacian, and must add up to
        // the same force in the bulk (King & Lind eq. 7 is an identity).
        const K: f64 = 2.0 * std::f64::consts::PI / 0.4;
        for v in [
            (|x: Vec2| Vec2::new((K * x.y).sin(), 0.0)) as fn(Vec2) -> Vec2,
            |x: Vec2| Vec2::new((K * x.x).sin(), 0.5 * (K * x.y).cos()),
        ] {
            let (plain, evss) = interior_acc(v);
            // The force each operator carries: the whole viscosity eta0 = 4 Pa s times k^2 U / rho.
            let scale = 4.0 * K * K / 1000.0;
            let worst = plain
                .iter()
                .zip(&evss)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).norm()));
            let solvent = plain.iter().fold(0.0f64, |m, a| m.max(a.norm()));
            assert!(
                solvent > 0.05 * scale,
                "the flow has a viscous force: {solvent}"
            );
            assert!(worst < 0.01 * scale, "{worst} vs {scale}");
        }
    }
}
