//! SPH schemes. A scheme advances a [`State`] by one time step; it reads as its paper's numbered
//! steps over the shared operators ([`crate::operators`]) and wall models
//! ([`crate::boundary`]).
//!
//! [`isph`] (King & Lind 2021) is incompressible: a pressure Poisson equation ([`isph::ppe`])
//! instead of an equation of state. [`wcsph`] (Fang 2006) and [`pdri`] (Ren 2015) share the weakly compressible rate evaluation
//! [`wc`], its constants [`params`] and its health check [`health`]; each keeps its own time
//! integration. [`build`] is the one place where the scheme, its kernel and the rheology are
//! resolved into a concrete type.

pub mod health;
pub mod isph;
pub mod params;
pub mod pdri;
pub mod wc;
pub mod wcsph;

use crate::boundary::wall::Wall;
use crate::config::{ConfigError, FluidParams, IsphFrame, IsphFreeSurface, Numerics, ParamSpec};
use crate::dispatch_rheology;
use crate::kernel::CubicSpline;
use crate::rheology::{AnyRheology, Rheology};
use crate::state::State;
use isph::Isph;
use params::Params;
use pdri::Pdri;
use wcsph::Wcsph;

pub const SCHEMES: &[(&str, &str)] = &[
    ("wcsph", "weakly compressible SPH of Fang et al. 2006"),
    (
        "pdri",
        "SPH with periodic density reinitialisation of Ren et al. 2015",
    ),
    ("isph", "incompressible SPH of King & Lind 2021"),
];

crate::choice_enum!(
    /// The SPH scheme: the `scheme` parameter. Item order is the FMU's (append only).
    SchemeKind, SCHEMES, Wcsph = "wcsph", Pdri = "pdri", Isph = "isph");

/// The row of the `scheme` parameter.
pub const SCHEME_ROW: ParamSpec =
    ParamSpec::choice::<SchemeKind>("scheme", 2, "Scheme", "wcsph", "SPH scheme");

/// What the rest of the solver may know about a scheme: data, never a branch on its name.
impl SchemeKind {
    /// Radius of the kernel's support in particle spacings: 2h with the weakly compressible
    /// schemes' cubic spline (h = `smoothing_ratio` dx), 3h = 3.9 dx with ISPH's quintic spline
    /// (whose h = 1.3 dx ignores `smoothing_ratio`).
    pub fn kernel_support(self, smoothing_ratio: f64) -> f64 {
        match self {
            SchemeKind::Isph => 3.0 * isph::H_OVER_DX,
            SchemeKind::Wcsph | SchemeKind::Pdri => 2.0 * smoothing_ratio,
        }
    }

    /// The wall model of the scheme's paper on straight walls, what `wall_boundary = auto`
    /// means there (Fang 2006's image particles, Ren 2015's ghost particles, King & Lind 2021's
    /// mirror particles).
    pub fn paper_wall_model(self) -> crate::boundary::Model {
        use crate::boundary::Model;
        match self {
            SchemeKind::Wcsph => Model::Image,
            SchemeKind::Pdri => Model::Ghost,
            SchemeKind::Isph => Model::Mirror,
        }
    }

    /// Whether the scheme is incompressible (a pressure Poisson equation, no equation of state
    /// or sound speed; every particle keeps its volume m / rho0).
    pub fn is_incompressible(self) -> bool {
        matches!(self, SchemeKind::Isph)
    }

    /// The free-surface pressure condition the scheme applies (`isph_free_surface`, with `auto`
    /// resolved to the scene's choice), or None for a scheme without one (the weakly
    /// compressible ones: their surface pressure follows from the density).
    pub fn free_surface_condition(
        self,
        numerics: &Numerics,
        auto: IsphFreeSurface,
    ) -> Option<IsphFreeSurface> {
        match self {
            SchemeKind::Isph => Some(match numerics.isph_free_surface {
                IsphFreeSurface::Auto => auto,
                chosen => chosen,
            }),
            SchemeKind::Wcsph | SchemeKind::Pdri => None,
        }
    }

    /// Whether the scheme reinitialises the density every `density_reinit_interval` steps (Ren
    /// 2015's PDRI-SPH): the one that reads that parameter.
    pub fn reinitialises_density(self) -> bool {
        matches!(self, SchemeKind::Pdri)
    }

    /// What `viscosph run` says instead of the sound speed, for a scheme that has none.
    pub fn sound_speed_text(self) -> Option<&'static str> {
        self.is_incompressible().then_some(
            "incompressible (isph): no sound speed; the time step follows the flow speed and the \
             polymer (and the viscosity with isph_viscous_step = explicit)",
        )
    }

    /// The checks of the numerics that belong to this scheme, for a domain with or without a
    /// free surface; `closed` names the scenes without one (for the message).
    pub fn validate(
        self,
        numerics: &Numerics,
        free_surface: bool,
        scene: &str,
        closed: &str,
    ) -> Result<(), ConfigError> {
        if self == SchemeKind::Isph && numerics.isph_frame == IsphFrame::Eulerian && free_surface {
            return Err(ConfigError::Inconsistent(format!(
                "isph_frame = 'eulerian' needs a domain without a free surface (scene = {closed}); \
                 the scene '{scene}' has one: use isph_frame = 'lagrangian'"
            )));
        }
        Ok(())
    }
}

