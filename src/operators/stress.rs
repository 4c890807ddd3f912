//! The stress of one particle and the viscous Laplacian.
//!
//! **Stress assembly** ([`assemble`]): sigma = -p I + viscous + polymer (Fang 2006 eq. 8, Ren 2015
//! eq. 16), or with EVSS (King & Lind 2021 eqs. 6-8) the split form whose viscous part goes
//! through Morris' Laplacian ([`morris_pair`]) instead.
//!
//! **The viscous operator.** Fang's nested form puts eta (kappa + kappa^T) into sigma and takes
//! the divergence with the same first-derivative operator: a second derivative from two first
//! ones, blind to a particle-scale zigzag. Where a wall holds a steady shear layer (the channel)
//! nothing damps it: measured on the Newtonian channel (20 across, no artificial viscosity) the
//! rows next to the walls decouple and by t = 1.9 t_v a cross-flow of 2 U and density errors of
//! 9 % have grown, under both schemes (Monaghan's artificial viscosity damps it but adds a
//! viscosity of order alpha h c / 8). The `laplacian` viscous operator sends the solvent
//! viscosity through Morris' Laplacian instead, which sees the zigzag (the channel's steady
//! centre line then within 0.3 % of the exact one under both schemes); `auto` keeps Fang's
//! operator for the drops and takes the Laplacian for the channel.
//!
//! **EVSS** (`evss_alpha` > 0). With Fang's nested summation the solvent stress goes through the
//! same first-derivative operator as the polymer stress, and the split
//! Phi + (beta + alpha_V) eta0 2D = tau_p + beta eta0 2D would be an identity. So with EVSS on,
//! the viscous part (solvent + added) goes through Morris' Laplacian instead, and the
//! first-derivative operator sees Phi. Weakly compressible flow has div(2D) = lap v + grad div v
//! where King & Lind's incompressible scheme has lap v, so what the Laplacian lacks stays with the
//! first-derivative operator; a unit test of the weakly compressible scheme checks that the split
//! leaves the viscous force of smooth flows, sheared or compressed, unchanged to 0.6 %. The two
//! operators still differ in the dissipation they add at the particle scale (King & Lind section
//! IV.A: the nested one reaches neighbours of neighbours). Measured on Fang's UCM drop (beta = 0,
//! lambda = 0.02 s, 316 to 1976 particles): it runs to t* = 8 without EVSS and with
//! evss_alpha = 0.01 or 0.1 (King & Lind's values), but evss_alpha >= 0.5 orders the particles
//! into chains that the void-fraction check reports as fracture by t* = 2, under both schemes and
//! both artificial stresses.

use crate::dim::{Tensor, Vector};
use crate::rheology::Evss;

/// Morris' regularisation of the viscous Laplacian, eta^2 = 0.01 h^2 (Morris, Fox & Zhu 1997).
pub const MORRIS_ETA2: f64 = 0.01;

/// Total stress of a particle: pressure `p`, solvent viscosity `eta` (possibly shear-dependent),
/// velocity gradient `kappa` and, for elastic models, the polymer stress `tau_p`. With
/// `laplacian` (EVSS on, or the `laplacian` viscous operator chosen) the solvent's (and EVSS's
/// added) eta lap v is left to Morris' Laplacian ([`morris_pair`]).
#[inline]
pub fn assemble<const N: usize>(
    p: f64,
    eta: f64,
    kappa: &Tensor<N>,
    tau_p: Option<&Tensor<N>>,
    evss: &Evss,
    laplacian: bool,
) -> Tensor<N> {
    let mut sigma = Tensor::identity() * (-p);
    if laplacian {
        // King & Lind eqs. (6)-(8), weakly compressible: the Laplacian carries
        // (eta_s + alpha_V eta0) lap v, and since div(2D) = lap v + grad(div v) here, the
        // first-derivative operator keeps what the Laplacian lacks: the solvent's
        // eta_s (div v) I, and Phi with the added viscosity taken out of the deviatoric rate of
        // strain only, tau_p - alpha_V eta0 (2D - (div v) I).
        let div = kappa.trace();
        sigma += Tensor::identity() * (eta * div);
        if let Some(t) = tau_p {
            sigma += evss.phi(t, kappa) + Tensor::identity() * (evss.added_viscosity() * div);
        }
    } else {
        // Fang eq. (8), Ren eq. (16): eta (kappa + kappa^T) in the stress.
        sigma += (kappa + kappa.transpose()) * eta;
        if let Some(t) = tau_p {
            sigma += t;
        }
    }
    sigma
}

/// The elastic stress as it enters sigma under EVSS (Phi and its trace term), which is what the
/// wall's zero-normal-elastic-stress condition removes.
#[inline]
pub fn evss_elastic_part<const N: usize>(
    evss: &Evss,
    tau_p: &Tensor<N>,
    kappa: &Tensor<N>,
) -> Tensor<N> {
    evss.phi(tau_p, kappa) + Tensor::identity() * (evss.added_viscosity() * kappa.trace())
}

/// Morris, Fox & Zhu 1997's viscous Laplacian, pair term (per unit mass of j):
/// (mu_i + mu_j) x_ij . grad W_ij / (rho_i rho_j (r^2 + eta^2)) v_ij.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn morris_pair<const N: usize>(
    vij: &Vector<N>,
    xij: &Vector<N>,
    grad: &Vector<N>,
    mu_sum: f64,
    rho_i: f64,
    rho_j: f64,
    r2: f64,
    eta2: f64,
) -> Vector<N> {
    vij * (mu_sum * xij.dot(grad) / (rho_i * rho_j * (r2 + eta2)))
}
