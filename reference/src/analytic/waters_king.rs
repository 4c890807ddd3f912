//! Start-up of plane Poiseuille flow of an Oldroyd-B fluid (Waters & King 1970), with the
//! Newtonian (lambda = 0) and UCM (beta = 0) limits.
//!
//! Walls at y = 0 and y = H, fluid at rest at t = 0, body force g along x from t = 0. The flow
//! stays unidirectional, u = u(y, t), and obeys
//!
//! ```text
//! rho du/dt = rho g + d tau/dy,            tau = eta_s du/dy + tau_p           (momentum)
//! lambda d tau_p/dt + tau_p = eta_p du/dy                                    (Oldroyd-B, xy)
//! lambda d tau_xx/dt + tau_xx = 2 lambda tau_p du/dy,  tau_yy = 0            (Oldroyd-B, xx, yy)
//! ```
//!
//! with eta_s = beta eta0, eta_p = (1 - beta) eta0 (King & Lind 2021 eqs. 3-11 in a parallel
//! flow). Scales: U = rho g H^2 / (8 eta0), viscous time t_v = rho H^2 / eta0, s = t / t_v,
//! elasticity E = lambda / t_v = Wi / Re, eta = y / H.
//!
//! **Velocity** (Waters & King 1970, in the notation of King & Lind's reference values): for the
//! odd multiples N = (2n - 1) pi, n = 1, 2, ...,
//!
//! ```text
//! u / U = 4 eta (1 - eta) - 32 sum_N sin(N eta) G_N(s) / N^3
//! G_N(s) = exp(-a s / 2E) [cosh(b s / 2E) + (c / b) sinh(b s / 2E)]
//! a = 1 + beta E N^2,  b^2 = a^2 - 4 E N^2,  c = 1 + (beta - 2) E N^2
//! ```
//!
//! (cos and sin of |b| s / 2E when b^2 < 0; G_N = exp(-N^2 s) when lambda = 0). Each mode is the
//! solution of E G'' + a G' + N^2 G = 0 with G(0) = 1, G'(0) = -N^2: the fluid starts at rest
//! with no polymer stress. Derivative: dG/ds = -N^2 exp(-a s/2E) [cosh - ((a - 2)/b) sinh].
//!
//! **Shear stresses** from the momentum balance (tau = 0 on the centre line by symmetry):
//! tau(y) = rho g (H/2 - y) - rho int_{H/2}^{y} du/dt dy', which gives
//!
//! ```text
//! tau   / (eta0 U / H) = 4 (1 - 2 eta) + 32 sum_N cos(N eta) G_N'(s) / N^4          (total)
//! tau_p / (eta0 U / H) = 4 (1 - beta)(1 - 2 eta) + 32 sum_N cos(N eta) [G_N'/N^4 + beta G_N/N^2]
//! du/dy / (U / H)       = 4 (1 - 2 eta) - 32 sum_N cos(N eta) G_N(s) / N^2
//! ```
//!
//! so tau_p = tau - eta_s du/dy. Using the momentum balance instead of differentiating the
//! velocity series keeps the stress series absolutely convergent even for UCM, where the velocity
//! gradient jumps across the shear wave and its own series converges only conditionally.
//!
//! **Normal stress**: tau_xx(y, t) = 2 int_0^t exp(-(t - t')/lambda) tau_p(y, t') du/dy(y, t') dt'
//! (the exact solution of the xx equation from tau_xx(0) = 0), integrated with the adaptive
//! 20-point Gauss-Legendre rule of [`quadrature::adaptive`] to a tolerance of `tolerance` times
//! the steady wall value 2 lambda eta_p (4 U/H)^2 (history older than 40 lambda, weighted by
//! exp(-40) < 5e-18, is dropped). At steady state tau_xx = 2 lambda eta_p (du/dy)^2.
//!
//! **Evaluation.** Naive cosh/sinh overflow for large N (a s / 2E grows like N^2). When b^2 > 0
//! the exponents are merged exactly: G = p exp(-sigma_s s) + q exp(-sigma_f s) with
//! p, q = (1 +- c/b)/2, sigma_s = 2 N^2 / (a + b) (written so, not as (a - b)/2E, to avoid
//! cancellation) and sigma_f = (a + b)/2E, both positive; near critical damping (b s/2E < 1/2) the
//! product form with sinh(z)/z is used instead, where nothing can overflow. For 0 < beta < 1
//! every mode tends to the same slow part ((beta - 1)/beta) exp(-s/(beta E)) as N grows (the
//! retardation time beta lambda); summed as it stands the series would converge only like its
//! weights (N^-2 for du/dy: 20,000 modes still leave 4e-5 in tau_p at early times). That common
//! part is summed in closed form and only the remainders are summed mode by mode (see
//! `sums`). Modes are added until the estimated tail of every series needed is below
//! `tolerance` (relative to U, U/H, eta0 U/H or U H; default 1e-10); `max_modes` (default
//! 20,000) caps the sum. Measured at Re = Wi = 1, beta = 0.1: 349, 299 and 45 modes for the
//! velocity at t = 0.001, 0.1 and 1, about 1,400 at t = 0.5 for the stresses (their fast parts
//! decay like exp(-beta N^2 s), so early times need more), 4 after t = 3. For UCM (beta = 0) the
//! terms decay only like N^-2 (the shear wave keeps every mode alive until exp(-s/2E) damps it)
//! and the velocity-gradient series converges only conditionally (du/dy jumps at the wave
//! front), so UCM velocities and stresses early in the start-up, and its tau_xx, are as
//! accurate as `max_modes` allows (with 100,000 modes, u = g t ahead of the front to 1e-8).