/// Where a scheme's time went since profiling was turned on: wall and CPU seconds per pass and
/// per step (see [`crate::profile`]).
pub use crate::profile::Timings;

/// One SPH scheme instantiated for a concrete kernel and rheology, in N space dimensions
/// (`Scheme` alone: two).
pub trait Scheme<const N: usize = 2>: Send {
    /// Advance `state` by one step of at most `max_dt`; returns the step taken, or the cause of
    /// a numerical breakdown.
    fn step(&mut self, state: &mut State<N>, max_dt: f64) -> Result<f64, String>;
    /// Positions of the virtual (wall) particles currently built for the walls of `state`.
    fn wall_positions(&self, state: &State<N>) -> Vec<crate::dim::Vector<N>>;
    /// Where the time of the steps went (empty for schemes that time nothing, or while
    /// profiling is off).
    fn timings(&self) -> Timings {
        Timings::default()
    }
    /// Turn the per-pass timers on or off (off by default: a step then reads no clock).
    fn set_profiling(&mut self, _on: bool) {}
}

/// Build the scheme `kind` for the fluid and numerics of an effective configuration, with the
/// constants `params` (which carry what the scene resolved: spacing, body force, domain, free
/// surface) for the walls `plates`, resolving scheme, kernel and rheology once. Each scheme
/// takes the kernel of its paper: the cubic spline of Fang 2006 eq. (22), which Ren 2015
/// (section 2) uses too, for WCSPH and PDRI-SPH; King & Lind 2021's quintic spline
/// (h = 1.3 dx) for ISPH. Returns the scheme and whether the model carries a conformation
/// tensor.
pub fn build(
    kind: SchemeKind,
    fluid: &FluidParams,
    numerics: &Numerics,
    params: Params,
    plates: &[Wall],
) -> Box<dyn Scheme> {
    let model = AnyRheology::from_fluid(fluid);
    let h = numerics.smoothing_ratio * params.dx;
    dispatch_rheology!(model, m => {
        let scheme: Box<dyn Scheme> = match kind {
            SchemeKind::Wcsph => Box::new(Wcsph::new(CubicSpline::new(h), m, params, plates)),
            SchemeKind::Pdri => Box::new(Pdri::new(CubicSpline::new(h), m, params, plates)),
            SchemeKind::Isph => Box::new(Isph::new(m, params, numerics, plates)),
        };
        scheme
    })
}

/// The scheme `kind` in three dimensions, as [`build`] does in two, with Adami, Hu & Adams
/// 2012's dummy particles on every wall (the one wall model built for a plane; the
/// configuration refuses the others under `dimension = 3`), or why it cannot be built.
pub fn build_3d(
    kind: SchemeKind,
    fluid: &FluidParams,
    numerics: &Numerics,
    params: Params<3>,
    walls: &[Wall<3>],
) -> Result<Box<dyn Scheme<3>>, String> {
    use crate::boundary::dummy::DummyWall;
    use crate::boundary::Boundary;
    use crate::kernel::CubicSplineKernel;
    let model = AnyRheology::from_fluid(fluid);
    let kernel = CubicSplineKernel::<3>::new(numerics.smoothing_ratio * params.dx);
    let dummies = || -> Vec<Box<dyn Boundary<3>>> {
        walls
            .iter()
            .map(|_| {
                Box::new(DummyWall::new(
                    kernel,
                    params.domain,
                    params.dx,
                    params.gravity,
                )) as Box<dyn Boundary<3>>
            })
            .collect()
    };
    dispatch_rheology!(model, m => {
        match kind {
            SchemeKind::Wcsph => Ok(Box::new(Wcsph::with_walls(kernel, m, params.clone(), dummies()))
                as Box<dyn Scheme<3>>),
            SchemeKind::Pdri => Ok(Box::new(Pdri::with_walls(kernel, m, params.clone(), dummies()))
                as Box<dyn Scheme<3>>),
            SchemeKind::Isph => Ok(Box::new(Isph::<_, 3>::new(m, params.clone(), numerics, walls))
                as Box<dyn Scheme<3>>),
        }
    })
}

/// Whether the fluid's model carries a conformation tensor, and its rest state if so.
pub fn rest_conformation(fluid: &FluidParams) -> Option<crate::Mat2> {
    rest_conformation_in::<2>(fluid)
}

/// [`rest_conformation`] in N dimensions.
pub fn rest_conformation_in<const N: usize>(fluid: &FluidParams) -> Option<crate::dim::Tensor<N>>
where
    crate::dim::Const<N>: crate::dim::Dim,
{
    dispatch_rheology!(AnyRheology::from_fluid(fluid), m => rest_of::<_, N>(&m))
}

fn rest_of<R: Rheology, const N: usize>(m: &R) -> Option<crate::dim::Tensor<N>>
where
    crate::dim::Const<N>: crate::dim::Dim,
{
    R::ELASTIC.then(|| m.rest_conformation::<N>())
}
