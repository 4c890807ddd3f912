//! PDRI-SPH of Ren, Lu & Jiang 2015: standard SPH with periodic density reinitialisation.
//!
//! The rates are the same discretisation as Fang's WCSPH (Ren eqs. 13-16, 19, 21 are Fang eqs.
//! 23, 26, 27, 30-38), computed by the shared [`WcCore`] with Ren's walls:
//! wall particles whose values are interpolated with the weights 2h - r (eq. 23a) and ghost
//! particles extrapolated from them and from the point F at d0 inside the fluid (eq. 23b).
//! What is Ren's own lives here:
//!
//! * **Time integration**, eqs. (25a)-(25b): a predictor X~^{n+1} = X^n + dt G(X^n), then
//!   X^{n+1} = X^n + dt/2 (G(X^n) + G(X~^{n+1})), for X = (x, v, rho, A): Heun's method, second
//!   order. Eq. (25a) is printed with dt/2; read literally, the pair is two explicit Euler
//!   half-steps, first order (amplification (1 + z/2)^2 against e^z), which contradicts the
//!   "second-order accuracy" the paper states and its notation X~^{n+1} for the predicted state;
//!   it also amplifies every undamped acoustic mode by 1 + (omega dt)^2/4 per step. Measured on
//!   the elliptical drop at Ren's 1961 particles (no artificial viscosity), the literal reading
//!   blew up at t = 4.2e-3 s without reinitialisation and its pressure roughness reached 4 rho0
//!   U^2 by t = 8e-3 s with reinitialisation every 20 steps, so we read (25a) with dt.
//! * **Time-step limits**, eq. (25c): dt <= min(0.25 h/c, 0.25 (h/F)^{1/2}, 0.125 h^2/nu), which
//!   is Fang's (51)-(53) with the safety factor 0.25 and without the flow speed in the sound
//!   limit. `time_step_factor` can only lower the factor: it is min(time_step_factor, 0.25).
//! * **Periodic density reinitialisation**, eqs. (18a)-(18c), every `density_reinit_interval`
//!   steps (0 = never): rho_i = sum_j m_j W^Tay_ij with the Taylor-corrected (MLS) kernel, a 3x3
//!   solve per particle, falling back to the Shepard sum when the matrix is singular.
//!
//! * **Walls' kinematic condition** (not in Ren's paper): a particle that ends a step inside a
//!   wall is put back across it, its velocity into the wall removed, as in Fang's scheme
//!   ([`crate::boundary::ghost::keep_out_of_walls`]).
//!
//! The wall force is the force of the virtual particles on the fluid averaged over the two rate
//! evaluations, the same average that moves the fluid in eq. (25b), plus the momentum the
//! kinematic condition gives, so its time integral is the fluid's momentum change minus the
//! gravity impulse, to round-off.

use super::health::check_health;
use super::params::Params;
use super::wc::{ghost_walls, WcCore, WcSpace};
use super::Scheme;
use crate::boundary::ghost::{keep_out_of_walls, WallModel};
use crate::boundary::wall::Wall;
use crate::boundary::Boundary;
use crate::dim::mls::Mls;
use crate::dim::{Const, Dim, Vector};
use crate::kernel::Kernel;
use crate::neighbors::Domain;
use crate::particles::Fluid;
use crate::rheology::Rheology;
use crate::state::State;
use rayon::prelude::*;

/// Ren 2015 eq. (25c): the safety factor on the sound, force and viscous limits.
pub const REN_DT_FACTOR: f64 = 0.25;

/// Below this determinant the moment matrix of eq. (18b) counts as singular. The matrix is
/// dimensionless (its determinant is invariant under the change of length unit) and tends to the
/// identity in the bulk of a regular lattice; at a straight free surface, where half the support
/// is empty, its determinant is still about 0.1 (tested below). It vanishes for particles whose
/// neighbours all lie on a line (a thin filament) or that have almost none.
pub const MLS_SINGULAR_DET: f64 = 1e-3;

/// The PDRI-SPH scheme for kernel `K` and rheology `R` in N space dimensions (`Pdri<K, R>`:
/// two).
pub struct Pdri<K: Kernel<N>, R: Rheology, const N: usize = 2> {
    core: WcCore<K, R, N>,
    /// X^n + dt/2 G(X^n), the first half of eq. (25b).
    first: Fluid<N>,
    /// The predicted state X~^{n+1} (eq. 25a).
    pred: Fluid<N>,
    next: Fluid<N>,
    rho_new: Vec<f64>,
}

