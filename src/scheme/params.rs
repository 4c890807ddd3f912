//! Constants of the weakly compressible schemes, resolved once from the configuration.

use crate::config::{ArtificialStressKind, ConformationMethod, SceneConfig, ViscousOperator};
use crate::eos::Eos;
use crate::neighbors::Domain;
use crate::Vec2;

#[derive(Debug, Clone)]
pub struct Params {
    /// Equation of state (reference density and sound speed).
    pub eos: Eos,
    /// Monaghan's artificial viscosity alpha and beta (Fang 2006 eq. 31).
    pub alpha: f64,
    pub beta: f64,
    /// Which artificial stress, and its coefficient (Fang's epsilon or Ren's b).
    pub art_kind: ArtificialStressKind,
    pub art_coef: f64,
    pub gravity: Vec2,
    pub dt_factor: f64,
    pub method: ConformationMethod,
    /// EVSS alpha_V / (1 - beta) (King & Lind eqs. 6-8); 0 = off.
    pub evss_alpha: f64,
    /// Whether the solvent viscosity goes through Morris' Laplacian even without EVSS.
    pub viscous_laplacian: bool,
    /// PDRI: steps between density reinitialisations (0 = never).
    pub reinit_interval: u64,
    /// Void fraction beyond which the fluid counts as torn (0 = never check).
    pub fracture_void_fraction: f64,
    pub dx: f64,
    /// Largest distance from the origin a particle may reach (the scene's; unbounded unless
    /// the scene says otherwise).
    pub domain_radius: f64,
    /// Open or periodic: every pair vector goes through it.
    pub domain: Domain,
}

impl Params {
    pub fn from_config(cfg: &SceneConfig) -> Self {
        Self {
            eos: Eos::from_config(cfg),
            alpha: cfg.artificial_viscosity_alpha,
            beta: cfg.artificial_viscosity_beta,
            art_kind: cfg.artificial_stress_kind,
            art_coef: match cfg.artificial_stress_kind {
                ArtificialStressKind::Fang => cfg.artificial_stress_epsilon,
                ArtificialStressKind::Ren => cfg.artificial_stress_b,
            },
            gravity: Vec2::new(0.0, -cfg.gravity),
            dt_factor: cfg.time_step_factor,
            // The weakly compressible schemes' own choice is the direct update of their papers.
            method: match cfg.conformation_method {
                ConformationMethod::Auto => ConformationMethod::Direct,
                m => m,
            },
            evss_alpha: cfg.evss_alpha,
            viscous_laplacian: cfg.viscous_operator == ViscousOperator::Laplacian,
            reinit_interval: cfg.density_reinit_interval.max(0) as u64,
            fracture_void_fraction: cfg.fracture_void_fraction,
            dx: cfg.dx(),
            domain_radius: f64::INFINITY,
            domain: Domain::OPEN,
        }
    }
}
