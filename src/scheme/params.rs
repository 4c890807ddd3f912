//! Constants of the schemes, resolved once from the fluid, the numerics and what the scene
//! says about its domain (`SceneConfig::scheme_params` fills the scene's part): nothing here
//! reads the scene itself, so the configuration flows into the scheme one way.

use crate::config::{
    ArtificialStressKind, ConformationMethod, FluidParams, IsphFreeSurface, Numerics,
    ViscousOperator, WallBoundary,
};
use crate::dim::Vector;
use crate::eos::Eos;
use crate::neighbors::Domain;

/// The constants of a scheme in N space dimensions (`Params` alone: two).
#[derive(Debug, Clone)]
pub struct Params<const N: usize = 2> {
    /// Equation of state (reference density and sound speed).
    pub eos: Eos,
    /// Background pressure added to the equation of state's pressure \[Pa\]: the scene's
    /// ([`crate::scene::Scene::background_pressure`]); 0 for a free surface.
    pub background_pressure: f64,
    /// Monaghan's artificial viscosity alpha and beta (Fang 2006 eq. 31).
    pub alpha: f64,
    pub beta: f64,
    /// Which artificial stress, and its coefficient (Fang's epsilon or Ren's b).
    pub art_kind: ArtificialStressKind,
    pub art_coef: f64,
    /// Body force per unit mass, along -y in 2D and -z in 3D (the last axis) [m/s2].
    pub gravity: Vector<N>,
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
    /// Whether the domain has a free surface (the scene's: every scene but the closed channel).
    pub free_surface: bool,
    /// The wall model asked for (`auto`: see [`crate::boundary`]).
    pub wall_boundary: WallBoundary,
    /// What `isph_free_surface = auto` means in this scene (never `Auto` itself).
    pub auto_free_surface: IsphFreeSurface,
}

impl Params {
    /// The constants for the fluid `f` and the numerics `n` at spacing `dx` and sound speed `c`,
    /// in an open domain with a free surface under gravity (the scene's terms are set over these
    /// by `SceneConfig::scheme_params`).
    pub fn new(f: &FluidParams, n: &Numerics, dx: f64, c: f64) -> Self {
        Self::in_dimension(f, n, dx, c)
    }
}

impl<const N: usize> Params<N> {
    /// [`Params::new`] in N dimensions, gravity along the last axis.
    pub fn in_dimension(f: &FluidParams, n: &Numerics, dx: f64, c: f64) -> Self {
        let mut gravity = Vector::zeros();
        gravity[N - 1] = -f.gravity;
        Self {
            eos: Eos::new(n.equation_of_state, f.density, c),
            background_pressure: 0.0,
            alpha: n.artificial_viscosity_alpha,
            beta: n.artificial_viscosity_beta,
            art_kind: n.artificial_stress_kind,
            art_coef: match n.artificial_stress_kind {
                ArtificialStressKind::Fang => n.artificial_stress_epsilon,
                ArtificialStressKind::Ren => n.artificial_stress_b,
            },
            gravity,
            dt_factor: n.time_step_factor,
            // The weakly compressible schemes' own choice is the direct update of their papers.
            method: match n.conformation_method {
                ConformationMethod::Auto => ConformationMethod::Direct,
                m => m,
            },
            evss_alpha: n.evss_alpha,
            viscous_laplacian: n.viscous_operator == ViscousOperator::Laplacian,
            reinit_interval: n.density_reinit_interval.max(0) as u64,
            fracture_void_fraction: n.fracture_void_fraction,
            dx,
            domain_radius: f64::INFINITY,
            domain: Domain::OPEN,
            free_surface: true,
            wall_boundary: n.wall_boundary,
            auto_free_surface: IsphFreeSurface::ZeroPressure,
        }
    }
}
