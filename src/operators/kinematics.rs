//! Kinematics of one particle from its neighbours: the velocity gradient kappa = (grad v)^T
//! (Fang 2006 eq. 23, Ren 2015 eq. 15) and the continuity rate (Fang eq. 26, Ren eq. 13), summed
//! pair by pair inside a scheme's gather pass ([`Kinematics`]), and King & Lind 2021's corrected
//! velocity gradient (eq. (20) with the Bonet & Lok correction of eq. (22)) over a pair cache
//! ([`corrected_velocity_gradients`]).

use super::pairs::PairCache;
use crate::dim::{Tensor, Vector};
use crate::neighbors::NeighborList;
use rayon::prelude::*;

/// Sums over one particle's pairs, in N dimensions (`Kinematics` alone: two).
#[derive(Debug, Clone, Copy)]
pub struct Kinematics<const N: usize = 2> {
    /// kappa_i = -sum_j V_j v_ij (x) grad_i W_ij, with kappa^{ab} = dv^a/dx^b.
    pub kappa: Tensor<N>,
    /// sum_j v_ij . grad_i W_ij; times the (uniform) particle mass it is d rho_i / dt.
    pub continuity: f64,
}

impl<const N: usize> Default for Kinematics<N> {
    fn default() -> Self {
        Self {
            kappa: Tensor::zeros(),
            continuity: 0.0,
        }
    }
}

impl<const N: usize> Kinematics<N> {
    /// Add pair (i, j): relative velocity `vij` = v_i - v_j, kernel gradient `grad` = grad_i W_ij,
    /// volume `vol_j` = m_j / rho_j.
    #[inline]
    pub fn add_pair(&mut self, vij: &Vector<N>, grad: &Vector<N>, vol_j: f64) {
        self.add_pair_split(vij, vij, grad, vol_j);
    }

    /// [`Kinematics::add_pair`] with its own relative velocity `cij` in the continuity rate: a
    /// wall's virtual particle j carries a no-slip velocity for the velocity gradient and the
    /// wall's own velocity for the density rate (see
    /// [`crate::boundary::Boundary::continuity_at_wall_velocity`]). With `cij = vij` it is
    /// [`Kinematics::add_pair`], operation for operation.
    #[inline]
    pub fn add_pair_split(
        &mut self,
        vij: &Vector<N>,
        cij: &Vector<N>,
        grad: &Vector<N>,
        vol_j: f64,
    ) {
        self.kappa -= (vij * grad.transpose()) * vol_j;
        self.continuity += cij.dot(grad);
    }
}

/// Smallest number of particles per parallel task of [`corrected_velocity_gradients`].
const MIN_TASK: usize = 64;

/// Corrected velocity gradients of the fluid particles `0..n` (King & Lind 2021 eq. (20),
/// negative form, with the Bonet & Lok 1999 correction matrices `l` of eq. (22)):
/// `kappa_i = V (sum_j (u_j - u_i) (grad_i W_ij)^T) L_i^T`, kappa^{ab} = du^a/dx^b, for the
/// uniform volume `vol`, from the pair gradients of `pairs` in the full layout of `list`
/// ([`PairCache::reset_full`]). `u` covers every point the lists refer to (fluid, then virtual
/// particles). With `L_i = I` it is the uncorrected gradient [`Kinematics`] sums per pair
/// (Fang 2006 eq. 23), up to the order of the operations.
pub fn corrected_velocity_gradients<const N: usize>(
    n: usize,
    u: &[Vector<N>],
    vol: f64,
    list: &NeighborList,
    pairs: &PairCache<N>,
    l: &[Tensor<N>],
) -> Vec<Tensor<N>> {
    (0..n)
        .into_par_iter()
        .with_min_len(MIN_TASK)
        .map(|i| corrected_velocity_gradient(i, u, vol, list, pairs, &l[i]))
        .collect()
}

/// Particle `i`'s term of [`corrected_velocity_gradients`] with the correction matrix `l_i`
/// (the same operations in the same order, so the same bits).
pub fn corrected_velocity_gradient<const N: usize>(
    i: usize,
    u: &[Vector<N>],
    vol: f64,
    list: &NeighborList,
    pairs: &PairCache<N>,
    l_i: &Tensor<N>,
) -> Tensor<N> {
    let off = list.offset(i);
    let mut k = Tensor::<N>::zeros();
    for (kk, &j) in list.of(i).iter().enumerate() {
        let g = pairs.grad[off + kk];
        k += (u[j as usize] - u[i]) * g.transpose();
    }
    k * l_i.transpose() * vol
}