impl<K: Kernel, R: Rheology> Pdri<K, R> {
    /// The scheme for the walls `plates` of the initial state, each with Ren's wall and ghost
    /// particles.
    pub fn new(kernel: K, model: R, p: Params, plates: &[Wall]) -> Self {
        let walls = ghost_walls(kernel, WallModel::Ren, &p, plates);
        Self::with_walls(kernel, model, p, walls)
    }
}

impl<K: Kernel<N>, R: Rheology, const N: usize> Pdri<K, R, N>
where
    Const<N>: Dim + WcSpace<N> + Mls<N>,
{
    /// The scheme with the wall models `walls`, one per wall of the state, in its order (any
    /// dimension: the caller chooses the models).
    pub fn with_walls(kernel: K, model: R, p: Params<N>, walls: Vec<Box<dyn Boundary<N>>>) -> Self {
        Self {
            core: WcCore::new(kernel, model, p, walls),
            first: Fluid::default(),
            pred: Fluid::default(),
            next: Fluid::default(),
            rho_new: Vec::new(),
        }
    }

    /// Reinitialise every fluid density by eq. (18a) from the current positions and densities.
    /// Neighbour lists must be up to date for `fl.x`.
    fn reinitialise_density(&mut self, fl: &mut Fluid<N>) {
        let nf = fl.len();
        let c = &self.core;
        let fluid = &*fl;
        self.rho_new.clear();
        self.rho_new.par_extend((0..nf).into_par_iter().map(|i| {
            // Fluid neighbours only: wall and ghost particles hold rho0 by construction (Ren 3.5),
            // not a measurement of the fluid's density; the correction restores first-order
            // consistency where the support is cut by the wall, as at the free surface.
            let list = c.neighbors_of(i);
            let end = list.partition_point(|&j| (j as usize) < nf);
            mls_density(&c.kernel, &c.p.domain, fluid, &list[..end], i)
        }));
        crate::particles::copy_par(&mut fl.rho, &self.rho_new);
    }
}

/// Density of fluid particle `i` by Ren 2015 eqs. (18a)-(18c): rho_i = sum_j m_j W^Tay_ij with
/// W^Tay_ij = B M^{-1} g_ij, g_ij = (W_ij, dW_ij/dx_i, dW_ij/dy_i), B = (1, 0, 0) and the moment
/// matrix M = sum_j V_j g_ij (1, x_ji, y_ji), V_j = m_j / rho_j. With uniform masses,
/// rho_i = m (M^{-T} e_1) . sum_j g_ij. `list` holds i's fluid neighbours (i included); those
/// beyond the support add nothing. When M is singular (determinant below [`MLS_SINGULAR_DET`]),
/// or the corrected value is not a positive number, the Shepard sum
/// sum_j m_j W_ij / sum_j V_j W_ij is used instead, as Ren's section 3.2 prescribes.
pub fn mls_density<const N: usize, K: Kernel<N>>(
    kernel: &K,
    dom: &Domain,
    fl: &Fluid<N>,
    list: &[u32],
    i: usize,
) -> f64
where
    Const<N>: Mls<N>,
{
    let r2max = kernel.radius().powi(2);
    let xi = fl.x[i];
    let mut sums = <Const<N> as Mls<N>>::Moments::default();
    let mut vw = 0.0;
    for &j in list {
        let j = j as usize;
        let xji = dom.delta(&fl.x[j], &xi);
        let r2 = xji.norm_squared();
        if r2 >= r2max {
            continue;
        }
        let r = r2.sqrt();
        let (w, dw_r) = kernel.w_and_dw_over_r(r);
        // grad_i W_ij = (x_i - x_j) W'/r = -x_ji W'/r.
        let grad = -xji * dw_r;
        let vol = fl.mass / fl.rho[j];
        Const::<N>::add_pair(&mut sums, w, &grad, &xji, vol);
        vw += vol * w;
    }
    let shepard = fl.mass * Const::<N>::kernel_sum(&sums) / vw;
    match Const::<N>::corrected(&sums, MLS_SINGULAR_DET) {
        Some(corrected) => {
            let rho = fl.mass * corrected;
            if rho.is_finite() && rho > 0.0 {
                rho
            } else {
                shepard
            }
        }
        None => shepard,
    }
}

