//! Weakly compressible SPH of Fang, Owens, Tacher & Parriaux 2006 (section 3).
//!
//! One step is Fang's predictor-corrector (eqs. 49-50). Each of its two rate evaluations runs:
//! 1. virtual velocities: boundary particles at rest, image velocities extrapolated from the
//!    interior point P (eqs. 46-47);
//! 2. fluid pass 1 (a gather): velocity gradient (eq. 23), continuity (eq. 26), pressure from the
//!    equation of state (eq. 10), solvent stress eta d (eq. 8, Fang's d = kappa + kappa^T) and
//!    polymer stress from the conformation tensor;
//! 3. virtual stresses: boundary particles by normalised interpolation with the wall-normal
//!    elastic stress set to zero (eq. 46), image particles extrapolated (eq. 48);
//! 4. fluid pass 2 (a gather): momentum (eq. 27) with artificial viscosity (eqs. 30-37) and
//!    artificial stress (eqs. 38-44); the part of it exerted by virtual particles is the wall force.
//!
//! Every pass is a gather over ascending neighbour indices, so results are bitwise independent of
//! the thread count.

use super::artificial;
use super::Scheme;
use crate::boundary::plate::{Plate, IMAGE_ROWS, PER_COLUMN};
use crate::config::{ConformationMethod, EquationOfState, SceneConfig};
use crate::kernel::Kernel;
use crate::neighbors::{CellGrid, NeighborList};
use crate::particles::Fluid;
use crate::rheology::{self, Rheology};
use crate::simulation::State;
use crate::{Mat2, Vec2};
use rayon::prelude::*;

/// Neighbour-list skin as a fraction of h.
const SKIN: f64 = 0.25;
/// A particle this far below the plate has gone through it.
const PENETRATION_DEPTH: f64 = 0.5;
/// Relative density deviation that stops a run.
const MAX_DENSITY_DEVIATION: f64 = 0.3;

/// Constants of the scheme, resolved once from the configuration.
#[derive(Debug, Clone)]
pub struct Params {
    pub rho0: f64,
    pub c: f64,
    pub alpha: f64,
    pub beta: f64,
    pub eps: f64,
    pub gravity: Vec2,
    pub eos: EquationOfState,
    pub dt_factor: f64,
    pub method: ConformationMethod,
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
            eps: cfg.artificial_stress_epsilon,
            gravity: Vec2::new(0.0, -cfg.gravity),
            eos: cfg.equation_of_state,
            dt_factor: cfg.time_step_factor,
            method: cfg.conformation_method,
            fracture_void_fraction: cfg.fracture_void_fraction,
            dx,
            domain_radius: 1000.0 * cfg.drop_diameter + 10.0 * cfg.drop_height,
        }
    }

    /// Pressure from density: Fang 2006 eq. (10), or Tait's equation (Ren 2015 eq. 8).
    #[inline]
    pub fn pressure(&self, rho: f64) -> f64 {
        match self.eos {
            EquationOfState::Linear => self.c * self.c * (rho - self.rho0),
            EquationOfState::Tait => {
                self.rho0 * self.c * self.c / 7.0 * ((rho / self.rho0).powi(7) - 1.0)
            }
        }
    }
}

/// What one rate evaluation reports besides the per-particle rates.
#[derive(Debug, Clone, Copy, Default)]
struct StageReport {
    /// Force of the virtual (wall) particles on the fluid [N/m].
    wall_on_fluid: Vec2,
    /// Largest acceleration magnitude.
    max_acc: f64,
}

/// The WCSPH scheme for kernel `K` and rheology `R`.
pub struct Wcsph<K: Kernel, R: Rheology> {
    kernel: K,
    model: R,
    p: Params,
    /// W(dx), the reference of the artificial-stress factor f_ij = W_ij / W(dx) (eq. 39).
    w_dx: f64,
    // Neighbour structures, rebuilt when particles have moved more than half the skin.
    built_x: Vec<Vec2>,
    nlist: NeighborList,
    /// Fluid neighbours of each column's boundary particle (2c) and interior point P (2c+1).
    clist: NeighborList,
    plate: Option<Plate>,
    // Work arrays over all particles (fluid first, then virtual).
    all_x: Vec<Vec2>,
    all_v: Vec<Vec2>,
    all_rho: Vec<f64>,
    all_sigma: Vec<Mat2>,
    all_art: Vec<Mat2>,
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
    /// Polymer stress of fluid particles (empty for inelastic models).
    tau_p: Vec<Mat2>,
    // Fluid rates.
    kappa: Vec<Mat2>,
    drho: Vec<f64>,
    acc: Vec<Vec2>,
    wall_acc: Vec<Vec2>,
    half: Fluid,
}