use super::quadrature;
use super::{AnalyticError, Channel};
use std::f64::consts::PI;
use viscosph::config::RheologyKind;
use viscosph::scene::SceneConfig;

/// A local extremum of the centre-line velocity in time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extremum {
    /// Time \[s\].
    pub time: f64,
    /// Centre-line velocity there \[m/s\].
    pub velocity: f64,
    /// Maximum (true) or minimum (false).
    pub maximum: bool,
}

/// The Waters & King solution for one channel and fluid. See the module documentation.
#[derive(Debug, Clone)]
pub struct WatersKing {
    ch: Channel,
    /// U = rho g H^2 / (8 eta0).
    u: f64,
    /// t_v = rho H^2 / eta0.
    tv: f64,
    /// E = lambda / t_v.
    e: f64,
    /// Upper edge, in E N^2, of the window of underdamped modes (infinite for UCM).
    x_plus: f64,
    tol: f64,
    max_modes: usize,
}

/// Which series a point evaluation needs.
#[derive(Debug, Clone, Copy, Default)]
struct Need {
    /// sum sin(N eta) G / N^3 (velocity).
    s3: bool,
    /// sum cos(N eta) G / N^2 (velocity gradient; polymer stress when beta > 0).
    s2: bool,
    /// sum cos(N eta) G' / N^4 (shear stresses).
    s4: bool,
    /// sum G / N^4 (flow rate).
    q4: bool,
}

#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    s3: f64,
    s2: f64,
    s4: f64,
    q4: f64,
    modes: usize,
}

/// One mode evaluated at s: G and dG/ds (less the common asymptote when one is subtracted) and
/// envelopes [slow |G|, fast |G|, slow |dG/ds|, fast |dG/ds|] for the tail estimate, meaningful
/// once `asymptotic` holds.
struct ModeAt {
    g: f64,
    dg: f64,
    env: [f64; 4],
    asymptotic: bool,
}

/// The common large-N slow part p exp(-sigma s) of every mode (0 < beta < 1), summed in closed
/// form; `on = false` (p = 0) otherwise.
#[derive(Debug, Clone, Copy, Default)]
struct Asymptote {
    on: bool,
    p: f64,
    sigma: f64,
    exp: f64,
}

/// All the point values of one evaluation.
#[derive(Debug, Clone, Copy)]
struct Point {
    u: f64,
    dudy: f64,
    tau: f64,
    tau_p: f64,
}

impl WatersKing {
    /// The solution for density rho, body force g, width H, zero-shear viscosity eta0, viscosity
    /// ratio beta (1 or lambda = 0: Newtonian; 0: UCM) and relaxation time lambda.
    pub fn new(ch: Channel) -> Result<Self, AnalyticError> {
        ch.check()?;
        let u = ch.velocity_scale();
        let tv = ch.density * ch.width * ch.width / ch.viscosity;
        let e = ch.relaxation_time / tv;
        let beta = ch.viscosity_ratio;
        let x_plus = if beta > 0.0 {
            ((1.0 + (1.0 - beta).sqrt()) / beta).powi(2)
        } else {
            f64::INFINITY
        };
        Ok(Self {
            ch,
            u,
            tv,
            e,
            x_plus,
            tol: 1e-10,
            max_modes: 20_000,
        })
    }

    /// From the scene's configuration (`density`, `viscosity`, `viscosity_ratio`,
    /// `relaxation_time`) and the channel's width and body force. Oldroyd-B as configured, UCM
    /// with beta = 0, Newtonian with lambda = 0; other models have no transient analytic solution.
    pub fn from_config(
        cfg: &SceneConfig,
        width: f64,
        body_force: f64,
    ) -> Result<Self, AnalyticError> {
        let mut ch = Channel::from_config(cfg, width, body_force);
        match cfg.fluid.rheology {
            RheologyKind::OldroydB => {}
            RheologyKind::Ucm => ch.viscosity_ratio = 0.0,
            RheologyKind::Newtonian => {
                ch.viscosity_ratio = 1.0;
                ch.relaxation_time = 0.0;
            }
            other => {
                return Err(AnalyticError::Unsupported {
                    model: other.as_str(),
                    what: "transient (Waters & King)",
                })
            }
        }
        Self::new(ch)
    }

    /// Truncation tolerance of the series (relative to the scale of each quantity).
    pub fn with_tolerance(mut self, tol: f64) -> Self {
        self.tol = tol;
        self
    }

    /// Largest number of modes summed.
    pub fn with_max_modes(mut self, max_modes: usize) -> Self {
        self.max_modes = max_modes.max(1);
        self
    }

    /// The channel and fluid parameters.
    pub fn channel(&self) -> &Channel {
        &self.ch
    }

    /// Steady centre-line velocity U = rho g H^2 / (8 eta0) \[m/s\].
    pub fn velocity_scale(&self) -> f64 {
        self.u
    }

    /// Viscous time t_v = rho H^2 / eta0 \[s\].
    pub fn viscous_time(&self) -> f64 {
        self.tv
    }

    /// Elasticity number E = lambda / t_v = Wi / Re.
    pub fn elasticity(&self) -> f64 {
        self.e
    }

    /// Whether mode n (N = (2n - 1) pi) is overdamped, b_N^2 >= 0: it then decays without
    /// oscillating. b^2 = (1 + beta x)^2 - 4x with x = E N^2 is negative exactly for
    /// x in (x-, x+), x+- = ((1 +- sqrt(1 - beta)) / beta)^2.
    pub fn mode_overdamped(&self, n: usize) -> bool {
        if self.e == 0.0 {
            return true;
        }
        let nn = (2 * n - 1) as f64 * PI;
        let a = 1.0 + self.ch.viscosity_ratio * self.e * nn * nn;
        a * a - 4.0 * self.e * nn * nn >= 0.0
    }

