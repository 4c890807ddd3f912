//! Elasto-viscous stress splitting, EVSS (King & Lind 2021 eqs. 6-8).
//!
//! The polymer stress is split as Phi = tau_p - alpha_V eta0 2D (eq. 6), so that the extra stress
//! is tau = Phi + (beta + alpha_V) eta0 2D (eq. 7) and the momentum equation carries the viscous
//! term (beta + alpha_V) eta0 / rho lap(u) (eq. 8). The total stress is unchanged; what changes is
//! the discretisation: the added viscosity alpha_V eta0 goes through the scheme's compact viscous
//! (Laplacian) operator and is taken back out of the stress whose divergence is computed with first
//! derivatives. That damps the stress/velocity decoupling that makes beta -> 0 (UCM) unstable.
//!
//! `evss_alpha` is alpha_V / (1 - beta) (parameter table): 0 is no EVSS, 1 the standard EVSS
//! alpha_V = 1 - beta. Hence alpha_V eta0 = evss_alpha eta_p, which is 0 for inelastic models.
//!
//! # How a scheme uses it
//! Build once: `let evss = Evss::new(&model, cfg.evss_alpha);`. Then per particle and stage,
//! with the velocity gradient `kappa` of that stage and the polymer stress `tau_p`:
//! * the stress whose divergence the scheme takes with its first-derivative operator is
//!   `evss.phi(&tau_p, &kappa)` instead of `tau_p` (King & Lind step 3, eq. 24's div Phi);
//! * the viscous (Laplacian) term uses the viscosity
//!   `evss.viscous_viscosity(model.solvent_viscosity(&kappa))` = (beta + alpha_V) eta0 (eq. 8);
//! * physical outputs (wall force, the free-surface pressure of eq. 35a, diagnostics) use the
//!   physical stress tau_p + 2 eta_s D, not Phi;
//! * the viscous time-step limit uses `evss.viscous_viscosity(model.max_viscosity())` at most,
//!   which is never more than eta0 + eta_p.
//!
//! If a scheme discretises the solvent stress with the same operator as the polymer stress (Fang
//! 2006 eq. 27 takes the divergence of sigma = -p I + eta d + tau_p), then
//! Phi + (beta + alpha_V) eta0 2D = tau_p + beta eta0 2D particle by particle and EVSS is an exact
//! identity: it only acts once the viscous part goes through a Laplacian (King & Lind eq. 21 or
//! Morris' form).

use super::Rheology;
use crate::dim::Tensor;

/// The EVSS split of King & Lind eqs. (6)-(8), resolved for one model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evss {
    /// alpha_V eta0 [Pa s].
    added: f64,
}

impl Evss {
    /// EVSS for `model` with `evss_alpha` = alpha_V / (1 - beta). Inelastic models get none.
    pub fn new<R: Rheology>(model: &R, evss_alpha: f64) -> Self {
        let added = if R::ELASTIC {
            evss_alpha * model.polymer_viscosity()
        } else {
            0.0
        };
        Self { added }
    }

    /// No EVSS (alpha_V = 0).
    pub fn off() -> Self {
        Self { added: 0.0 }
    }

    /// Whether the split changes anything.
    pub fn is_on(&self) -> bool {
        self.added > 0.0
    }

    /// The added viscosity alpha_V eta0 [Pa s].
    #[inline]
    pub fn added_viscosity(&self) -> f64 {
        self.added
    }

    /// Viscosity of the Laplacian term, (beta + alpha_V) eta0 = eta_s + alpha_V eta0 (eq. 8), from
    /// the solvent viscosity `eta_s` (which may be shear-rate dependent).
    #[inline]
    pub fn viscous_viscosity(&self, eta_s: f64) -> f64 {
        eta_s + self.added
    }

    /// Phi = tau_p - alpha_V eta0 2D (eq. 6), with 2D = kappa + kappa^T and
    /// kappa_ab = d v_a / d x_b.
    #[inline]
    pub fn phi<const N: usize>(&self, tau_p: &Tensor<N>, kappa: &Tensor<N>) -> Tensor<N> {
        tau_p - (kappa + kappa.transpose()) * self.added
    }
}