impl<K: Kernel, R: Rheology> Wcsph<K, R> {
    pub fn new(kernel: K, model: R, p: Params, plate: Option<Plate>) -> Self {
        let w_dx = kernel.w(p.dx);
        Self {
            kernel,
            model,
            p,
            w_dx,
            built_x: Vec::new(),
            nlist: NeighborList::default(),
            clist: NeighborList::default(),
            plate,
            all_x: Vec::new(),
            all_v: Vec::new(),
            all_rho: Vec::new(),
            all_sigma: Vec::new(),
            all_art: Vec::new(),
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
            half: Fluid::default(),
        }
    }

    fn search_radius(&self) -> f64 {
        self.kernel.radius() + SKIN * self.kernel.h()
    }

    /// Rebuild the neighbour lists (and grow the plate) if any particle moved more than half the
    /// skin since the last build.
    fn refresh_neighbors(&mut self, x: &[Vec2], st_plate: &mut Option<Plate>) {
        let half_skin2 = (0.5 * SKIN * self.kernel.h()).powi(2);
        let stale = self.built_x.len() != x.len()
            || x.par_iter()
                .zip(self.built_x.par_iter())
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
    }

    /// Normalised SPH interpolation weights (Fang 2006 eq. 46) of fluid neighbours of point `q`:
    /// calls `f(j, w_j)` with sum_j w_j = 1, and returns false when no fluid is within reach.
    #[inline]
    fn shepard(
        kernel: &K,
        fluid: &Fluid,
        list: &[u32],
        q: &Vec2,
        mut f: impl FnMut(usize, f64),
    ) -> bool {
        let r2max = kernel.radius().powi(2);
        let mut den = 0.0;
        for &j in list {
            let j = j as usize;
            let r2 = (fluid.x[j] - q).norm_squared();
            if r2 < r2max {
                den += fluid.mass / fluid.rho[j] * kernel.w(r2.sqrt());
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
                f(j, fluid.mass / fluid.rho[j] * kernel.w(r2.sqrt()) * inv);
            }
        }
        true
    }

    /// Image-particle factor 1 + d_I/d_P of image row m (d_I = m dx, d_P = dx; eqs. 47-48).
    #[inline]
    fn image_factor(row: usize) -> f64 {
        1.0 + row as f64
    }

    /// Steps 1: virtual velocities.
    fn virtual_velocities(&mut self, fluid: &Fluid) {
        let Some(plate) = &self.plate else { return };
        let nf = fluid.len();
        let (kernel, clist) = (&self.kernel, &self.clist);
        self.all_v[nf..]
            .par_chunks_mut(PER_COLUMN)
            .enumerate()
            .for_each(|(c, out)| {
                let q = plate.interior_point(c);
                let mut vp = Vec2::zeros();
                Self::shepard(kernel, fluid, clist.of(2 * c + 1), &q, |j, w| {
                    vp += fluid.v[j] * w
                });
                out[0] = Vec2::zeros(); // boundary particle moves with the (fixed) wall
                for (row, o) in out.iter_mut().enumerate().skip(1) {
                    // eq. (47) with v_W = 0
                    *o = vp - vp * Self::image_factor(row);
                }
            });
    }

    /// Step 3: virtual stresses and their artificial stresses.
    fn virtual_stresses(&mut self, fluid: &Fluid) {
        let Some(plate) = &self.plate else { return };
        let nf = fluid.len();
        let n = plate.n;
        let nn = n * n.transpose();
        let (kernel, clist, eps, rho0) = (&self.kernel, &self.clist, self.p.eps, self.p.rho0);
        let (fsig, vsig) = self.all_sigma.split_at_mut(nf);
        let fsig = &*fsig;
        let tau_p = &self.tau_p;
        let vart = &mut self.all_art[nf..];
        vsig.par_chunks_mut(PER_COLUMN)
            .zip(vart.par_chunks_mut(PER_COLUMN))
            .enumerate()
            .for_each(|(c, (sig, art))| {
                let qb = plate.point(plate.column_s(c), 0.0);
                let mut sb = Mat2::zeros();
                let mut snn = 0.0;
                Self::shepard(kernel, fluid, clist.of(2 * c), &qb, |j, w| {
                    sb += fsig[j] * w;
                    if R::ELASTIC {
                        snn += n.dot(&(tau_p[j] * n)) * w;
                    }
                });
                // Fang 3.3: the wall-normal component of the elastic stress is zero on the wall.
                sb -= nn * snn;
                let qp = plate.interior_point(c);
                let mut sp = Mat2::zeros();
                if !Self::shepard(kernel, fluid, clist.of(2 * c + 1), &qp, |j, w| {
                    sp += fsig[j] * w
                }) {
                    sp = sb;
                }
                sig[0] = sb;
                for row in 1..=IMAGE_ROWS {
                    sig[row] = sp + (sb - sp) * Self::image_factor(row); // eq. (48)
                }
                for k in 0..PER_COLUMN {
                    art[k] = artificial::fang_stress(eps, &sig[k], rho0);
                }
            });
    }