    /// Whether every mode is overdamped. For beta > 0 this holds when E pi^2 >= x+, i.e.
    /// E >= [`Self::overdamped_elasticity`] (the first mode is past the window and the others
    /// further), or when the window of underdamped x = E N^2 falls between two modes; for
    /// UCM (beta = 0) never (every mode with 4 E N^2 > 1 oscillates); for lambda = 0 always.
    pub fn all_modes_overdamped(&self) -> bool {
        if self.e == 0.0 {
            return true;
        }
        if !self.x_plus.is_finite() {
            return false;
        }
        // Modes with E N^2 >= x+ are overdamped; check the finitely many below.
        (1..)
            .take_while(|&n| {
                let nn = (2 * n - 1) as f64 * PI;
                self.e * nn * nn < self.x_plus
            })
            .all(|n| self.mode_overdamped(n))
    }

    /// The elasticity above which every mode is overdamped, E* = ((1 + sqrt(1 - beta)) /
    /// (beta pi))^2. It is below, and for small beta tends to, the 4 / (beta^2 pi^2) usually
    /// quoted: above it the centre-line velocity overshoots once and then decays without
    /// oscillating.
    pub fn overdamped_elasticity(beta: f64) -> f64 {
        ((1.0 + (1.0 - beta).sqrt()) / (beta * PI)).powi(2)
    }

    /// Mode n at s: G and dG/ds with the asymptotic slow part subtracted when 0 < beta < 1
    /// (see [`Self::sums`]), and envelopes for the tail estimate.
    fn mode_at(&self, n: usize, s: f64, asym: &Asymptote) -> (f64, ModeAt) {
        let nn = (2 * n - 1) as f64 * PI;
        let n2 = nn * nn;
        let e = self.e;
        let beta = self.ch.viscosity_ratio;
        if e == 0.0 {
            let g = (-n2 * s).exp();
            return (
                nn,
                ModeAt {
                    g,
                    dg: -n2 * g,
                    env: [0.0, g, 0.0, n2 * g],
                    asymptotic: true,
                },
            );
        }
        let a = 1.0 + beta * e * n2;
        let b2 = a * a - 4.0 * e * n2;
        let c = 1.0 + (beta - 2.0) * e * n2;
        let x = s / (2.0 * e);
        let (g, dg, env, asymptotic) = if b2 >= 0.0 && b2.sqrt() * x >= 0.5 {
            // Merged exponents: exp(-(a -+ b) x), with a - b = 4 E N^2 / (a + b).
            let b = b2.sqrt();
            let sig_s = 2.0 * n2 / (a + b);
            let sig_f = (a + b) / (2.0 * e);
            let (e1, e2) = ((-sig_s * s).exp(), (-sig_f * s).exp());
            let p = 0.5 * (1.0 + c / b);
            let q = 0.5 * (1.0 - c / b);
            let g = p * e1 + q * e2;
            let dg = -(p * sig_s * e1 + q * sig_f * e2);
            let env = if asym.on {
                // |p e1 - p_inf e_inf| <= |p - p_inf| e1 + |p_inf| |e_inf - e1|, both ~ N^-2
                // without sign changes; sigma_s - sigma_inf = 4 (1 - beta) N^2 /
                // (beta (a - 2 + b)(a + b)) written without cancellation.
                let dsig = if a - 2.0 + b > 1e-3 * a {
                    4.0 * (1.0 - beta) * n2 / (beta * (a - 2.0 + b) * (a + b))
                } else {
                    sig_s - asym.sigma
                };
                let de = (asym.exp * (-dsig * s).exp_m1()).abs();
                [
                    (p - asym.p).abs() * e1 + asym.p.abs() * de,
                    q.abs() * e2,
                    (p * sig_s - asym.p * asym.sigma).abs() * e1 + (asym.p * asym.sigma).abs() * de,
                    (q * sig_f).abs() * e2,
                ]
            } else {
                [
                    p.abs() * e1,
                    q.abs() * e2,
                    (p * sig_s).abs() * e1,
                    (q * sig_f).abs() * e2,
                ]
            };
            (g, dg, env, beta == 0.0 || e * n2 >= self.x_plus)
        } else if b2 >= 0.0 {
            // Near critical damping: exp(-a x) [cosh(bx) + c x shc(bx)], nothing large.
            let z = b2.sqrt() * x;
            let ea = (-a * x).exp();
            let ch = z.cosh();
            let shx = if z == 0.0 { x } else { x * z.sinh() / z };
            let g = ea * (ch + c * shx);
            let dg = -n2 * ea * (ch - (a - 2.0) * shx);
            let env = [
                ea * (ch + c.abs() * shx),
                0.0,
                n2 * ea * (ch + (a - 2.0).abs() * shx),
                0.0,
            ];
            (g, dg, env, false)
        } else {
            let w = (-b2).sqrt();
            let ea = (-a * x).exp();
            let (sn, cs) = (w * x).sin_cos();
            let sn = sn / w;
            let g = ea * (cs + c * sn);
            let dg = -n2 * ea * (cs - (a - 2.0) * sn);
            let m = x.min(1.0 / w);
            let env = [
                ea * (1.0 + c.abs() * m),
                0.0,
                n2 * ea * (1.0 + (a - 2.0).abs() * m),
                0.0,
            ];
            // Only UCM has oscillating modes for arbitrarily large N.
            (g, dg, env, beta == 0.0)
        };
        (
            nn,
            ModeAt {
                g: g - asym.p * asym.exp,
                dg: dg + asym.p * asym.sigma * asym.exp,
                env,
                asymptotic,
            },
        )
    }

