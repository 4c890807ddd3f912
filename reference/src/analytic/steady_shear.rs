//! Steady fully developed channel flow of the constitutive models of King & Lind 2021 Table I
//! (and Newtonian), driven by the body force of the `channel` scene.
//!
//! **Momentum.** At steady state rho g + d tau/dy = 0 with tau = 0 on the centre line, so the
//! total shear stress is known exactly whatever the model: tau(y) = rho g (H/2 - y). At each y
//! the local flow is steady simple shear at the (unknown) rate gamma = du/dy, and
//! tau = eta_s gamma + tau_p,xy(gamma).
//!
//! **Steady simple shear, parametrised by the polymer shear stress.** With the modulus
//! G = eta_p / lambda, Wi = lambda gamma and T = tau_p,xy / G, every model of Table I
//! (tau_p = G f_S(A), upper-convected dA/dt = -f_R(A)/lambda) gives Wi and the normal stresses as
//! explicit functions of T (derived from the xx, xy, yy components of the steady conformation
//! equation; A_yy, A_xy, A_xx are eliminated):
//!
//! | model | Wi(T) | tau_p,xx / G | tau_p,yy / G |
//! |---|---|---|---|
//! | Oldroyd-B, UCM | T | 2 T^2 | 0 |
//! | FENE-CR | T | 2 T^2 phi, phi = 2(1 - 2/L^2) / (1 + sqrt(1 + 8 T^2 (1 - 2/L^2)/L^2)) | 0 |
//! | FENE-P | T (1 + (2 + 2 T^2)/L^2) | 2 T^2 | 0 |
//! | linear PTT | T (1 + 2 eps T^2) | 2 T^2 | 0 |
//! | exponential PTT | T exp(2 eps T^2) | 2 T^2 | 0 |
//! | Giesekus | T (1 + alpha (X + Y)) / (1 + Y) | X | Y |
//!
//! For Giesekus, the yy component Y + alpha (T^2 + Y^2) = 0 gives
//! Y = -2 alpha T^2 / (1 + sqrt(1 - 4 alpha^2 T^2)), and eliminating Wi between the xy and xx
//! components leaves a quadratic alpha X^2 + b X + c = 0 with b = 1 - 2 alpha T^2 / (1 + Y),
//! c = alpha T^2 - 2 T^2 (1 + alpha Y)/(1 + Y) < 0, whose positive root is X. Y reaches -1 (and Wi
//! infinity) at T_max = sqrt((1 - alpha)/alpha): the largest polymer shear stress a Giesekus fluid
//! carries: with beta = 0 (the case of Yoo & Choi 1989 that King & Lind use) a steady channel
//! flow exists only if the wall stress is below T_max G. With a solvent the flow curve
//! T + beta/(1 - beta) Wi(T) rises without bound, so a solution exists for every wall stress
//! (the case Schleiniger & Weinberger 1991 analyse). Wi(T) >= T (the model thins in shear).
//!
//! **Solving for T at each y.** r = tau(y) / G = T + beta/(1 - beta) Wi(T), increasing in T:
//! beta = 0: T = r; Oldroyd-B, FENE-CR: T = (1 - beta) r; FENE-P and linear PTT: a cubic
//! p T^3 + q T = r with p, q > 0 (Cruz, Pinho & Oliveira 2005; Oliveira & Pinho 1999), solved
//! by the hyperbolic form of Cardano's formula, T = 2 sqrt(q/3p) sinh(asinh((3r/2q)
//! sqrt(3p/q)) / 3), which has no cancellation, then one Newton step; exponential PTT and
//! Giesekus with beta > 0: bisection on the bracket [0, min(r/(1 + beta/(1-beta)), T_max)] (Wi >= T
//! for these shear-thinning models) down to adjacent floating-point numbers.
//!
//! **Velocity.** u(y) = int_0^y gamma dy'. Changing variable to the stress (dy = -d tau / rho g)
//! and splitting tau into its solvent and polymer parts,
//!
//! ```text
//! u(y) = [ (eta_p / lambda^2) (I(T_w) - I(T(y))) + eta_s (gamma_w^2 - gamma(y)^2) / 2 ] / (rho g),
//! I(T) = int_0^T Wi(T') dT'
//! ```
//!
//! (subscript w: at the wall). I is a polynomial or exponential in closed form for every model
//! but Giesekus (Oldroyd-B, FENE-CR: T^2/2; FENE-P: (1 + 2/L^2) T^2/2 + T^4/(2 L^2); linear PTT:
//! T^2/2 + eps T^4/2; exponential PTT: expm1(2 eps T^2) / (4 eps)), so the velocity is exact to
//! round-off. For Giesekus, by parts, I(T) = T Wi - int_0^Wi T(w) dw with the closed-form flow
//! curve T(w) of Giesekus 1982 (bounded and smooth), integrated by the adaptive 20-point
//! Gauss-Legendre rule on the panels [0, 1], [1, 2], [2, 4], ... to 1e-14 absolute per panel.
//! The flow rate Q = 2 int_0^{H/2} u dy is integrated with the same adaptive rule in y to
//! 1e-13 U H.

use super::quadrature;
use super::{AnalyticError, Channel};
use viscosph::config::RheologyKind;
use viscosph::scene::SceneConfig;

