//! Kinematics of one particle from its neighbours: the velocity gradient kappa = (grad v)^T
//! (Fang 2006 eq. 23, Ren 2015 eq. 15) and the continuity rate (Fang eq. 26, Ren eq. 13).

use crate::{Mat2, Vec2};

/// Sums over one particle's pairs.
#[derive(Debug, Clone, Copy)]
pub struct Kinematics {
    /// kappa_i = -sum_j V_j v_ij (x) grad_i W_ij, with kappa^{ab} = dv^a/dx^b.
    pub kappa: Mat2,
    /// sum_j v_ij . grad_i W_ij; times the (uniform) particle mass it is d rho_i / dt.
    pub continuity: f64,
}

impl Default for Kinematics {
    fn default() -> Self {
        Self {
            kappa: Mat2::zeros(),
            continuity: 0.0,
        }
    }
}

impl Kinematics {
    /// Add pair (i, j): relative velocity `vij` = v_i - v_j, kernel gradient `grad` = grad_i W_ij,
    /// volume `vol_j` = m_j / rho_j.
    #[inline]
    pub fn add_pair(&mut self, vij: &Vec2, grad: &Vec2, vol_j: f64) {
        self.kappa -= (vij * grad.transpose()) * vol_j;
        self.continuity += vij.dot(grad);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{CubicSpline, Kernel};

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
}