    /// Estimated sum of |term| over all modes after the one of wavenumber N, for a term bounded
    /// by `bound` there that decays like N^-k: sum_{n > M} N^-k <= N_M^(1-k) / (2 pi (k - 1))
    /// (integral comparison), times bound N_M^k. Infinite when k <= 1: no absolute convergence
    /// to rely on.
    fn tail(bound: f64, nn: f64, k: f64) -> f64 {
        if k <= 1.0 {
            f64::INFINITY
        } else {
            bound * nn / (2.0 * PI * (k - 1.0))
        }
    }

    /// The four series at (eta, s), summed until the estimated tail of each one needed is below
    /// `tolerance` / 32.
    ///
    /// **Acceleration (0 < beta < 1).** For N -> infinity every mode tends to the same slow part
    /// p_inf exp(-s / (beta E)), p_inf = (beta - 1)/beta (the retardation time beta lambda of the
    /// polymer-solvent mixture), so the plain series converge only like their weights N^-2,
    /// N^-3. This common part is summed in closed form (Kummer's transformation) with, for
    /// 0 <= eta <= 1, sum sin(N eta)/N^3 = eta (1 - eta)/8, sum cos(N eta)/N^2 = (1 - 2 eta)/8,
    /// sum cos(N eta)/N^4 = 1/96 - eta^2/16 + eta^3/24, sum 1/N^4 = 1/96; the remainders fall
    /// two powers of N faster, plus fast parts q exp(-sigma_f s) that die like exp(-beta N^2 s).
    ///
    /// **Tail estimate.** Envelopes of the slow and fast parts of G and dG/ds are extrapolated
    /// with their large-N power laws: slow part N^-2 (after subtraction; UCM: the envelope grows
    /// like N for G and N^2 for dG/ds, c/|b| ~ sqrt(E) N), fast part N^0 for G and N^2 for
    /// dG/ds (conservative: the fast part decays like a Gaussian in N once beta N^2 s > 1). The
    /// estimate is used only once modes are in their asymptotic regime (past the window of
    /// underdamped modes for beta > 0, merged-exponent branch).
    fn sums(&self, eta: f64, s: f64, need: Need) -> Sums {
        let beta = self.ch.viscosity_ratio;
        let ucm = beta == 0.0 && self.e > 0.0;
        let asym = if beta > 0.0 && beta < 1.0 && self.e > 0.0 {
            let sigma = 1.0 / (beta * self.e);
            Asymptote {
                on: true,
                p: (beta - 1.0) / beta,
                sigma,
                exp: (-sigma * s).exp(),
            }
        } else {
            Asymptote::default()
        };
        // Extra decay of the slow envelope, growth of the fast one, for G and dG/ds.
        let (slow_g, slow_dg) = if ucm { (-1.0, -2.0) } else { (2.0, 2.0) };
        let (fast_g, fast_dg) = (0.0, 2.0);
        let tol = self.tol / 32.0;
        let mut out = Sums::default();
        for n in 1..=self.max_modes {
            let (nn, m) = self.mode_at(n, s, &asym);
            let n2 = nn * nn;
            let (sn, cs) = (nn * eta).sin_cos();
            out.s3 += sn * m.g / (n2 * nn);
            out.s2 += cs * m.g / n2;
            out.s4 += cs * m.dg / (n2 * n2);
            out.q4 += m.g / (n2 * n2);
            out.modes = n;
            if !m.asymptotic || n < 4 {
                continue;
            }
            let [sg, fg, sdg, fdg] = m.env;
            let g_tail = |k: f64| {
                let w = nn.powf(-k);
                Self::tail(w * sg, nn, k + slow_g) + Self::tail(w * fg, nn, k - fast_g)
            };
            let dg_tail = |k: f64| {
                let w = nn.powf(-k);
                Self::tail(w * sdg, nn, k + slow_dg) + Self::tail(w * fdg, nn, k - fast_dg)
            };
            let mut worst: f64 = 0.0;
            if need.s3 {
                worst = worst.max(g_tail(3.0));
            }
            if need.s2 {
                worst = worst.max(g_tail(2.0));
            }
            if need.s4 {
                worst = worst.max(dg_tail(4.0));
            }
            if need.q4 {
                worst = worst.max(2.0 * g_tail(4.0));
            }
            if worst < tol {
                break;
            }
        }
        if asym.on {
            let a = asym.p * asym.exp;
            out.s3 += a * eta * (1.0 - eta) / 8.0;
            out.s2 += a * (1.0 - 2.0 * eta) / 8.0;
            out.s4 -= a * asym.sigma * (1.0 / 96.0 - eta * eta / 16.0 + eta * eta * eta / 24.0);
            out.q4 += a / 96.0;
        }
        out
    }

    fn point(&self, y: f64, t: f64, need: Need) -> Point {
        if t <= 0.0 {
            return Point {
                u: 0.0,
                dudy: 0.0,
                tau: 0.0,
                tau_p: 0.0,
            };
        }
        let h = self.ch.width;
        let beta = self.ch.viscosity_ratio;
        let eta = y / h;
        let sm = self.sums(eta, t / self.tv, need);
        let sc = self.ch.viscosity * self.u / h;
        Point {
            u: self.u * (4.0 * eta * (1.0 - eta) - 32.0 * sm.s3),
            dudy: self.u / h * (4.0 * (1.0 - 2.0 * eta) - 32.0 * sm.s2),
            tau: sc * (4.0 * (1.0 - 2.0 * eta) + 32.0 * sm.s4),
            tau_p: sc * (4.0 * (1.0 - beta) * (1.0 - 2.0 * eta) + 32.0 * (sm.s4 + beta * sm.s2)),
        }
    }