    /// One rate evaluation at fluid state `fl`: fills kappa, drho, acc, wall_acc.
    fn rates(&mut self, fl: &Fluid) -> StageReport {
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
        if R::ELASTIC {
            let model = &self.model;
            self.tau_p.resize(nf, Mat2::zeros());
            self.tau_p
                .par_iter_mut()
                .zip(fl.conf.par_iter())
                .for_each(|(t, a)| *t = model.polymer_stress(a));
        }

        // Pass 1 (a gather): velocity gradient (eq. 23), continuity (eq. 26), stresses, and the
        // kernel values of every pair inside the support, cached for pass 2.
        let npairs = self.nlist.pairs();
        self.pair_j.resize(npairs, 0);
        self.pair_grad.resize(npairs, Vec2::zeros());
        self.pair_w.resize(npairs, 0.0);
        self.pair_len.resize(nf, 0);
        self.kappa.resize(nf, Mat2::zeros());
        self.drho.resize(nf, 0.0);
        {
            let (kernel, model, p, eps) = (&self.kernel, &self.model, &self.p, self.p.eps);
            let (ax, av, avol, tau_p) = (&self.all_x, &self.all_v, &self.all_vol, &self.tau_p);
            let nlist = &self.nlist;
            let r2max = kernel.radius().powi(2);
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
            )
                .into_par_iter()
                .enumerate()
                .for_each(|(i, (js, gs, ws, len, kappa_i, drho_i, sigma_i, art_i))| {
                    let (xi, vi) = (ax[i], av[i]);
                    let mut kappa = Mat2::zeros();
                    let mut drho = 0.0;
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
                        let (w, dw_r) = kernel.w_and_dw_over_r(r2.sqrt());
                        let grad = xij * dw_r;
                        js[k] = j;
                        gs[k] = grad;
                        ws[k] = w;
                        k += 1;
                        let vij = vi - av[ju];
                        kappa -= (vij * grad.transpose()) * avol[ju];
                        drho += vij.dot(&grad);
                    }
                    *len = k as u32;
                    *kappa_i = kappa;
                    *drho_i = drho * mass;
                    let eta = model.solvent_viscosity(&kappa);
                    let mut sigma = Mat2::identity() * (-p.pressure(fl.rho[i]))
                        + (kappa + kappa.transpose()) * eta;
                    if R::ELASTIC {
                        sigma += tau_p[i];
                    }
                    *sigma_i = sigma;
                    *art_i = artificial::fang_stress(eps, &sigma, fl.rho[i]);
                });
        }
        self.virtual_stresses(fl);
        self.all_sr2.resize(self.all_sigma.len(), Mat2::zeros());
        self.all_sr2
            .par_iter_mut()
            .zip(self.all_sigma.par_iter().zip(self.all_rho.par_iter()))
            .for_each(|(o, (sg, r))| *o = sg / (r * r));

        // Pass 2 (a gather over the cached pairs): momentum (eq. 27) with artificial viscosity
        // (eqs. 30-37) and artificial stress (eq. 38).
        self.acc.resize(nf, Vec2::zeros());
        self.wall_acc.resize(nf, Vec2::zeros());
        {
            let p = &self.p;
            let (ax, av, arho, asr2, aart) = (
                &self.all_x,
                &self.all_v,
                &self.all_rho,
                &self.all_sr2,
                &self.all_art,
            );
            let (pj, pg, pw, plen) = (&self.pair_j, &self.pair_grad, &self.pair_w, &self.pair_len);
            let nlist = &self.nlist;
            let h = self.kernel.h();
            let inv_wdx = 1.0 / self.w_dx;
            let use_art = p.eps > 0.0;
            (&mut self.acc[..], &mut self.wall_acc[..])
                .into_par_iter()
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
                        let pi = artificial::viscosity(
                            p.alpha,
                            p.beta,
                            h,
                            p.c,
                            0.5 * (rhoi + arho[j]),
                            &(vi - av[j]),
                            &xij,
                            xij.norm_squared(),
                        );
                        t[(0, 0)] -= pi;
                        t[(1, 1)] -= pi;
                        if use_art {
                            let f = pw[k] * inv_wdx;
                            let f2 = f * f;
                            t += (ri + aart[j]) * (f2 * f2); // f^n with n = 4
                        }
                        let contrib = t * pg[k];
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

    /// Time-step limit from Fang 2006 eqs. (51)-(53) times the safety factor, plus the
    /// relaxation time for the explicit conformation update.
    fn stable_dt(&self, fl: &Fluid, report: &StageReport) -> f64 {
        let h = self.kernel.h();
        let vmax = fl.v.iter().fold(0.0f64, |m, v| m.max(v.norm()));
        let nu = self.model.max_viscosity() / self.p.rho0;
        let mut dt = h / (self.p.c + vmax); // eq. (51)
        if report.max_acc > 0.0 {
            dt = dt.min((h / report.max_acc).sqrt()); // eq. (52)
        }
        dt = dt.min(0.5 * h * h / nu); // eq. (53)
        if R::ELASTIC {
            dt = dt.min(self.model.relaxation_time());
        }
        self.p.dt_factor * dt
    }

    /// Health of a state after a step: the void fraction, or the cause of a breakdown.
    fn check_health(&self, fl: &Fluid, plate: &Option<Plate>) -> Result<f64, String> {
        let p = &self.p;
        let bad = (0..fl.len()).into_par_iter().find_first(|&i| {
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
            return Err(format!(
                "fracture by the tensile instability: holes make up {:.1} % of the fluid's area \
                 (limit {:.1} %); raise artificial_stress_epsilon",
                100.0 * voids,
                100.0 * p.fracture_void_fraction
            ));
        }
        Ok(voids)
    }
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

impl<K: Kernel, R: Rheology> Scheme for Wcsph<K, R> {
    fn step(&mut self, st: &mut State, max_dt: f64) -> Result<f64, String> {
        let method = self.p.method;
        self.refresh_neighbors(&st.fluid.x.clone(), &mut st.plate);
        let r0 = self.rates(&st.fluid);
        let dt_stable = self.stable_dt(&st.fluid, &r0);
        let dt = dt_stable.min(max_dt);
        if !(dt > 0.0) {
            return Err(format!("time step collapsed to {dt:e} s"));
        }
        // Predictor, eq. (49): X^{n+1/2} = X^n + F^n dt/2.
        let hdt = 0.5 * dt;
        let fl = &st.fluid;
        let mut half = std::mem::take(&mut self.half);
        half.mass = fl.mass;
        half.x.clear();
        half.x
            .extend(fl.x.iter().zip(&fl.v).map(|(x, v)| x + v * hdt));
        half.v.clear();
        half.v
            .extend(fl.v.iter().zip(&self.acc).map(|(v, a)| v + a * hdt));
        half.rho.clear();
        half.rho
            .extend(fl.rho.iter().zip(&self.drho).map(|(r, d)| r + d * hdt));
        half.conf.clear();
        if R::ELASTIC {
            let model = &self.model;
            half.conf.par_extend(
                fl.conf
                    .par_iter()
                    .zip(self.kappa.par_iter())
                    .map(|(a, k)| rheology::advance(method, model, a, a, k, hdt)),
            );
        }
        self.refresh_neighbors(&half.x, &mut st.plate);
        let r1 = self.rates(&half);
        // Corrector, eq. (50): X^{n+1} = X^n + F^{n+1/2} dt.
        let fl = &mut st.fluid;
        (&mut fl.x[..], &mut fl.v[..], &mut fl.rho[..])
            .into_par_iter()
            .zip((&half.v[..], &self.acc[..], &self.drho[..]))
            .for_each(|((x, v, rho), (vh, a, d))| {
                *x += vh * dt;
                *v += a * dt;
                *rho += d * dt;
            });
        if R::ELASTIC {
            let model = &self.model;
            let (hc, kp) = (&half.conf, &self.kappa);
            fl.conf
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, a)| *a = rheology::advance(method, model, a, &hc[i], &kp[i], dt));
        }
        self.half = half;
        // Force of the fluid on the plate is minus the force of the wall particles on the fluid;
        // integrating it with the corrector's own rates makes the momentum balance exact.
        st.wall_force = -r1.wall_on_fluid;
        st.wall_impulse += -r1.wall_on_fluid * dt;
        st.last_dt = dt_stable;
        st.void_fraction = self.check_health(&st.fluid, &st.plate)?;
        Ok(dt)
    }

    fn wall_positions(&self) -> Vec<Vec2> {
        self.plate
            .as_ref()
            .map(|p| p.virtual_positions())
            .unwrap_or_default()
    }
}
