//! Constitutive models as strain and relaxation functions (King & Lind 2021, Table I), plus
//! generalized-Newtonian viscosity (the Cross model of Ren 2015).
//!
//! The polymer stress is tau_p = (eta_p / lambda) f_S(A) (King & Lind eq. 9) and the conformation
//! tensor obeys the upper-convected equation dA/dt = kappa A + A kappa^T - f_R(A) / lambda
//! (eqs. 10-11), with kappa_ab = d v_a / d x_b (Fang 2006 eq. 23). A scheme only calls this trait,
//! so adding a model is adding a file: the scheme never changes.
//!
//! Fang 2006 evolves the elastic stress S directly (eq. 28); for Oldroyd-B, S = (eta_p/lambda)(A - I)
//! turns eq. (28) into exactly the conformation equation above, so one formulation serves both
//! papers.

mod newtonian;
mod oldroyd_b;

pub use newtonian::Newtonian;
pub use oldroyd_b::OldroydB;

use crate::config::{ConformationMethod, RheologyKind, SceneConfig};
use crate::Mat2;

/// A constitutive model. `ELASTIC = false` models (Newtonian, Cross) carry no conformation
/// tensor: schemes test the constant, so the tensor work compiles away for them.
pub trait Rheology: Send + Sync + Clone + std::fmt::Debug + 'static {
    /// Whether the model has a conformation tensor (a polymer stress).
    const ELASTIC: bool;
    /// Viscosity of the Newtonian (solvent) part [Pa s] given the velocity gradient
    /// kappa_ab = d v_a / d x_b. Constant for most models; shear-rate dependent for Cross.
    fn solvent_viscosity(&self, kappa: &Mat2) -> f64;
    /// Largest value `solvent_viscosity` can take plus the polymer viscosity [Pa s]: what the
    /// viscous time-step limit (Fang 2006 eq. 53) must respect.
    fn max_viscosity(&self) -> f64;
    /// Polymer modulus eta_p / lambda [Pa] (0 for inelastic models).
    fn modulus(&self) -> f64;
    /// Relaxation time lambda [s] (infinite for inelastic models).
    fn relaxation_time(&self) -> f64;
    /// Strain function f_S(A) (King & Lind Table I).
    fn strain(&self, a: &Mat2) -> Mat2;
    /// Relaxation function f_R(A) (King & Lind Table I).
    fn relax(&self, a: &Mat2) -> Mat2;

    /// Polymer stress tau_p = (eta_p / lambda) f_S(A) (King & Lind eq. 9).
    #[inline]
    fn polymer_stress(&self, a: &Mat2) -> Mat2 {
        self.strain(a) * self.modulus()
    }
}

/// Right-hand side of the conformation equation: kappa A + A kappa^T - f_R(A) / lambda
/// (King & Lind eqs. 10-11 in the Lagrangian frame).
#[inline]
pub fn conformation_rate<R: Rheology>(model: &R, a: &Mat2, kappa: &Mat2) -> Mat2 {
    kappa * a + a * kappa.transpose() - model.relax(a) / model.relaxation_time()
}

/// Advance the conformation tensor by `dt`: from `a_base`, with rates evaluated at `a_eval` and
/// the velocity gradient `kappa`. A predictor-corrector (Fang 2006 eqs. 49-50) calls this with
/// a_eval = a_base for the half step, then with a_eval = A^{n+1/2} for the full step.
#[inline]
pub fn advance<R: Rheology>(
    method: ConformationMethod,
    model: &R,
    a_base: &Mat2,
    a_eval: &Mat2,
    kappa: &Mat2,
    dt: f64,
) -> Mat2 {
    match method {
        ConformationMethod::Direct | ConformationMethod::Log => {
            let mut a = a_base + conformation_rate(model, a_eval, kappa) * dt;
            // Keep exact symmetry against round-off.
            let off = 0.5 * (a[(0, 1)] + a[(1, 0)]);
            a[(0, 1)] = off;
            a[(1, 0)] = off;
            a
        }
    }
}

/// Whether a rheology can be built yet.
pub fn is_implemented(kind: RheologyKind) -> bool {
    matches!(
        kind,
        RheologyKind::Newtonian | RheologyKind::OldroydB | RheologyKind::Ucm
    )
}

/// Every model, resolved once from the configuration. Schemes are instantiated per variant
/// through [`dispatch_rheology!`], so hot loops see a concrete type.
#[derive(Debug, Clone)]
pub enum AnyRheology {
    Newtonian(Newtonian),
    OldroydB(OldroydB),
}

impl AnyRheology {
    /// Build the configured model. UCM is Oldroyd-B with no solvent (beta = 0).
    pub fn from_config(cfg: &SceneConfig) -> Result<Self, crate::config::ConfigError> {
        let eta0 = cfg.viscosity;
        let beta = cfg.viscosity_ratio;
        let lambda = cfg.relaxation_time;
        Ok(match cfg.rheology {
            RheologyKind::Newtonian => AnyRheology::Newtonian(Newtonian::new(eta0)),
            RheologyKind::OldroydB => AnyRheology::OldroydB(OldroydB::new(eta0, beta, lambda)),
            RheologyKind::Ucm => AnyRheology::OldroydB(OldroydB::new(eta0, 0.0, lambda)),
            other => {
                return Err(crate::config::ConfigError::Inconsistent(format!(
                    "rheology '{other}' is not implemented yet"
                )))
            }
        })
    }
}

/// Run `$body` with `$m` bound to the concrete model inside an [`AnyRheology`].
#[macro_export]
macro_rules! dispatch_rheology {
    ($any:expr, $m:ident => $body:expr) => {
        match $any {
            $crate::rheology::AnyRheology::Newtonian($m) => $body,
            $crate::rheology::AnyRheology::OldroydB($m) => $body,
        }
    };
}