    /// Number of modes the convergence criterion sums for the velocity at (y, t) (diagnostics).
    pub fn modes_for_velocity(&self, y: f64, t: f64) -> usize {
        self.sums(
            y / self.ch.width,
            t / self.tv,
            Need {
                s3: true,
                ..Need::default()
            },
        )
        .modes
    }

    /// Velocity u(y, t) \[m/s\]. Every point value takes 0 <= y <= H (the closed-form sums used
    /// hold there) and is the rest state for t <= 0.
    pub fn velocity(&self, y: f64, t: f64) -> f64 {
        self.point(
            y,
            t,
            Need {
                s3: true,
                ..Need::default()
            },
        )
        .u
    }

    /// Centre-line velocity u(H/2, t) \[m/s\].
    pub fn centreline_velocity(&self, t: f64) -> f64 {
        self.velocity(0.5 * self.ch.width, t)
    }

    /// Velocity gradient du/dy(y, t) \[1/s\] (UCM: conditionally convergent, see the module
    /// documentation).
    pub fn velocity_gradient(&self, y: f64, t: f64) -> f64 {
        self.point(
            y,
            t,
            Need {
                s2: true,
                ..Need::default()
            },
        )
        .dudy
    }

    /// Total shear stress eta_s du/dy + tau_p,xy at (y, t) \[Pa\].
    pub fn shear_stress_total(&self, y: f64, t: f64) -> f64 {
        self.point(
            y,
            t,
            Need {
                s4: true,
                ..Need::default()
            },
        )
        .tau
    }

    /// Polymer shear stress tau_p,xy(y, t) \[Pa\] (the "tau_xy" of King & Lind's figures).
    pub fn shear_stress_polymer(&self, y: f64, t: f64) -> f64 {
        let beta_pos = self.ch.viscosity_ratio > 0.0;
        self.point(
            y,
            t,
            Need {
                s4: true,
                s2: beta_pos,
                ..Need::default()
            },
        )
        .tau_p
    }

    /// Total wall shear stress tau(0, t) \[Pa\]: the force per unit area the fluid exerts on a
    /// wall; steady value rho g H / 2.
    pub fn wall_shear_stress_total(&self, t: f64) -> f64 {
        self.shear_stress_total(0.0, t)
    }

    /// Polymer part of the wall shear stress tau_p,xy(0, t) \[Pa\]; steady value
    /// (1 - beta) rho g H / 2.
    pub fn wall_shear_stress_polymer(&self, t: f64) -> f64 {
        self.shear_stress_polymer(0.0, t)
    }

    /// Flow rate per unit depth Q(t) = int_0^H u dy = U H [2/3 - 64 sum_N G_N / N^4] \[m2/s\]
    /// (the integral of sin(N eta) over the width is 2/N for odd multiples of pi).
    pub fn flow_rate(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        let sm = self.sums(
            0.0,
            t / self.tv,
            Need {
                q4: true,
                ..Need::default()
            },
        );
        self.u * self.ch.width * (2.0 / 3.0 - 64.0 * sm.q4)
    }

    /// Polymer normal stress tau_p,xx(y, t) \[Pa\] by quadrature of its exact memory integral
    /// (module documentation). tau_p,yy = 0 in this flow.
    pub fn normal_stress_polymer(&self, y: f64, t: f64) -> f64 {
        let lambda = self.ch.relaxation_time;
        if lambda == 0.0 || t <= 0.0 || self.ch.viscosity_ratio >= 1.0 {
            return 0.0;
        }
        let need = Need {
            s2: true,
            s4: true,
            ..Need::default()
        };
        let mut integrand = |tp: f64| {
            let p = self.point(y, tp, need);
            (-(t - tp) / lambda).exp() * p.tau_p * p.dudy
        };
        let t0 = (t - 40.0 * lambda).max(0.0);
        let steady_wall = 2.0
            * lambda
            * (1.0 - self.ch.viscosity_ratio)
            * self.ch.viscosity
            * (4.0 * self.u / self.ch.width).powi(2);
        let width = (0.125 * lambda.min(self.tv)).max((t - t0) / 4000.0);
        let panels = ((t - t0) / width).ceil() as usize;
        2.0 * quadrature::adaptive(&mut integrand, t0, t, 0.5 * self.tol * steady_wall, panels)
    }

    /// Steady velocity rho g y (H - y) / (2 eta0) \[m/s\].
    pub fn steady_velocity(&self, y: f64) -> f64 {
        let eta = y / self.ch.width;
        4.0 * self.u * eta * (1.0 - eta)
    }

    /// Steady polymer normal stress 2 lambda eta_p (du/dy)^2 \[Pa\] (28.8 at the wall in King &
    /// Lind's Re = Wi = 1, beta = 0.1 case).
    pub fn steady_normal_stress_polymer(&self, y: f64) -> f64 {
        let dudy = 4.0 * self.u / self.ch.width * (1.0 - 2.0 * y / self.ch.width);
        2.0 * self.ch.relaxation_time
            * (1.0 - self.ch.viscosity_ratio)
            * self.ch.viscosity
            * dudy
            * dudy
    }