/// A constitutive model with its own parameter (King & Lind 2021 Table I; names as in
/// the parameter table: `fene_L2`, `ptt_epsilon`, `giesekus_alpha`). UCM is [`SteadyModel::OldroydB`]
/// with beta = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SteadyModel {
    Newtonian,
    OldroydB,
    FeneCr { l2: f64 },
    FeneP { l2: f64 },
    PttLinear { epsilon: f64 },
    PttExponential { epsilon: f64 },
    Giesekus { alpha: f64 },
}

impl SteadyModel {
    /// Wi = lambda gamma as a function of T = tau_p,xy / G (table of the module documentation).
    pub fn weissenberg_of_stress(&self, t: f64) -> f64 {
        match *self {
            SteadyModel::Newtonian | SteadyModel::OldroydB | SteadyModel::FeneCr { .. } => t,
            SteadyModel::FeneP { l2 } => t * (1.0 + (2.0 + 2.0 * t * t) / l2),
            SteadyModel::PttLinear { epsilon } => t * (1.0 + 2.0 * epsilon * t * t),
            SteadyModel::PttExponential { epsilon } => t * (2.0 * epsilon * t * t).exp(),
            SteadyModel::Giesekus { alpha } => giesekus(alpha, t).0,
        }
    }

    /// (tau_p,xx / G, tau_p,yy / G) as functions of T = tau_p,xy / G.
    pub fn normal_stresses_of_stress(&self, t: f64) -> (f64, f64) {
        match *self {
            SteadyModel::Newtonian => (0.0, 0.0),
            SteadyModel::FeneCr { l2 } => {
                let k = 1.0 - 2.0 / l2;
                let phi = 2.0 * k / (1.0 + (1.0 + 8.0 * t * t * k / l2).sqrt());
                (2.0 * t * t * phi, 0.0)
            }
            SteadyModel::Giesekus { alpha } => {
                let (_, x, y) = giesekus(alpha, t);
                (x, y)
            }
            _ => (2.0 * t * t, 0.0),
        }
    }

    /// Largest polymer shear stress / G the model sustains in steady shear (infinite except for
    /// Giesekus: sqrt((1 - alpha)/alpha)).
    pub fn max_stress(&self) -> f64 {
        match *self {
            SteadyModel::Giesekus { alpha } if alpha > 0.0 => ((1.0 - alpha) / alpha).sqrt(),
            _ => f64::INFINITY,
        }
    }

    /// I(T) = int_0^T Wi(T') dT' (module documentation).
    fn int_weissenberg(&self, t: f64) -> f64 {
        let t2 = t * t;
        match *self {
            SteadyModel::Newtonian | SteadyModel::OldroydB | SteadyModel::FeneCr { .. } => 0.5 * t2,
            SteadyModel::FeneP { l2 } => 0.5 * (1.0 + 2.0 / l2) * t2 + 0.5 * t2 * t2 / l2,
            SteadyModel::PttLinear { epsilon } => 0.5 * t2 + 0.5 * epsilon * t2 * t2,
            SteadyModel::PttExponential { epsilon } => {
                if epsilon == 0.0 {
                    0.5 * t2
                } else {
                    (2.0 * epsilon * t2).exp_m1() / (4.0 * epsilon)
                }
            }
            SteadyModel::Giesekus { alpha } => {
                let wi = giesekus(alpha, t).0;
                if alpha == 0.0 {
                    return 0.5 * t2;
                }
                // By parts: T Wi - int_0^Wi T(w) dw on dyadic panels.
                let mut f = |w: f64| giesekus_flow_curve(alpha, w);
                let mut sum = 0.0;
                let (mut lo, mut hi) = (0.0, 1.0f64.min(wi));
                while lo < wi {
                    sum += quadrature::adaptive(&mut f, lo, hi, 1e-14, 1);
                    lo = hi;
                    hi = (2.0 * hi).min(wi);
                }
                t * wi - sum
            }
        }
    }

    fn name(&self) -> &'static str {
        match self {
            SteadyModel::Newtonian => "newtonian",
            SteadyModel::OldroydB => "oldroyd_b",
            SteadyModel::FeneCr { .. } => "fene_cr",
            SteadyModel::FeneP { .. } => "fene_p",
            SteadyModel::PttLinear { .. } => "ptt_linear",
            SteadyModel::PttExponential { .. } => "ptt_exponential",
            SteadyModel::Giesekus { .. } => "giesekus",
        }
    }
}

/// Giesekus steady shear from T = tau_p,xy / G: (Wi, tau_p,xx / G, tau_p,yy / G), module
/// documentation. alpha = 0 gives Oldroyd-B exactly (the roots are written without 1/alpha).
fn giesekus(alpha: f64, t: f64) -> (f64, f64, f64) {
    let t2 = t * t;
    let disc = 1.0 - 4.0 * alpha * alpha * t2;
    if disc < 0.0 {
        return (f64::INFINITY, f64::INFINITY, -1.0);
    }
    let y = -2.0 * alpha * t2 / (1.0 + disc.sqrt());
    let b = 1.0 - 2.0 * alpha * t2 / (1.0 + y);
    let c = alpha * t2 - 2.0 * t2 * (1.0 + alpha * y) / (1.0 + y);
    let d = (b * b - 4.0 * alpha * c).sqrt();
    let x = if b > 0.0 {
        -2.0 * c / (b + d)
    } else {
        (d - b) / (2.0 * alpha)
    };
    let wi = t * (1.0 + alpha * (x + y)) / (1.0 + y);
    (wi, x, y)
}

