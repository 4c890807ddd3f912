//! Analytic solutions of the plane channel flow the `channel` scene is checked against.
//!
//! A channel of width H between no-slip walls at y = 0 and y = H, periodic (infinitely long) in x,
//! driven from rest by a body force g along x. Every solution takes the physical parameters the
//! scene has (density rho, body force g, width H, zero-shear viscosity eta0 = `viscosity`,
//! viscosity ratio beta = `viscosity_ratio`, relaxation time lambda = `relaxation_time`, and the
//! model's own parameter), so the scene can call it with its [`SceneConfig`] values.
//!
//! * [`waters_king`]: the transient start-up of an Oldroyd-B fluid (Waters & King 1970), with
//!   the Newtonian (lambda = 0) and UCM (beta = 0) limits: velocity, polymer and total shear
//!   stress, polymer normal stress, flow rate, wall shear stress, centre-line extrema.
//! * [`steady_shear`]: the steady fully developed profiles of every elastic model of King & Lind
//!   2021 Table I (and Newtonian): velocity, shear rate and the polymer stresses.
//!
//! Scales used throughout: U = rho g H^2 / (8 eta0) (Newtonian centre-line velocity, the U of
//! King & Lind section IV.A), Re = rho U H / eta0, Wi = lambda U / H.
//!
//! [`SceneConfig`]: viscosph::scene::SceneConfig

pub mod falling_sheet;
pub mod falling_thread;
pub mod quadrature;
pub mod steady_shear;
pub mod waters_king;

pub use steady_shear::{SteadyChannel, SteadyModel, SteadyPoint};
pub use waters_king::{Extremum, WatersKing};

use thiserror::Error;

/// Why an analytic solution cannot be built or evaluated.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AnalyticError {
    /// A parameter is out of its physical range (name, value, what is allowed).
    #[error("analytic channel solution: {name} = {value} is invalid ({allowed})")]
    Parameter {
        name: &'static str,
        value: f64,
        allowed: &'static str,
    },
    /// The configured rheology has no analytic solution of this kind.
    #[error("analytic channel solution: no {what} solution for the {model} model")]
    Unsupported {
        model: &'static str,
        what: &'static str,
    },
    /// The wall shear stress exceeds the largest shear stress the model can carry (Giesekus with
    /// beta = 0: sqrt((1 - alpha)/alpha) eta_p/lambda), so no steady flow exists.
    #[error(
        "no steady channel flow: the wall shear stress {wall} Pa exceeds the largest polymer \
         shear stress {max} Pa the model can sustain"
    )]
    NoSteadyState { wall: f64, max: f64 },
}

/// Channel and fluid parameters shared by every solution (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Channel {
    /// Density rho \[kg/m3\].
    pub density: f64,
    /// Body force per unit mass g along x \[m/s2\].
    pub body_force: f64,
    /// Channel width H \[m\] (walls at y = 0 and y = H).
    pub width: f64,
    /// Zero-shear (total) viscosity eta0 \[Pa s\].
    pub viscosity: f64,
    /// Solvent to total viscosity beta = eta_s / eta0.
    pub viscosity_ratio: f64,
    /// Relaxation time lambda \[s\] (0: Newtonian).
    pub relaxation_time: f64,
}

impl Channel {
    /// Refuse non-physical parameters (the scene's parameter table already bounds them; this
    /// guards direct callers).
    fn check(&self) -> Result<(), AnalyticError> {
        let pos = |name, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(AnalyticError::Parameter {
                    name,
                    value: v,
                    allowed: "finite and > 0",
                })
            }
        };
        pos("density", self.density)?;
        pos("body_force", self.body_force)?;
        pos("width", self.width)?;
        pos("viscosity", self.viscosity)?;
        if !(0.0..=1.0).contains(&self.viscosity_ratio) {
            return Err(AnalyticError::Parameter {
                name: "viscosity_ratio",
                value: self.viscosity_ratio,
                allowed: "0 <= beta <= 1",
            });
        }
        if !(self.relaxation_time.is_finite() && self.relaxation_time >= 0.0) {
            return Err(AnalyticError::Parameter {
                name: "relaxation_time",
                value: self.relaxation_time,
                allowed: "finite and >= 0",
            });
        }
        Ok(())
    }

    /// The channel of a scene configuration (`density`, `viscosity`, `viscosity_ratio`,
    /// `relaxation_time`) with the given width and body force, the model's parameters as
    /// configured (UCM and Newtonian limits are the caller's to apply).
    pub fn from_config(cfg: &viscosph::scene::SceneConfig, width: f64, body_force: f64) -> Self {
        Channel {
            density: cfg.fluid.density,
            body_force,
            width,
            viscosity: cfg.fluid.viscosity,
            viscosity_ratio: cfg.fluid.viscosity_ratio,
            relaxation_time: cfg.fluid.relaxation_time,
        }
    }

    /// The non-dimensional set-up of King & Lind section IV.A with H = U = 1 and rho = 1:
    /// eta0 = 1/Re, g = 8 eta0 U / (rho H^2) = 8/Re, lambda = Wi H / U = Wi. At Re = 1 this is
    /// their body force g = 8.
    pub fn from_re_wi(re: f64, wi: f64, beta: f64) -> Self {
        Self {
            density: 1.0,
            body_force: 8.0 / re,
            width: 1.0,
            viscosity: 1.0 / re,
            viscosity_ratio: beta,
            relaxation_time: wi,
        }
    }

    /// Newtonian centre-line velocity U = rho g H^2 / (8 eta0) \[m/s\].
    pub fn velocity_scale(&self) -> f64 {
        self.density * self.body_force * self.width * self.width / (8.0 * self.viscosity)
    }

    /// Viscous stress scale eta0 U / H \[Pa\] (also rho g H / 8).
    pub fn stress_scale(&self) -> f64 {
        self.viscosity * self.velocity_scale() / self.width
    }

    /// Total shear stress at the wall y = 0 in any steady or unsteady flow at rest in the mean:
    /// rho g H / 2 \[Pa\] (momentum balance of the whole channel at steady state).
    pub fn steady_wall_shear_stress(&self) -> f64 {
        0.5 * self.density * self.body_force * self.width
    }

    /// Reynolds number rho U H / eta0.
    pub fn reynolds(&self) -> f64 {
        self.density * self.velocity_scale() * self.width / self.viscosity
    }

    /// Weissenberg number lambda U / H.
    pub fn weissenberg(&self) -> f64 {
        self.relaxation_time * self.velocity_scale() / self.width
    }
}