    /// Local extrema of the centre-line velocity for 0 < t <= t_end, in time order: scanned on
    /// steps of min(lambda, t_v) / 100 (at least 2000 steps), each bracket then refined by
    /// golden-section search to 1e-10 t_v. Two extrema closer than a scan step could be missed;
    /// changes below 1e-13 U (round-off once the flow has converged) are not counted.
    pub fn centreline_extrema(&self, t_end: f64) -> Vec<Extremum> {
        let scale = if self.ch.relaxation_time > 0.0 {
            self.ch.relaxation_time.min(self.tv)
        } else {
            self.tv
        };
        let steps = ((t_end / (scale / 100.0)).ceil() as usize).max(2000);
        let dt = t_end / steps as f64;
        let uc = |t: f64| self.centreline_velocity(t);
        // Differences below this are round-off of a converged flow, not extrema.
        let noise = 1e-13 * self.u;
        let mut out = Vec::new();
        let (mut u0, mut u1) = (uc(0.0), uc(dt));
        for k in 2..=steps {
            let t2 = k as f64 * dt;
            let u2 = uc(t2);
            let is_max = u1 - u0 > noise && u1 - u2 > noise;
            let is_min = u0 - u1 > noise && u2 - u1 > noise;
            if is_max || is_min {
                let sign = if is_max { -1.0 } else { 1.0 };
                let tm = golden(|t| sign * uc(t), t2 - 2.0 * dt, t2, 1e-10 * self.tv);
                out.push(Extremum {
                    time: tm,
                    velocity: uc(tm),
                    maximum: is_max,
                });
            }
            u0 = u1;
            u1 = u2;
        }
        out
    }
}