/// Giesekus flow curve T(Wi) = tau_p,xy / G in closed form (Giesekus 1982; Bird, Armstrong &
/// Hassager 1987 vol. 1): T = Wi (1 - f)^2 / (1 + (1 - 2 alpha) f),
/// f = (1 - chi) / (1 + (1 - 2 alpha) chi), chi^2 = (sqrt(1 + 16 alpha (1 - alpha) Wi^2) - 1) /
/// (8 alpha (1 - alpha) Wi^2), written as 2 / (sqrt(1 + 2k) + 1) against cancellation.
pub fn giesekus_flow_curve(alpha: f64, wi: f64) -> f64 {
    let k = 8.0 * alpha * (1.0 - alpha) * wi * wi;
    let chi = (2.0 / ((1.0 + 2.0 * k).sqrt() + 1.0)).sqrt();
    let f = (1.0 - chi) / (1.0 + (1.0 - 2.0 * alpha) * chi);
    wi * (1.0 - f) * (1.0 - f) / (1.0 + (1.0 - 2.0 * alpha) * f)
}

/// Steady state at one height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyPoint {
    /// Velocity u(y) \[m/s\].
    pub velocity: f64,
    /// Shear rate du/dy \[1/s\].
    pub shear_rate: f64,
    /// Total shear stress rho g (H/2 - y) \[Pa\].
    pub tau_xy: f64,
    /// Polymer stress components \[Pa\].
    pub tau_p_xy: f64,
    pub tau_p_xx: f64,
    pub tau_p_yy: f64,
}

/// The steady channel flow of one model. See the module documentation.
#[derive(Debug, Clone)]
pub struct SteadyChannel {
    ch: Channel,
    model: SteadyModel,
    /// The flow is Newtonian with viscosity eta0 (Newtonian model, lambda = 0 or beta = 1).
    viscous: bool,
    /// G = eta_p / lambda.
    modulus: f64,
    /// T at the wall, Wi at the wall and I(T_w).
    t_w: f64,
    wi_w: f64,
    i_w: f64,
}

impl SteadyChannel {
    /// The steady flow of `model` in the channel `ch`. Fails on out-of-range model parameters
    /// (FENE L^2 <= 2, eps < 0, alpha outside [0, 1/2]) and when no steady state exists
    /// (Giesekus, beta = 0, wall stress above sqrt((1 - alpha)/alpha) eta_p / lambda).
    pub fn new(ch: Channel, model: SteadyModel) -> Result<Self, AnalyticError> {
        ch.check()?;
        let bad = |name, value, allowed| {
            Err(AnalyticError::Parameter {
                name,
                value,
                allowed,
            })
        };
        match model {
            SteadyModel::FeneCr { l2 } | SteadyModel::FeneP { l2 } if l2.is_nan() || l2 <= 2.0 => {
                return bad("fene_L2", l2, "> 2")
            }
            SteadyModel::PttLinear { epsilon } | SteadyModel::PttExponential { epsilon }
                if !(epsilon >= 0.0 && epsilon.is_finite()) =>
            {
                return bad("ptt_epsilon", epsilon, ">= 0")
            }
            SteadyModel::Giesekus { alpha } if !(0.0..=0.5).contains(&alpha) => {
                return bad("giesekus_alpha", alpha, "0 <= alpha <= 1/2")
            }
            _ => {}
        }
        let viscous = model == SteadyModel::Newtonian
            || ch.relaxation_time == 0.0
            || ch.viscosity_ratio >= 1.0;
        let mut s = Self {
            ch,
            model,
            viscous,
            modulus: 0.0,
            t_w: 0.0,
            wi_w: 0.0,
            i_w: 0.0,
        };
        if !viscous {
            s.modulus = (1.0 - ch.viscosity_ratio) * ch.viscosity / ch.relaxation_time;
            let r_w = ch.steady_wall_shear_stress() / s.modulus;
            if ch.viscosity_ratio == 0.0 && r_w >= model.max_stress() {
                return Err(AnalyticError::NoSteadyState {
                    wall: ch.steady_wall_shear_stress(),
                    max: model.max_stress() * s.modulus,
                });
            }
            s.t_w = s.solve(r_w);
            s.wi_w = model.weissenberg_of_stress(s.t_w);
            s.i_w = model.int_weissenberg(s.t_w);
        }
        Ok(s)
    }

