//! The fluid: its constitutive model and material parameters, and the gravity acting on it.

use super::{enumeration, real, real_pos, ConfigError, Kind};
use crate::rheology::{
    AnyRheology, Cross, FeneCr, FeneP, Giesekus, Newtonian, OldroydB, PttExponential, PttLinear,
};

pub const RHEOLOGIES: &[(&str, &str)] = &[
    ("newtonian", "Newtonian fluid"),
    ("oldroyd_b", "Oldroyd-B"),
    ("ucm", "upper-convected Maxwell (Oldroyd-B with no solvent)"),
    ("fene_p", "FENE-P"),
    ("fene_cr", "FENE-CR"),
    ("ptt_linear", "linear Phan-Thien-Tanner"),
    ("ptt_exponential", "exponential Phan-Thien-Tanner"),
    ("giesekus", "Giesekus"),
    ("cross", "Cross shear-thinning generalized Newtonian"),
];

crate::choice_enum!(
    /// The constitutive model.
    RheologyKind, RHEOLOGIES,
    Newtonian = "newtonian", OldroydB = "oldroyd_b", Ucm = "ucm", FeneP = "fene_p",
    FeneCr = "fene_cr", PttLinear = "ptt_linear", PttExponential = "ptt_exponential",
    Giesekus = "giesekus", Cross = "cross");

crate::params! {
    /// The fluid and the gravity acting on it. Defaults are Fang et al. 2006's Oldroyd-B drop
    /// (nu = 0.004 m2/s, lambda1 = 0.02 s, lambda2 = 0.002 s, so beta = lambda2/lambda1 = 0.1).
    pub struct FluidParams {
        rheology: RheologyKind = enumeration::<RheologyKind>("Rheology", "oldroyd_b"), vr 3, unit "";
            "Constitutive model of the fluid",
        density: f64 = real_pos(1000.0, 1.0e5), vr 8, unit "kg/m3";
            "Reference density rho0",
        gravity: f64 = real(9.81, 0.0, 1000.0), vr 9, unit "m/s2";
            "Gravitational acceleration, vertically down",
        viscosity: f64 = real_pos(4.0, 1.0e6), vr 10, unit "Pa.s";
            "Total zero-shear viscosity eta0 (solvent + polymer)",
        viscosity_ratio: f64 = real(0.1, 0.0, 1.0), vr 11, unit "1";
            "Solvent to total viscosity beta = eta_s/eta0 (Fang's lambda2/lambda1)",
        relaxation_time: f64 = real_pos(0.02, 1.0e6), vr 12, unit "s";
            "Polymer relaxation time lambda (Fang's lambda1)",
        fene_L2: f64 = Kind::Real { default: 100.0, min: 2.0, max: 1.0e12, min_open: true, max_open: false }, vr 13, unit "1";
            "FENE extensibility L^2 (> 2 in 2D)",
        ptt_epsilon: f64 = real(0.25, 0.0, 10.0), vr 14, unit "1";
            "PTT extensibility parameter epsilon",
        giesekus_alpha: f64 = real(0.1, 0.0, 0.5), vr 15, unit "1";
            "Giesekus mobility alpha (0 <= alpha <= 0.5)",
        cross_viscosity_inf: f64 = real(0.4, 0.0, 1.0e6), vr 16, unit "Pa.s";
            "Cross model infinite-shear viscosity (Ren 2015 eq. 5)",
        cross_K: f64 = real(1.0, 0.0, 1.0e6), vr 17, unit "s";
            "Cross model time constant K (Ren 2015 eq. 5)",
        cross_m: f64 = real(1.0, 0.0, 10.0), vr 18, unit "1";
            "Cross model exponent m (Ren 2015 eq. 5)",
    }
}

impl FluidParams {
    /// Whether the model carries no conformation tensor (its whole viscosity is the solvent's).
    pub fn is_inelastic(&self) -> bool {
        matches!(self.rheology, RheologyKind::Newtonian | RheologyKind::Cross)
    }

    /// The checks that involve several of the fluid's parameters: a model's own range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let inconsistent = |s: String| Err(ConfigError::Inconsistent(s));
        if self.rheology == RheologyKind::PttLinear && self.ptt_epsilon > 0.5 {
            return inconsistent(format!(
                "ptt_epsilon = {} is outside [0, 0.5] for the linear PTT model: its relaxation factor \
                 1 + epsilon tr(A - I) would turn negative for a compressed, still positive-definite A",
                self.ptt_epsilon
            ));
        }
        if self.rheology == RheologyKind::Cross && self.cross_viscosity_inf > self.viscosity {
            return inconsistent(format!(
                "cross_viscosity_inf = {} Pa.s exceeds the zero-shear viscosity = {} Pa.s: the Cross \
                 model (Ren 2015 eq. 5) is shear-thinning, so it must be at most viscosity",
                self.cross_viscosity_inf, self.viscosity
            ));
        }
        Ok(())
    }
}

/// The rheology is built here, next to the rows that name its parameters, so that the
/// constitutive models (`crate::rheology`) depend on nothing above them.
impl AnyRheology {
    /// Build the configured model from `viscosity` (eta0, total zero-shear), `viscosity_ratio`
    /// (beta = eta_s/eta0), `relaxation_time` (lambda) and the model's own parameter. UCM is
    /// Oldroyd-B with beta = 0 whatever `viscosity_ratio` says; Newtonian and Cross ignore
    /// beta and lambda (the whole viscosity is the solvent's). Parameter ranges were checked by
    /// the parameter table.
    pub fn from_fluid(f: &FluidParams) -> Self {
        let eta0 = f.viscosity;
        let beta = f.viscosity_ratio;
        let lambda = f.relaxation_time;
        match f.rheology {
            RheologyKind::Newtonian => AnyRheology::Newtonian(Newtonian::new(eta0)),
            RheologyKind::OldroydB => AnyRheology::OldroydB(OldroydB::new(eta0, beta, lambda)),
            RheologyKind::Ucm => AnyRheology::OldroydB(OldroydB::new(eta0, 0.0, lambda)),
            RheologyKind::FeneP => AnyRheology::FeneP(FeneP::new(eta0, beta, lambda, f.fene_L2)),
            RheologyKind::FeneCr => AnyRheology::FeneCr(FeneCr::new(eta0, beta, lambda, f.fene_L2)),
            RheologyKind::PttLinear => {
                AnyRheology::PttLinear(PttLinear::new(eta0, beta, lambda, f.ptt_epsilon))
            }
            RheologyKind::PttExponential => {
                AnyRheology::PttExponential(PttExponential::new(eta0, beta, lambda, f.ptt_epsilon))
            }
            RheologyKind::Giesekus => {
                AnyRheology::Giesekus(Giesekus::new(eta0, beta, lambda, f.giesekus_alpha))
            }
            RheologyKind::Cross => AnyRheology::Cross(Cross::new(
                eta0,
                f.cross_viscosity_inf,
                f.cross_K,
                f.cross_m,
            )),
        }
    }
}
