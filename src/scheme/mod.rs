//! SPH schemes. A scheme advances a [`State`] by one time step; it reads as its paper's numbered
//! steps over the shared operators ([`crate::operators`]) and wall models
//! ([`crate::boundary`]).
//!
//! [`isph`] (King & Lind 2021) is incompressible: a pressure Poisson equation ([`ppe`]) instead
//! of an equation of state. [`wcsph`] (Fang 2006) and [`pdri`] (Ren 2015) share the weakly compressible rate evaluation
//! [`wc`], its constants [`params`] and its health check [`health`]; each keeps its own time
//! integration. [`build`] is the one place where the scheme, its kernel and the rheology are
//! resolved into a concrete type.

pub mod health;
pub mod isph;
pub mod params;
pub mod pdri;
pub mod ppe;
pub mod wc;
pub mod wcsph;

use crate::boundary::plate::Plate;
use crate::config::{ConfigError, SceneConfig, SchemeKind};
use crate::kernel::CubicSpline;
use crate::rheology::{AnyRheology, Rheology};
use crate::state::State;
use crate::{dispatch_rheology, Vec2};
use isph::Isph;
use params::Params;
use pdri::Pdri;
use wcsph::Wcsph;

/// One SPH scheme instantiated for a concrete kernel and rheology.
pub trait Scheme: Send {
    /// Advance `state` by one step of at most `max_dt`; returns the step taken, or the cause of
    /// a numerical breakdown.
    fn step(&mut self, state: &mut State, max_dt: f64) -> Result<f64, String>;
    /// Positions of the virtual (wall) particles currently built for the walls of `state`.
    fn wall_positions(&self, state: &State) -> Vec<Vec2>;
    /// Where the time of the incompressible scheme's steps went (None for the other schemes).
    fn timings(&self) -> Option<isph::IsphTimings> {
        None
    }
}

/// Build the scheme of `cfg` (an effective configuration) with the constants `params` for the
/// walls `plates`, resolving scheme, kernel and rheology once. Each scheme takes the kernel of its
/// paper: the cubic spline of Fang 2006 eq. (22), which Ren 2015 (section 2) uses too, for WCSPH and
/// PDRI-SPH; King & Lind 2021's quintic spline (h = 1.3 dx) for ISPH.
/// Returns the scheme and whether the model carries a conformation tensor.
pub fn build(
    cfg: &SceneConfig,
    params: Params,
    plates: &[Plate],
) -> Result<(Box<dyn Scheme>, bool), ConfigError> {
    let model = AnyRheology::from_config(cfg)?;
    Ok(dispatch_rheology!(model, m => {
        let elastic = elastic_of(&m);
        let scheme: Box<dyn Scheme> = match cfg.scheme {
            SchemeKind::Wcsph => Box::new(Wcsph::new(CubicSpline::new(cfg.h()), m, params, plates)),
            SchemeKind::Pdri => Box::new(Pdri::new(CubicSpline::new(cfg.h()), m, params, plates)),
            SchemeKind::Isph => Box::new(Isph::new(m, params, cfg, plates)),
        };
        (scheme, elastic)
    }))
}

fn elastic_of<R: Rheology>(_: &R) -> bool {
    R::ELASTIC
}