/// Replace `kappa[i]` for every `i` with `rows[i]` by particle i's corrected gradient with its
/// own matrix `l[i]` ([`corrected_velocity_gradient`]), in parallel, the other rows untouched:
/// the ISPH free surface's rows take their own Bonet & Lok matrix where the rest of the step
/// keeps L = I (King & Lind 2021 (35a)'s surface value, the surface rows' stretching).
pub fn recorrect_rows<const N: usize>(
    kappa: &mut [Tensor<N>],
    rows: &[bool],
    u: &[Vector<N>],
    vol: f64,
    list: &NeighborList,
    pairs: &PairCache<N>,
    l: &[Tensor<N>],
) {
    kappa
        .par_iter_mut()
        .enumerate()
        .filter(|(i, _)| rows[*i])
        .for_each(|(i, k)| *k = corrected_velocity_gradient(i, u, vol, list, pairs, &l[i]));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{CubicSpline, Kernel};
    use crate::{Mat2, Vec2};

    #[test]
    fn velocity_gradient_of_a_linear_field_in_the_bulk() {
        // A lattice under v = G x: the gradient comes out as G in the bulk (first-order
        // consistency of the symmetric lattice sum), and the continuity rate as -rho tr(G)/m ...
        let (dx, h) = (0.1, 0.15);
        let k = CubicSpline::new(h);
        let g = Mat2::new(0.3, -1.2, 0.7, 0.1);
        let mut kin = Kinematics::default();
        for j in -4i32..=4 {
            for i in -4i32..=4 {
                let xj = Vec2::new(i as f64 * dx, j as f64 * dx);
                let r = xj.norm();
                if r == 0.0 || r >= k.radius() {
                    continue;
                }
                let grad = -xj * k.dw_over_r(r); // x_i = 0, x_ij = -x_j
                kin.add_pair(&(-(g * xj)), &grad, dx * dx);
            }
        }
        assert!((kin.kappa - g).norm() < 0.02 * g.norm(), "{}", kin.kappa);
        // ... with V_j = dx^2: sum_j v_ij . grad W_ij = -tr(G) / dx^2 to the same accuracy.
        assert!((kin.continuity * dx * dx + g.trace()).abs() < 0.02 * g.norm());
    }

    /// On a disordered disc (every particle moved by up to +/-0.25 dr), the corrected velocity
    /// gradient of a linear field is exact to round-off at every particle, the truncated
    /// supports of the rim included; with L = I the rim is off by tens of percent.
    #[test]
    fn corrected_velocity_gradient_of_a_linear_field_is_exact() {
        use crate::kernel::QuinticSpline;
        use crate::neighbors::Domain;
        use crate::operators::{correction, fixtures::disc};
        let dr = 0.01;
        let radius = 12.0 * dr;
        let set = disc(radius, dr, 0.25, 5);
        let k = QuinticSpline::new(1.3 * dr);
        let nl = set.neighbours(k.radius());
        let vol = dr * dr;
        let mut pairs = PairCache::default();
        pairs.reset_full(&nl);
        for i in 0..set.n_fluid {
            let off = nl.offset(i);
            for (kk, &j) in nl.of(i).iter().enumerate() {
                let xij = set.x[i] - set.x[j as usize];
                if j as usize != i {
                    pairs.grad[off + kk] = xij * k.dw_over_r(xij.norm());
                }
            }
        }
        let g = Mat2::new(0.3, -1.2, 0.7, 0.1);
        let u: Vec<Vec2> = set.x.iter().map(|x| g * x + Vec2::new(2.0, -1.0)).collect();
        let vols = vec![vol; set.x.len()];
        let l = correction::correction_matrices(&set.x, &vols, &nl, &k, &Domain::OPEN);
        let corrected = corrected_velocity_gradients(set.n_fluid, &u, vol, &nl, &pairs, &l);
        let worst = corrected
            .iter()
            .map(|kappa| (kappa - g).norm() / g.norm())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "{worst:e}");
        let ident = vec![Mat2::identity(); set.n_fluid];
        let plain = corrected_velocity_gradients(set.n_fluid, &u, vol, &nl, &pairs, &ident);
        let rim = (0..set.n_fluid)
            .filter(|&i| set.x[i].norm() > radius - 1.5 * dr)
            .map(|i| (plain[i] - g).norm() / g.norm())
            .fold(0.0, f64::max);
        assert!(rim > 0.2, "{rim}");
    }
}