/// Minimum of a unimodal f on [a, b] by golden-section search to an interval of `tol`.
fn golden(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> f64 {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - r * (b - a);
    let mut d = a + r * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    while b - a > tol {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - r * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// King & Lind section IV.A: Re = Wi = 1, H = U = rho = 1, g = 8, eta0 = 1, lambda = 1.
    fn kl(beta: f64) -> WatersKing {
        WatersKing::new(Channel::from_re_wi(1.0, 1.0, beta)).unwrap()
    }

    #[test]
    fn reproduces_the_reference_table() {
        let wk = kl(0.1);
        assert_eq!(wk.velocity_scale(), 1.0);
        assert_eq!(wk.elasticity(), 1.0);
        // t, u(0.25), u(0.5), tau_p,xy(0): the values of two independent implementations
        // (King's code, an OpenFOAM validation case) that agree with each other to about 1e-5.
        let table = [
            (0.5, 2.01592, 2.83708, 2.89679),
            (1.0, 1.14793, 1.55704, 4.60767),
            (3.0, 0.83411, 1.11896, 3.70819),
            (5.0, 0.76443, 1.02041, 3.60918),
        ];
        for (t, u1, uc, tw) in table {
            let got = (
                wk.velocity(0.25, t),
                wk.centreline_velocity(t),
                wk.wall_shear_stress_polymer(t),
            );
            println!(
                "t = {t}: u(0.25) {:.7} u(0.5) {:.7} tau_p(0) {:.7}",
                got.0, got.1, got.2
            );
            assert!((got.0 - u1).abs() < 1e-5, "u(0.25, {t}) = {}", got.0);
            assert!((got.1 - uc).abs() < 1e-5, "u(0.5, {t}) = {}", got.1);
            // At t = 0.5 we get 2.8967782 against the table's 2.89679 (1.2e-5 off): ours is
            // confirmed to 1e-10 by the memory integral of the constitutive equation
            // (`polymer_stress_solves_its_constitutive_equation`); the plain series cut at 200
            // modes gives 2.8968028, so the table carries a truncation error of that order.
            let tol = if t == 0.5 { 1.5e-5 } else { 1e-5 };
            assert!((got.2 - tw).abs() < tol, "tau_p(0, {t}) = {}", got.2);
        }
        // Steady state (t = 200 lambda).
        let t = 200.0;
        assert!((wk.velocity(0.25, t) - 0.75).abs() < 1e-12);
        assert!((wk.centreline_velocity(t) - 1.0).abs() < 1e-12);
        assert!((wk.wall_shear_stress_polymer(t) - 3.6).abs() < 1e-12);
        assert!((wk.wall_shear_stress_total(t) - 4.0).abs() < 1e-12);
        assert!((wk.flow_rate(t) - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(wk.steady_normal_stress_polymer(0.0), 28.8);
        let txx = wk.normal_stress_polymer(0.0, 60.0);
        assert!((txx - 28.8).abs() < 1e-8 * 28.8, "tau_xx(0, 60) = {txx}");
    }

    #[test]
    fn centre_line_extrema_match_the_reference() {
        let ex = kl(0.1).centreline_extrema(3.0);
        for e in &ex {
            println!("{e:?}");
        }
        assert_eq!(ex.len(), 3, "{ex:?}");
        // First peak 2.8454 at 0.528, minimum 0.3611 at 1.583, second peak 1.2242 at 2.636
        // (values rounded as given).
        for (e, (t, u, max)) in ex.iter().zip([
            (0.528, 2.8454, true),
            (1.583, 0.3611, false),
            (2.636, 1.2242, true),
        ]) {
            assert_eq!(e.maximum, max);
            // The minimum is at t = 1.58208: the reference's 1.583 is 1e-3 off, which moves the
            // velocity by only ~1e-5 (u'' ~ 20 there), below the 5 digits it was read to.
            assert!((e.time - t).abs() <= 1e-3, "{e:?}");
            assert!((e.velocity - u).abs() <= 5e-5, "{e:?}");
        }
    }

    #[test]
    fn polymer_stress_solves_its_constitutive_equation() {
        // tau_p comes from the momentum balance; the constitutive equation
        // lambda dtau_p/dt + tau_p = eta_p du/dy, tau_p(0) = 0, gives it independently as
        // (eta_p/lambda) int_0^t exp(-(t - t')/lambda) du/dy(t') dt'.
        for beta in [0.1, 0.5] {
            let wk = kl(beta);
            let eta_p = 1.0 - beta;
            for y in [0.0, 0.2] {
                for t in [0.01, 0.5, 2.0] {
                    let series = wk.shear_stress_polymer(y, t);
                    let mut f = |tp: f64| (-(t - tp)).exp() * wk.velocity_gradient(y, tp);
                    let memory = eta_p * quadrature::adaptive(&mut f, 0.0, t, 1e-12, 16);
                    println!("beta {beta} y {y} t {t}: series {series:.12} memory {memory:.12}");
                    assert!((series - memory).abs() < 1e-9, "{series} {memory}");
                }
            }
        }
    }

    /// Central difference of f at x with step h.
    fn diff(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
        (f(x + h) - f(x - h)) / (2.0 * h)
    }

    #[test]
    fn momentum_balance_holds_locally_and_globally() {
        // rho du/dt = rho g + d tau/dy (velocity series against stress series), and for the
        // whole channel rho dQ/dt = rho g H - 2 tau_wall.
        for (re, wi, beta) in [
            (1.0, 1.0, 0.1),
            (0.01, 1.0, 0.1),
            (1.0, 0.0, 1.0),
            (1.0, 2.0, 0.5),
        ] {
            let ch = Channel::from_re_wi(re, wi, beta);
            let wk = WatersKing::new(ch).unwrap();
            let g = ch.body_force;
            let sc = wk.channel().stress_scale();
            for t in [0.05, 0.4, 1.5] {
                let h = 1e-4 * t;
                for y in [0.1, 0.3, 0.5] {
                    let dudt = diff(|t| wk.velocity(y, t), t, h);
                    let dtau = diff(|y| wk.shear_stress_total(y, t), y, 1e-4);
                    let res = (dudt - g - dtau) / (sc / ch.width);
                    assert!(
                        res.abs() < 1e-6,
                        "Re {re} Wi {wi} beta {beta} t {t} y {y}: {res:e}"
                    );
                }
                let dqdt = diff(|t| wk.flow_rate(t), t, h);
                let res = (dqdt - g + 2.0 * wk.wall_shear_stress_total(t)) / (sc / ch.width);
                assert!(
                    res.abs() < 1e-6,
                    "Re {re} Wi {wi} beta {beta} t {t}: {res:e}"
                );
            }
        }
    }

    #[test]
    fn normal_stress_matches_an_independent_time_integration() {
        // RK4 on lambda dtau_xx/dt + tau_xx = 2 lambda tau_p du/dy with dt = 1e-3 (error
        // ~1e-9 here) against the Gauss-Legendre memory integral.
        let wk = kl(0.1);
        for y in [0.0, 0.3] {
            let rhs = |t: f64, x: f64| {
                2.0 * wk.shear_stress_polymer(y, t) * wk.velocity_gradient(y, t) - x
            };
            let dt = 1e-3;
            let mut x = 0.0;
            for k in 0..1000 {
                let t = k as f64 * dt;
                let k1 = rhs(t, x);
                let k2 = rhs(t + 0.5 * dt, x + 0.5 * dt * k1);
                let k3 = rhs(t + 0.5 * dt, x + 0.5 * dt * k2);
                let k4 = rhs(t + dt, x + dt * k3);
                x += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            }
            let quad = wk.normal_stress_polymer(y, 1.0);
            println!("y {y}: tau_xx(1) quadrature {quad:.10} RK4 {x:.10}");
            assert!((quad - x).abs() < 1e-7 * 28.8, "{quad} vs {x}");
        }
    }

    #[test]
    fn newtonian_limits_agree() {
        // lambda = 0, beta = 1 (all solvent) and a vanishing lambda are the same Newtonian flow.
        let newt = WatersKing::new(Channel::from_re_wi(1.0, 0.0, 0.1)).unwrap();
        let solvent = WatersKing::new(Channel::from_re_wi(1.0, 1.0, 1.0)).unwrap();
        let tiny = WatersKing::new(Channel::from_re_wi(1.0, 1e-12, 0.1)).unwrap();
        for t in [0.01, 0.1, 0.5] {
            for y in [0.1, 0.5] {
                let u = newt.velocity(y, t);
                assert!((solvent.velocity(y, t) - u).abs() < 1e-10, "t {t} y {y}");
                assert!((tiny.velocity(y, t) - u).abs() < 1e-9, "t {t} y {y}");
                let tau = newt.shear_stress_total(y, t);
                assert!((solvent.shear_stress_total(y, t) - tau).abs() < 1e-9);
                assert!(solvent.shear_stress_polymer(y, t).abs() < 1e-9);
                assert!((tiny.shear_stress_polymer(y, t) - 0.9 * tau).abs() < 1e-8);
            }
        }
        // Newtonian: no overshoot, monotone rise to U.
        assert!(newt.centreline_extrema(3.0).is_empty());
    }

    #[test]
    fn ucm_shear_wave_leaves_the_core_in_free_fall() {
        // UCM at Re = Wi = 1: shear waves run from the walls at c = sqrt(eta0 / (rho lambda))
        // = 1; ahead of them there is no stress and the fluid accelerates freely, u = g t.
        let wk = kl(0.0).with_max_modes(100_000);
        for (y, t) in [(0.5, 0.3), (0.5, 0.45), (0.3, 0.2)] {
            let u = wk.velocity(y, t);
            let tau = wk.shear_stress_total(y, t);
            println!(
                "UCM y {y} t {t}: u {u:.8} (g t = {}), tau {tau:.2e}",
                8.0 * t
            );
            assert!((u - 8.0 * t).abs() < 1e-4, "u({y}, {t}) = {u}");
            assert!(tau.abs() < 1e-4, "tau({y}, {t}) = {tau}");
        }
        // Behind the front the flow is slowed: at the same time closer to the wall.
        assert!(wk.velocity(0.1, 0.3) < 8.0 * 0.3 - 0.1);
    }

    #[test]
    fn overdamped_above_the_critical_elasticity() {
        let beta: f64 = 0.1;
        let e_star = WatersKing::overdamped_elasticity(beta);
        let quoted = 4.0 / (beta * beta * PI * PI);
        println!("E* = {e_star}, 4/(beta^2 pi^2) = {quoted}");
        assert!(e_star < quoted && e_star > 0.9 * quoted);
        // E = Wi / Re with Re = 1.
        let at = |e: f64| WatersKing::new(Channel::from_re_wi(1.0, e, beta)).unwrap();
        assert!(at(1.001 * e_star).all_modes_overdamped());
        assert!(!at(0.999 * e_star).all_modes_overdamped());
        assert!(at(quoted).all_modes_overdamped());
        assert!(!at(1.0).all_modes_overdamped());
        assert!(!kl(0.0).all_modes_overdamped());
        // Above it the centre-line velocity overshoots once and then settles without
        // oscillating: any later extremum is a shallow undershoot (here 1.8e-6 U at t = 45 t_v:
        // the modes' retardation parts, decaying at 1/(beta lambda), and their viscous parts
        // have opposite signs), not the 64 % dip of the oscillating case below.
        let wk = at(quoted * 1.05);
        let ex = wk.centreline_extrema(400.0);
        println!("{ex:?}");
        assert!(ex[0].maximum && ex[0].velocity > 7.0, "{ex:?}");
        assert!(ex.len() <= 2, "{ex:?}");
        for e in &ex[1..] {
            assert!((e.velocity - 1.0).abs() < 1e-5, "{e:?}");
        }
        // Below it the centre line oscillates (E = 1: three extrema by t = 3).
        assert!(kl(0.1).centreline_extrema(3.0).len() >= 3);
    }

    #[test]
    fn series_converge_to_the_requested_tolerance() {
        // Tighter tolerance and more modes change nothing beyond the default tolerance.
        for (re, wi, beta) in [
            (1.0, 1.0, 0.1),
            (0.01, 64.0, 0.1),
            (1.0, 100.0, 0.1),
            (1.0, 1.0, 0.9),
        ] {
            let ch = Channel::from_re_wi(re, wi, beta);
            let wk = WatersKing::new(ch).unwrap();
            let fine = wk.clone().with_tolerance(1e-13).with_max_modes(200_000);
            let (u, sc) = (wk.velocity_scale(), ch.stress_scale());
            for t in [1e-3, 0.1, 1.0, 10.0] {
                for y in [0.0, 0.17, 0.5] {
                    let du = (wk.velocity(y, t) - fine.velocity(y, t)).abs() / u;
                    let dt = (wk.shear_stress_polymer(y, t) - fine.shear_stress_polymer(y, t))
                        .abs()
                        / sc;
                    let dg = (wk.velocity_gradient(y, t) - fine.velocity_gradient(y, t)).abs()
                        / (u / ch.width);
                    assert!(
                        du < 2e-10 && dt < 2e-10 && dg < 2e-10,
                        "Re {re} Wi {wi} beta {beta} t {t} y {y}: {du:e} {dt:e} {dg:e}"
                    );
                    assert!(wk.velocity(y, t).is_finite());
                }
                let dq = (wk.flow_rate(t) - fine.flow_rate(t)).abs() / (u * ch.width);
                assert!(dq < 2e-10, "Re {re} Wi {wi} t {t}: {dq:e}");
            }
            println!(
                "Re {re} Wi {wi} beta {beta}: modes for u(0.17) at t = 0.001, 0.1, 1: {} {} {}",
                wk.modes_for_velocity(0.17, 1e-3),
                wk.modes_for_velocity(0.17, 0.1),
                wk.modes_for_velocity(0.17, 1.0)
            );
        }
    }

    #[test]
    fn builds_from_the_scene_configuration() {
        let mut cfg = {
            let mut c = SceneConfig::default();
            c.fluid.density = 1.0;
            c.fluid.viscosity = 1.0;
            c.fluid.viscosity_ratio = 0.1;
            c.fluid.relaxation_time = 1.0;
            c.fluid.rheology = RheologyKind::OldroydB;
            c
        };
        let wk = WatersKing::from_config(&cfg, 1.0, 8.0).unwrap();
        assert!((wk.centreline_velocity(1.0) - 1.55704).abs() < 1e-5);
        cfg.fluid.rheology = RheologyKind::Ucm;
        assert_eq!(
            WatersKing::from_config(&cfg, 1.0, 8.0)
                .unwrap()
                .channel()
                .viscosity_ratio,
            0.0
        );
        cfg.fluid.rheology = RheologyKind::Newtonian;
        let n = WatersKing::from_config(&cfg, 1.0, 8.0).unwrap();
        assert_eq!(n.elasticity(), 0.0);
        cfg.fluid.rheology = RheologyKind::FeneP;
        assert!(matches!(
            WatersKing::from_config(&cfg, 1.0, 8.0),
            Err(AnalyticError::Unsupported { .. })
        ));
        assert!(WatersKing::new(Channel {
            width: -1.0,
            ..Channel::from_re_wi(1.0, 1.0, 0.1)
        })
        .is_err());
    }
}