impl<K: Kernel<N>, R: Rheology, const N: usize> Scheme<N> for Pdri<K, R, N>
where
    Const<N>: Dim + WcSpace<N> + Mls<N>,
{
    fn step(&mut self, st: &mut State<N>, max_dt: f64) -> Result<f64, String> {
        let c = &mut self.core;
        let start = c.prof.start();
        c.refresh_neighbors(&st.fluid.x, &mut st.walls);
        let r0 = c.rates(&st.fluid, &st.walls);
        let t = c.prof.start();
        let per_wall0 = c.wall_on_fluid_per_wall(r0.wall_on_fluid, st.fluid.mass);
        let t = c.prof.lap(t, "wall forces per wall", true);
        let load0 = st.plate.map(|k| c.wall_on_particles(k, st.fluid.mass));
        let t = c.prof.lap(t, "wall forces and plate load", false);
        let factor = c.p.dt_factor.min(REN_DT_FACTOR);
        let dt_stable = c.stable_dt(&st.fluid, &r0, factor, false); // eq. (25c)
        let dt = dt_stable.min(max_dt);
        if dt.is_nan() || dt <= 0.0 {
            return Err(format!("time step collapsed to {dt:e} s"));
        }
        // Predictor, eq. (25a): X~^{n+1} = X^n + dt G(X^n); and the corrector's first half,
        // X^n + dt/2 G(X^n), while G(X^n) is at hand.
        let t = c.prof.lap(t, "time step", false);
        let fl = &st.fluid;
        c.update(&mut self.pred, fl, &fl.v, &fl.conf, dt);
        c.update(&mut self.first, fl, &fl.v, &fl.conf, 0.5 * dt);
        c.prof.lap(t, "update", false);
        c.refresh_neighbors(&self.pred.x, &mut st.walls);
        let r1 = c.rates(&self.pred, &st.walls);
        // Corrector, eq. (25b): X^{n+1} = (X^n + dt/2 G(X^n)) + dt/2 G(X~^{n+1}).
        let t = c.prof.start();
        c.update(
            &mut self.next,
            &self.first,
            &self.pred.v,
            &self.pred.conf,
            0.5 * dt,
        );
        std::mem::swap(&mut st.fluid, &mut self.next);
        let t = c.prof.lap(t, "update", false);
        // The fluid's velocity moved by dt/2 (a^n + a~^{n+1}), so the wall force that balances its
        // momentum is the same average of the two evaluations.
        let on_fluid = (r0.wall_on_fluid + r1.wall_on_fluid) * 0.5;
        let per_wall1 = c.wall_on_fluid_per_wall(r1.wall_on_fluid, st.fluid.mass);
        let mut per_wall: Vec<Vector<N>> = per_wall0
            .iter()
            .zip(&per_wall1)
            .map(|(a, b)| -(a + b) * 0.5)
            .collect();
        // A particle that ended the step inside a wall is put back, its velocity into the wall
        // removed (`keep_out_of_wall`, as in Fang's scheme); Ren's walls have no such condition,
        // and a fluid that flows past its walls for long needs it: in the cylinder array
        // (8 across, Newtonian, density reinitialised every 100 steps or never) particles went
        // through the channel walls at t = 2.4-3.1 s. The momentum it gives is the wall's, as in
        // WCSPH. A particle is never inside a wall otherwise (the health check stops the run),
        // so runs without contact are unchanged bit for bit.
        let (momenta, contacts, reflections) =
            keep_out_of_walls(&mut st.fluid, &st.walls, st.plate);
        let mut contact = Vector::<N>::zeros();
        for (k, m) in momenta.iter().enumerate() {
            contact += m;
            if let Some(w) = per_wall.get_mut(k) {
                *w -= m / dt;
            }
        }
        st.wall_reflections += reflections;
        st.wall_force = -on_fluid - contact / dt;
        st.wall_impulse += -on_fluid * dt - contact;
        st.book_wall_forces(per_wall, dt);
        let t = c.prof.lap(t, "wall forces per wall", true);
        // The plate's load by particle: the same average of the two evaluations, into the
        // state's kept vector.
        match (load0, st.plate) {
            (Some(a), Some(k)) => {
                let b = c.wall_on_particles(k, st.fluid.mass);
                st.plate_load.clear();
                st.plate_load.par_extend(
                    a.par_iter()
                        .zip(b.par_iter())
                        .with_min_len(1024)
                        .map(|(a, b)| -(a + b) * 0.5),
                );
            }
            _ => st.plate_load.clear(),
        }
        for (i, m) in contacts {
            if let Some(l) = st.plate_load.get_mut(i) {
                *l -= m / dt;
            }
        }
        st.last_dt = dt_stable;
        c.prof.lap(t, "wall forces and plate load", false);
        let interval = c.p.reinit_interval;
        if interval > 0 && (st.step + 1).is_multiple_of(interval) {
            c.refresh_neighbors(&st.fluid.x, &mut st.walls);
            let t = c.prof.start();
            self.reinitialise_density(&mut st.fluid);
            self.core.prof.lap(t, "density reinitialisation", false);
        }
        let t = self.core.prof.start();
        st.void_fraction = check_health::<R, _>(&self.core.p, st)?;
        self.core.prof.lap(t, "health check", false);
        self.core.prof.step(start);
        Ok(dt)
    }

    fn set_profiling(&mut self, on: bool) {
        self.core.prof.enable(on);
    }

    fn timings(&self) -> super::Timings {
        self.core.prof.timings()
    }

    fn wall_positions(&self, st: &State<N>) -> Vec<Vector<N>> {
        self.core.wall_positions(&st.walls)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::CubicSpline;
    use crate::scheme::wc::lattice_block;
    use crate::Vec2;
    use nalgebra::{Matrix3, Vector3};

    /// A square lattice block of side n dx, densities rho(x) = rho0 (1 + g . x).
    fn block(n: i64, dx: f64, g: Vec2) -> Fluid {
        lattice_block(n, dx, |x| 1000.0 * (1.0 + g.dot(&x)), |_| Vec2::zeros())
    }

    fn all(f: &Fluid) -> Vec<u32> {
        (0..f.len() as u32).collect()
    }

    fn moment_det(k: &CubicSpline, f: &Fluid, i: usize) -> f64 {
        let mut m = Matrix3::<f64>::zeros();
        for j in 0..f.len() {
            let xji = f.x[j] - f.x[i];
            let r = xji.norm();
            if r < k.radius() {
                let (w, dw_r) = k.w_and_dw_over_r(r);
                let g = Vector3::new(w, -xji.x * dw_r, -xji.y * dw_r);
                m += g * Vector3::new(1.0, xji.x, xji.y).transpose() * (f.mass / f.rho[j]);
            }
        }
        m.determinant()
    }

    #[test]
    fn moment_matrix_is_regular_in_the_bulk_and_at_a_free_surface() {
        let dx = 0.1;
        let k = CubicSpline::new(1.5 * dx);
        let f = block(12, dx, Vec2::zeros());
        let bulk = moment_det(&k, &f, 6 * 12 + 6);
        let edge = moment_det(&k, &f, 6);
        let corner = moment_det(&k, &f, 0);
        assert!((bulk - 1.0).abs() < 0.05, "bulk det {bulk}");
        assert!(
            edge > 0.05 && corner > MLS_SINGULAR_DET,
            "edge {edge}, corner {corner}"
        );
    }

    #[test]
    fn mls_density_reproduces_a_linear_field_up_to_the_free_surface() {
        // Eq. (18) has C^0 and C^1 consistency: sum_j V_j rho_j W^Tay_ij is exact for linear
        // rho, at the corner of the block as in its middle. The Shepard sum is not at the edge.
        let dx = 0.1;
        let k = CubicSpline::new(1.5 * dx);
        let g = Vec2::new(0.05, -0.03);
        let f = block(12, dx, g);
        let list = all(&f);
        for i in [0, 5, 6 * 12 + 6, 143] {
            let rho = mls_density(&k, &Domain::OPEN, &f, &list, i);
            assert!(
                (rho - f.rho[i]).abs() < 1e-9 * f.rho[i],
                "particle {i}: {rho} vs {}",
                f.rho[i]
            );
        }
        let shepard_corner = {
            let (mut num, mut den) = (0.0, 0.0);
            for j in 0..f.len() {
                let w = k.w((f.x[j] - f.x[0]).norm());
                num += f.mass * w;
                den += f.mass / f.rho[j] * w;
            }
            num / den
        };
        assert!((shepard_corner - f.rho[0]).abs() > 1e-5 * f.rho[0]);
    }

    #[test]
    fn singular_moment_matrix_falls_back_to_shepard() {
        // Particles on a line: no spread across it, M is singular.
        let dx = 0.1;
        let k = CubicSpline::new(1.5 * dx);
        let mut f = Fluid {
            mass: 10.0,
            ..Default::default()
        };
        for i in 0..5 {
            f.x.push(Vec2::new(i as f64 * dx, 0.0));
            f.v.push(Vec2::zeros());
            f.rho.push(1000.0 + i as f64);
        }
        let rho = mls_density(&k, &Domain::OPEN, &f, &all(&f), 2);
        let (mut num, mut den) = (0.0, 0.0);
        for j in 0..5 {
            let w = k.w((f.x[j] - f.x[2]).norm());
            num += f.mass * w;
            den += f.mass / f.rho[j] * w;
        }
        assert!(
            (rho - num / den).abs() < 1e-12 * rho,
            "{rho} vs {}",
            num / den
        );
    }
}