    /// From the scene's configuration (`rheology`, `density`, `viscosity`, `viscosity_ratio`,
    /// `relaxation_time`, `fene_L2`, `ptt_epsilon`, `giesekus_alpha`) and the channel's width and
    /// body force. UCM is Oldroyd-B with beta = 0; Cross is not covered.
    pub fn from_config(
        cfg: &SceneConfig,
        width: f64,
        body_force: f64,
    ) -> Result<Self, AnalyticError> {
        let mut ch = Channel::from_config(cfg, width, body_force);
        let model = match cfg.fluid.rheology {
            RheologyKind::Newtonian => {
                ch.viscosity_ratio = 1.0;
                ch.relaxation_time = 0.0;
                SteadyModel::Newtonian
            }
            RheologyKind::OldroydB => SteadyModel::OldroydB,
            RheologyKind::Ucm => {
                ch.viscosity_ratio = 0.0;
                SteadyModel::OldroydB
            }
            RheologyKind::FeneCr => SteadyModel::FeneCr {
                l2: cfg.fluid.fene_L2,
            },
            RheologyKind::FeneP => SteadyModel::FeneP {
                l2: cfg.fluid.fene_L2,
            },
            RheologyKind::PttLinear => SteadyModel::PttLinear {
                epsilon: cfg.fluid.ptt_epsilon,
            },
            RheologyKind::PttExponential => SteadyModel::PttExponential {
                epsilon: cfg.fluid.ptt_epsilon,
            },
            RheologyKind::Giesekus => SteadyModel::Giesekus {
                alpha: cfg.fluid.giesekus_alpha,
            },
            RheologyKind::Cross => {
                return Err(AnalyticError::Unsupported {
                    model: "cross",
                    what: "steady channel",
                })
            }
        };
        Self::new(ch, model)
    }

    /// The channel and fluid parameters.
    pub fn channel(&self) -> &Channel {
        &self.ch
    }

    /// The model.
    pub fn model(&self) -> SteadyModel {
        self.model
    }

    /// Polymer modulus G = eta_p / lambda \[Pa\] (0 for a viscous flow).
    pub fn modulus(&self) -> f64 {
        self.modulus
    }

    /// T solving T + beta/(1 - beta) Wi(T) = r (module documentation).
    fn solve(&self, r: f64) -> f64 {
        let beta = self.ch.viscosity_ratio;
        if r == 0.0 {
            return 0.0;
        }
        if beta == 0.0 {
            return r;
        }
        let c1 = beta / (1.0 - beta);
        let cubic = |p: f64, q: f64| {
            if p == 0.0 {
                return r / q;
            }
            let k = (q / (3.0 * p)).sqrt();
            let mut t = 2.0 * k * ((1.5 * r / q / k).asinh() / 3.0).sinh();
            t -= (p * t * t * t + q * t - r) / (3.0 * p * t * t + q);
            t
        };
        match self.model {
            SteadyModel::Newtonian | SteadyModel::OldroydB | SteadyModel::FeneCr { .. } => {
                r / (1.0 + c1)
            }
            SteadyModel::FeneP { l2 } => cubic(2.0 * c1 / l2, 1.0 + c1 * (1.0 + 2.0 / l2)),
            SteadyModel::PttLinear { epsilon } => cubic(2.0 * c1 * epsilon, 1.0 + c1),
            SteadyModel::PttExponential { .. } | SteadyModel::Giesekus { .. } => {
                let hi = (r / (1.0 + c1)).min(self.model.max_stress());
                bisect(
                    |t| t + c1 * self.model.weissenberg_of_stress(t) - r,
                    0.0,
                    hi,
                )
            }
        }
    }

    /// The steady state at height y (0 <= y <= H).
    pub fn at(&self, y: f64) -> SteadyPoint {
        let ch = &self.ch;
        let h = ch.width;
        let rg = ch.density * ch.body_force;
        let tau = rg * (0.5 * h - y);
        let sign = if tau < 0.0 { -1.0 } else { 1.0 };
        if self.viscous {
            let eta_p = if self.model == SteadyModel::Newtonian {
                0.0
            } else {
                (1.0 - ch.viscosity_ratio) * ch.viscosity
            };
            let gamma = tau / ch.viscosity;
            return SteadyPoint {
                velocity: rg * y * (h - y) / (2.0 * ch.viscosity),
                shear_rate: gamma,
                tau_xy: tau,
                tau_p_xy: eta_p * gamma,
                tau_p_xx: 0.0,
                tau_p_yy: 0.0,
            };
        }
        let lambda = ch.relaxation_time;
        let eta_s = ch.viscosity_ratio * ch.viscosity;
        let g = self.modulus;
        let t = self.solve(tau.abs() / g);
        let wi = self.model.weissenberg_of_stress(t);
        let (txx, tyy) = self.model.normal_stresses_of_stress(t);
        let gamma = wi / lambda;
        let gamma_w = self.wi_w / lambda;
        let velocity = ((g / lambda) * (self.i_w - self.model.int_weissenberg(t))
            + 0.5 * eta_s * (gamma_w * gamma_w - gamma * gamma))
            / rg;
        SteadyPoint {
            velocity,
            shear_rate: sign * gamma,
            tau_xy: tau,
            tau_p_xy: sign * g * t,
            tau_p_xx: g * txx,
            tau_p_yy: g * tyy,
        }
    }

    /// Velocity u(y) \[m/s\].
    pub fn velocity(&self, y: f64) -> f64 {
        self.at(y).velocity
    }

    /// Centre-line velocity u(H/2) \[m/s\].
    pub fn centreline_velocity(&self) -> f64 {
        self.velocity(0.5 * self.ch.width)
    }

    /// Total wall shear stress rho g H / 2 \[Pa\] (every model).
    pub fn wall_shear_stress_total(&self) -> f64 {
        self.ch.steady_wall_shear_stress()
    }

    /// Polymer part of the wall shear stress \[Pa\].
    pub fn wall_shear_stress_polymer(&self) -> f64 {
        self.at(0.0).tau_p_xy
    }

    /// Flow rate per unit depth int_0^H u dy \[m2/s\].
    pub fn flow_rate(&self) -> f64 {
        let h = self.ch.width;
        let tol = 1e-13 * self.ch.velocity_scale() * h;
        2.0 * quadrature::adaptive(&mut |y| self.velocity(y), 0.0, 0.5 * h, 0.5 * tol, 4)
    }

    /// The model name (config spelling).
    pub fn model_name(&self) -> &'static str {
        self.model.name()
    }
}

/// Root of an increasing f on [lo, hi] with f(lo) <= 0 by bisection down to adjacent
/// floating-point numbers (f may be infinite or NaN at hi: treated as positive).
fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..2000 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        let v = f(mid);
        if v.is_nan() || v > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytic::WatersKing;
    use viscosph::rheology::{
        conformation_rate, FeneCr, FeneP, Giesekus, OldroydB, PttExponential, PttLinear, Rheology,
    };
    use viscosph::Mat2;

    /// King & Lind section IV.A channel: Re = Wi = 1 (H = U = rho = 1, g = 8, eta0 = 1,
    /// lambda = 1).
    fn kl(beta: f64) -> Channel {
        Channel::from_re_wi(1.0, 1.0, beta)
    }

    fn heights() -> [f64; 6] {
        [0.0, 0.05, 0.2, 0.37, 0.5, 0.8]
    }

    /// The models of the cross-checks, with King & Lind's parameters where they give them.
    fn models() -> Vec<SteadyModel> {
        vec![
            SteadyModel::OldroydB,
            SteadyModel::FeneCr { l2: 100.0 },
            SteadyModel::FeneCr { l2: 10.0 },
            SteadyModel::FeneP { l2: 100.0 },
            SteadyModel::FeneP { l2: 10.0 },
            SteadyModel::PttLinear { epsilon: 0.25 },
            SteadyModel::PttExponential { epsilon: 0.05 },
            SteadyModel::PttExponential { epsilon: 0.25 },
            SteadyModel::Giesekus { alpha: 0.1 },
            SteadyModel::Giesekus { alpha: 0.5 },
        ]
    }

    /// Every (channel, model) pair the cross-checks run: King & Lind's Re = Wi = 1 channel at
    /// beta = 0, 0.1, 0.5 (Giesekus at beta = 0 has no steady state there: the wall stress 4 G
    /// exceeds sqrt((1 - alpha)/alpha) G), plus Giesekus at beta = 0 in their Fig. 8 channel
    /// (Re = 1, Wi = 0.25).
    fn cases() -> Vec<(Channel, SteadyModel)> {
        let mut out = Vec::new();
        for beta in [0.0, 0.1, 0.5] {
            for m in models() {
                if !(beta == 0.0 && matches!(m, SteadyModel::Giesekus { .. })) {
                    out.push((kl(beta), m));
                }
            }
        }
        for alpha in [0.1, 0.3, 0.45] {
            out.push((
                Channel::from_re_wi(1.0, 0.25, 0.0),
                SteadyModel::Giesekus { alpha },
            ));
        }
        out
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    /// Root of an increasing function on [lo, hi] by plain bisection (independent of the
    /// module's solver).
    fn bisect_ref(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
        assert!(f(lo) <= 0.0 && f(hi) >= 0.0);
        for _ in 0..200 {
            let m = 0.5 * (lo + hi);
            if f(m) > 0.0 {
                hi = m
            } else {
                lo = m
            }
        }
        0.5 * (lo + hi)
    }

    #[test]
    fn oldroyd_b_ucm_and_newtonian_are_the_parabola() {
        for (model, beta) in [
            (SteadyModel::OldroydB, 0.1),
            (SteadyModel::OldroydB, 0.0),
            (SteadyModel::Newtonian, 0.1),
        ] {
            let s = SteadyChannel::new(kl(beta), model).unwrap();
            for y in heights() {
                let p = s.at(y);
                let eta = y;
                assert!(
                    (p.velocity - 4.0 * eta * (1.0 - eta)).abs() < 1e-14,
                    "{model:?} {y}"
                );
                assert!((p.shear_rate - 4.0 * (1.0 - 2.0 * eta)).abs() < 1e-13);
                assert!((p.tau_xy - 4.0 * (1.0 - 2.0 * eta)).abs() < 1e-14);
                if model == SteadyModel::OldroydB {
                    let eta_p = 1.0 - beta;
                    assert!((p.tau_p_xy - eta_p * p.shear_rate).abs() < 1e-13);
                    let txx = 2.0 * eta_p * p.shear_rate * p.shear_rate;
                    assert!((p.tau_p_xx - txx).abs() < 1e-12, "{} {txx}", p.tau_p_xx);
                    assert_eq!(p.tau_p_yy, 0.0);
                }
            }
            assert!(
                (s.flow_rate() - 2.0 / 3.0).abs() < 1e-13,
                "{}",
                s.flow_rate()
            );
            assert!((s.centreline_velocity() - 1.0).abs() < 1e-14);
        }
        // The steady state of the Waters & King solution.
        let s = SteadyChannel::new(kl(0.1), SteadyModel::OldroydB).unwrap();
        assert_eq!(s.at(0.0).tau_p_xx, 28.8);
        assert!((s.wall_shear_stress_polymer() - 3.6).abs() < 1e-14);
        let wk = WatersKing::new(kl(0.1)).unwrap();
        for y in heights() {
            assert!((wk.velocity(y, 300.0) - s.velocity(y)).abs() < 1e-12);
            let d = wk.shear_stress_polymer(y, 300.0) - s.at(y).tau_p_xy;
            assert!(d.abs() < 1e-12);
        }
    }

    /// Independent steady simple-shear stresses (tau_xy, tau_xx, tau_yy) at Wi = lambda gamma
    /// with G = 1: published closed forms and the steady-state algebra solved by bisection (as in
    /// `tests/rheology.rs`).
    fn reference_stresses(model: SteadyModel, wi: f64) -> (f64, f64, f64) {
        match model {
            SteadyModel::Newtonian => (0.0, 0.0, 0.0),
            SteadyModel::OldroydB => (wi, 2.0 * wi * wi, 0.0),
            SteadyModel::FeneCr { l2 } => {
                // A_yy = 1, A_xy = Wi/F, A_xx = 1 + 2 Wi^2/F^2, F = 1/(1 - tr A / L^2).
                let f = bisect_ref(
                    |f| f * (1.0 - (2.0 + 2.0 * wi * wi / (f * f)) / l2) - 1.0,
                    1.0,
                    1e6,
                );
                (wi, 2.0 * wi * wi / f, 0.0)
            }
            SteadyModel::FeneP { l2 } => {
                // L^2 f^3 - (L^2 + 2) f^2 - 2 Wi^2 = 0.
                let f = bisect_ref(
                    |f| l2 * f.powi(3) - (l2 + 2.0) * f * f - 2.0 * wi * wi,
                    1.0,
                    1e6,
                );
                (wi / f, 2.0 * wi * wi / (f * f), 0.0)
            }
            SteadyModel::PttLinear { epsilon } => {
                let s = 2.0 * epsilon * wi * wi;
                let h = bisect_ref(|h| h - 1.0 - s / (h * h), 1.0, 1.0 + s);
                (wi / h, 2.0 * wi * wi / (h * h), 0.0)
            }
            SteadyModel::PttExponential { epsilon } => {
                let s = 2.0 * epsilon * wi * wi;
                let f = |h: f64| h - (s / (h * h)).exp();
                let mut hi = 2.0;
                while f(hi) < 0.0 {
                    hi *= 2.0;
                }
                let h = bisect_ref(f, 1.0, hi);
                (wi / h, 2.0 * wi * wi / (h * h), 0.0)
            }
            SteadyModel::Giesekus { alpha } => {
                // Giesekus 1982; Bird, Armstrong & Hassager 1987: viscosity and Psi1 in terms of
                // chi and f; tau_yy from tau_yy + alpha (tau_xy^2 + tau_yy^2) = 0.
                let k = 8.0 * alpha * (1.0 - alpha) * wi * wi;
                let chi = (((1.0 + 2.0 * k).sqrt() - 1.0) / k).sqrt();
                let f = (1.0 - chi) / (1.0 + (1.0 - 2.0 * alpha) * chi);
                let txy = wi * (1.0 - f).powi(2) / (1.0 + (1.0 - 2.0 * alpha) * f);
                let n1 = 2.0 * f * (1.0 - alpha * f) / (alpha * (1.0 - f));
                let tyy = ((1.0 - 4.0 * alpha * alpha * txy * txy).sqrt() - 1.0) / (2.0 * alpha);
                (txy, n1 + tyy, tyy)
            }
        }
    }

    #[test]
    fn profiles_match_independent_closed_forms() {
        for (ch, model) in cases() {
            {
                let beta = ch.viscosity_ratio;
                let s = SteadyChannel::new(ch, model).unwrap();
                let g = s.modulus();
                let eta_s = beta * ch.viscosity;
                let mut worst: f64 = 0.0;
                for y in heights() {
                    let p = s.at(y);
                    // Momentum: eta_s gamma + tau_p,xy is the known total stress.
                    let tot = eta_s * p.shear_rate + p.tau_p_xy;
                    assert!((tot - p.tau_xy).abs() < 1e-12 * 4.0, "{model:?} {y}: {tot}");
                    let (txy, txx, tyy) =
                        reference_stresses(model, ch.relaxation_time * p.shear_rate.abs());
                    let sign = p.shear_rate.signum();
                    let e = [
                        (p.tau_p_xy - sign * g * txy).abs() / (g * txy.abs()).max(1e-300),
                        (p.tau_p_xx - g * txx).abs() / (g * txx).max(1e-300),
                        (p.tau_p_yy - g * tyy).abs() / (g * txy.abs()).max(1e-300),
                    ];
                    if y != 0.5 {
                        for ei in e {
                            worst = worst.max(ei);
                        }
                    } else {
                        assert!(p.tau_p_xy == 0.0 && p.tau_p_xx == 0.0 && p.shear_rate == 0.0);
                    }
                    // Velocity: the closed-form antiderivative against adaptive Gauss-Legendre
                    // quadrature of the shear rate, int_0^y gamma dy'.
                    if y > 0.0 {
                        let quad =
                            quadrature::adaptive(&mut |yy| s.at(yy).shear_rate, 0.0, y, 1e-13, 8);
                        assert!(
                            (quad - p.velocity).abs() < 1e-11,
                            "{model:?} beta {beta} y {y}: {quad} {}",
                            p.velocity
                        );
                    }
                }
                println!(
                    "{model:?} beta {beta}: u_c {:.10} Q {:.10} wall Wi {:.4}; worst relative \
                     stress difference to the closed form {worst:.1e}",
                    s.centreline_velocity(),
                    s.flow_rate(),
                    ch.relaxation_time * s.at(0.0).shear_rate
                );
                // Bisection to 200 halvings and closed forms with square roots: ~1e-13.
                assert!(worst < 1e-10, "{model:?} beta {beta}: {worst:e}");
            }
        }
    }

    /// Steady state of dA/dt = kappa A + A kappa^T - f_R(A)/lambda under the shear rate
    /// `gamma`, by classical RK4 from the model's rest state until |dA/dt| lambda < 1e-13 |A|
    /// or the increments drop below round-off.
    fn homogeneous_steady<R: Rheology>(model: &R, gamma: f64) -> Mat2 {
        let kappa = Mat2::new(0.0, gamma, 0.0, 0.0);
        let lambda = model.relaxation_time();
        let dt = lambda / (100.0 * (1.0 + lambda * gamma.abs()));
        let mut a = model.rest_conformation();
        let f = |a: &Mat2| conformation_rate(model, a, &kappa);
        for _ in 0..10_000_000 {
            let k1 = f(&a);
            if k1.norm() * lambda < 1e-13 * a.norm() {
                return a;
            }
            let k2 = f(&(a + k1 * (0.5 * dt)));
            let k3 = f(&(a + k2 * (0.5 * dt)));
            let k4 = f(&(a + k3 * dt));
            let next = a + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6.0);
            if next == a {
                // Increments below round-off: converged as far as this step size can tell.
                return a;
            }
            a = next;
        }
        panic!("no steady state");
    }

    fn check_against_rheology<R: Rheology>(s: &SteadyChannel, model: &R) -> f64 {
        let mut worst: f64 = 0.0;
        for y in [0.0, 0.1, 0.3] {
            let p = s.at(y);
            let tau = model.polymer_stress(&homogeneous_steady(model, p.shear_rate));
            let e = [
                rel(tau[(0, 1)], p.tau_p_xy),
                rel(tau[(0, 0)], p.tau_p_xx),
                (tau[(1, 1)] - p.tau_p_yy).abs() / p.tau_p_xy.abs(),
            ];
            for ei in e {
                worst = worst.max(ei);
            }
        }
        worst
    }

    #[test]
    fn profiles_match_the_constitutive_code() {
        for (ch, model) in cases() {
            {
                let beta = ch.viscosity_ratio;
                let s = SteadyChannel::new(ch, model).unwrap();
                let (eta0, lam) = (ch.viscosity, ch.relaxation_time);
                let worst = match model {
                    SteadyModel::Newtonian => 0.0,
                    SteadyModel::OldroydB => {
                        check_against_rheology(&s, &OldroydB::new(eta0, beta, lam))
                    }
                    SteadyModel::FeneCr { l2 } => {
                        check_against_rheology(&s, &FeneCr::new(eta0, beta, lam, l2))
                    }
                    SteadyModel::FeneP { l2 } => {
                        check_against_rheology(&s, &FeneP::new(eta0, beta, lam, l2))
                    }
                    SteadyModel::PttLinear { epsilon } => {
                        check_against_rheology(&s, &PttLinear::new(eta0, beta, lam, epsilon))
                    }
                    SteadyModel::PttExponential { epsilon } => {
                        check_against_rheology(&s, &PttExponential::new(eta0, beta, lam, epsilon))
                    }
                    SteadyModel::Giesekus { alpha } => {
                        check_against_rheology(&s, &Giesekus::new(eta0, beta, lam, alpha))
                    }
                };
                println!(
                    "{model:?} beta {beta}: worst relative difference to src/rheology {worst:.1e}"
                );
                assert!(worst < 1e-6, "{model:?} beta {beta}: {worst:e}");
            }
        }
    }

    #[test]
    fn limits_reduce_to_oldroyd_b() {
        for beta in [0.0, 0.1] {
            let ob = SteadyChannel::new(kl(beta), SteadyModel::OldroydB).unwrap();
            let same = [
                SteadyModel::PttLinear { epsilon: 0.0 },
                SteadyModel::PttExponential { epsilon: 0.0 },
                SteadyModel::Giesekus { alpha: 0.0 },
            ];
            let near = [
                SteadyModel::PttLinear { epsilon: 1e-9 },
                SteadyModel::PttExponential { epsilon: 1e-9 },
                SteadyModel::Giesekus { alpha: 1e-9 },
                SteadyModel::FeneP { l2: 1e10 },
                SteadyModel::FeneCr { l2: 1e10 },
            ];
            for (model, tol) in same
                .iter()
                .map(|m| (m, 1e-14))
                .chain(near.iter().map(|m| (m, 1e-6)))
            {
                let s = SteadyChannel::new(kl(beta), *model).unwrap();
                for y in heights() {
                    let (a, b) = (s.at(y), ob.at(y));
                    assert!(
                        (a.velocity - b.velocity).abs() < tol,
                        "{model:?} beta {beta} y {y}"
                    );
                    assert!((a.tau_p_xy - b.tau_p_xy).abs() < tol * 4.0);
                    assert!(
                        (a.tau_p_xx - b.tau_p_xx).abs() < tol * 30.0,
                        "{model:?} {y}"
                    );
                    assert!(a.tau_p_yy.abs() < tol);
                }
            }
            // FENE-CR has Oldroyd-B's viscosity at any L^2: the same velocity and shear stress,
            // a smaller normal stress.
            let cr = SteadyChannel::new(kl(beta), SteadyModel::FeneCr { l2: 10.0 }).unwrap();
            for y in heights() {
                let (a, b) = (cr.at(y), ob.at(y));
                assert!((a.velocity - b.velocity).abs() < 1e-14);
                assert!((a.tau_p_xy - b.tau_p_xy).abs() < 1e-14);
                if y != 0.5 {
                    assert!(a.tau_p_xx < b.tau_p_xx);
                }
            }
        }
    }

    #[test]
    fn shear_thinning_models_flow_faster() {
        // FENE-P, PTT and Giesekus thin in shear: more flow than Oldroyd-B under the same
        // pressure gradient, more for smaller L^2, larger eps or alpha (King & Lind Figs. 7, 8).
        let uc = |m| {
            SteadyChannel::new(kl(0.1), m)
                .unwrap()
                .centreline_velocity()
        };
        assert!(uc(SteadyModel::FeneP { l2: 10.0 }) > uc(SteadyModel::FeneP { l2: 100.0 }));
        assert!(uc(SteadyModel::FeneP { l2: 100.0 }) > 1.0);
        assert!(
            uc(SteadyModel::PttLinear { epsilon: 0.5 })
                > uc(SteadyModel::PttLinear { epsilon: 0.1 })
        );
        assert!(
            uc(SteadyModel::PttExponential { epsilon: 0.1 })
                > uc(SteadyModel::PttLinear { epsilon: 0.1 })
        );
        assert!(uc(SteadyModel::PttLinear { epsilon: 0.1 }) > 1.0);
        // Giesekus, beta = 0, Wi = 0.25, Re = 1 (King & Lind Fig. 8): the centre-line velocity
        // in units of the UCM one (U = 1) grows with alpha; at alpha = 1/2 the wall stress
        // reaches the largest the model carries and there is no steady flow.
        let fig8 = Channel::from_re_wi(1.0, 0.25, 0.0);
        let mut last = 1.0;
        for alpha in [0.0, 0.1, 0.2, 0.3, 0.4, 0.45] {
            let s = SteadyChannel::new(fig8, SteadyModel::Giesekus { alpha }).unwrap();
            let u = s.centreline_velocity();
            println!(
                "Giesekus Fig. 8 alpha {alpha}: u_c / U_UCM = {u:.6}, wall shear rate {:.4}",
                s.at(0.0).shear_rate
            );
            assert!(if alpha == 0.0 {
                (u - 1.0).abs() < 1e-14
            } else {
                u > last
            });
            last = u;
        }
        assert!(matches!(
            SteadyChannel::new(fig8, SteadyModel::Giesekus { alpha: 0.5 }),
            Err(AnalyticError::NoSteadyState { .. })
        ));
        // With a solvent there is always a steady flow.
        assert!(SteadyChannel::new(
            Channel::from_re_wi(1.0, 0.25, 0.01),
            SteadyModel::Giesekus { alpha: 0.5 }
        )
        .is_ok());
    }

    #[test]
    fn builds_from_the_scene_configuration() {
        let mut cfg = {
            let mut c = SceneConfig::default();
            c.fluid.density = 1.0;
            c.fluid.viscosity = 1.0;
            c.fluid.viscosity_ratio = 0.1;
            c.fluid.relaxation_time = 1.0;
            c.fluid.fene_L2 = 100.0;
            c.fluid.ptt_epsilon = 0.25;
            c.fluid.giesekus_alpha = 0.1;
            c
        };
        for (kind, model) in [
            (RheologyKind::FeneP, SteadyModel::FeneP { l2: 100.0 }),
            (RheologyKind::FeneCr, SteadyModel::FeneCr { l2: 100.0 }),
            (
                RheologyKind::PttLinear,
                SteadyModel::PttLinear { epsilon: 0.25 },
            ),
            (
                RheologyKind::PttExponential,
                SteadyModel::PttExponential { epsilon: 0.25 },
            ),
            (RheologyKind::Giesekus, SteadyModel::Giesekus { alpha: 0.1 }),
            (RheologyKind::OldroydB, SteadyModel::OldroydB),
            (RheologyKind::Ucm, SteadyModel::OldroydB),
            (RheologyKind::Newtonian, SteadyModel::Newtonian),
        ] {
            cfg.fluid.rheology = kind;
            let s = SteadyChannel::from_config(&cfg, 1.0, 8.0).unwrap();
            assert_eq!(s.model(), model);
            assert_eq!(
                s.model_name(),
                if kind == RheologyKind::Ucm {
                    "oldroyd_b"
                } else {
                    kind.as_str()
                }
            );
        }
        cfg.fluid.rheology = RheologyKind::Cross;
        assert!(SteadyChannel::from_config(&cfg, 1.0, 8.0).is_err());
        cfg.fluid.rheology = RheologyKind::FeneP;
        cfg.fluid.fene_L2 = 2.0;
        assert!(SteadyChannel::from_config(&cfg, 1.0, 8.0).is_err());
    }
}
