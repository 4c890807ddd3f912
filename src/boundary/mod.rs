//! Rigid walls: the plate geometry ([`plate`]) and the wall models that give the fluid something
//! to push against ([`ghost`]: Fang 2006's boundary + image particles and Ren 2015's wall + ghost
//! particles; [`mirror`]: King & Lind 2021's mirror particles).
//!
//! A wall model is a [`Boundary`]: for the current fluid it places virtual particles near the
//! wall (appended after the fluid in the scheme's work arrays), then fills their velocities and
//! stresses from the fluid before each pass that reads them. The force the virtual particles
//! exert on the fluid is the wall's reaction; the scheme sums it in its momentum pass. The wall's
//! shape, pose and motion (a [`wall::Wall`]: a straight [`plate::Plate`] or a circle, each a
//! [`crate::geometry::Shape`]) live in the simulation state, and the wall integrates its own
//! motion ([`plate::Motion`]); a boundary holds only what it rebuilds from the state
//! (interpolation lists, mirror parents), so nothing is stored twice.
//!
//! Which model fits which shape: Fang's and Ren's virtual particles are built in a straight
//! wall's frame (columns along it), so they take straight walls only; King & Lind's mirrors need
//! only the signed distance and the reflection across the local tangent, so they take any
//! [`crate::geometry::Shape`] (a circle: `x_m = 2 c(x) - x`, c the closest point).
//!
//! The incompressible scheme needs more than filled values: its pressure Poisson equation and
//! implicit viscous step take the virtual particles' values as unknowns of linear systems, so a
//! virtual value has to be an affine function of one fluid particle's. A model whose virtual
//! particles each continue one fluid particle across the wall says which
//! ([`Boundary::parents`]) and at what wall velocity ([`Boundary::wall_velocities`]); the
//! scheme then links a virtual pressure to its parent's (Neumann, plus the hydrostatic offset)
//! and a virtual velocity as no slip, `2 u_wall - u_parent`, without knowing the model's type.

pub mod dummy;
pub mod ghost;
pub mod mirror;
pub mod plate;
pub mod wall;
pub mod wall_profile;

use crate::config::WallBoundary;
use crate::dim::{Tensor, Vector};
use crate::geometry::Shape;
use crate::neighbors::Grid;
use crate::particles::Fluid;
use wall::Wall;

/// The wall models, as `wall_boundary` names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// Fang 2006's boundary + image particles ([`ghost::WallModel::Fang`]).
    Image,
    /// Ren 2015's wall + ghost particles ([`ghost::WallModel::Ren`]).
    Ghost,
    /// Adami, Hu & Adams 2012's dummy particles ([`dummy::DummyWall`]).
    Dummy,
    /// King & Lind 2021's mirror particles ([`mirror::MirrorWall`]).
    Mirror,
}

impl Model {
    /// Distance from a straight wall's line to the first row of a fluid lattice that fills a
    /// walled domain, in particle spacings: the rows the model's virtual particles leave to the
    /// fluid. One with wall particles on the wall line (Fang's and Ren's: the half cell next to
    /// the line is the wall particles'); one half with dummy particles (their rows at -(k + 1/2)
    /// dx, Adami, Hu & Adams 2012) and with mirrors (the first mirror row dx below the first
    /// fluid row). The lattice then runs on into the virtual rows and the fluid fills the whole
    /// region the walls leave it: N m / rho0 is its area. A lattice one spacing from a dummy
    /// wall leaves a strip half a spacing wide along it, which a weakly compressible fluid
    /// fills by expanding; in a closed cell that is a tension of rho0 c^2 times the strip's
    /// share of the area (the cylinder cell, `scene::cylinder_array`, "Lattice").
    pub fn lattice_offset(self) -> f64 {
        match self {
            Model::Image | Model::Ghost => 1.0,
            Model::Dummy | Model::Mirror => 0.5,
        }
    }
}

/// The model `choice` means for `wall` under a scheme whose own (paper's) straight-wall model
/// is `paper` (the incompressible scheme's is [`Model::Mirror`]): `auto` is `paper` on a
/// straight wall and dummy or mirror particles on a curved one. A model the scheme cannot take
/// (the incompressible scheme links every virtual particle to one fluid parent: mirrors only;
/// the weakly compressible schemes read the virtual particles' total stress, which mirrors do
/// not carry) or the shape does not fit (image and ghost particles are built along a straight
/// wall) is refused, naming the parameter.
pub fn resolve<const N: usize>(
    choice: WallBoundary,
    paper: Model,
    wall: &Wall<N>,
) -> Result<Model, String> {
    let incompressible = paper == Model::Mirror;
    let model = match choice {
        WallBoundary::Auto if wall.is_straight() => paper,
        WallBoundary::Auto if incompressible => Model::Mirror,
        WallBoundary::Auto => Model::Dummy,
        WallBoundary::Image => Model::Image,
        WallBoundary::Ghost => Model::Ghost,
        WallBoundary::Dummy => Model::Dummy,
        WallBoundary::Mirror => Model::Mirror,
    };
    let name = format!("wall_boundary = {}", choice.as_str());
    if incompressible != (model == Model::Mirror) {
        return Err(format!(
            "{name}: {} takes {}",
            if incompressible {
                "the incompressible scheme (isph)"
            } else {
                "a weakly compressible scheme (wcsph, pdri)"
            },
            if incompressible {
                "mirror particles only (or auto)"
            } else {
                "image, ghost or dummy particles (or auto)"
            }
        ));
    }
    if matches!(model, Model::Image | Model::Ghost) && !wall.is_straight() {
        return Err(format!(
            "{name}: image and ghost particles are built along a straight wall, and this scene has a curved one (use dummy or auto)"
        ));
    }
    Ok(model)
}

/// A wall model acting on the fluid through virtual particles, in N space dimensions
/// (`Boundary` alone: two).
pub trait Boundary<const N: usize = 2>: Send + Sync {
    /// Grow `wall` to cover the fluid at `fluid_x`, append the positions of this wall's virtual
    /// particles to `out`, and rebuild whatever the fill steps need (`fluid_grid` bins `fluid_x`
    /// with cells of side `radius`, the search radius).
    fn place(
        &mut self,
        wall: &mut Wall<N>,
        fluid_x: &[Vector<N>],
        fluid_grid: &Grid<N>,
        radius: f64,
        out: &mut Vec<Vector<N>>,
    );

    /// Velocities of this wall's virtual particles (in the order of [`Boundary::place`]).
    fn fill_velocities(&self, wall: &Wall<N>, fluid: &Fluid<N>, out: &mut [Vector<N>]);

    /// Whether the continuity equation of the weakly compressible schemes takes the wall's own
    /// velocity ([`wall::Wall::wall_velocity`]) for this wall's virtual particles instead of
    /// the velocities of [`Boundary::fill_velocities`]. Adami, Hu & Adams 2012 (section 2.3)
    /// extrapolate the no-slip velocity `2 u_wall - Shepard(u)` (eqs. 22-23) for the viscous
    /// forces only; the density rate sees the wall as it moves. With the extrapolated velocity
    /// in the continuity equation, a flow that diverges or converges along the wall reads its
    /// own tangential velocity differences, mirrored, as a compression of the first fluid rows.
    /// False (the default) for Fang's and Ren's walls, whose papers sum the continuity over
    /// their virtual particles' filled velocities.
    fn continuity_at_wall_velocity(&self) -> bool {
        false
    }

    /// Stresses of this wall's virtual particles from the fluid's total stresses `sigma` and
    /// elastic stresses `tau_p` (empty for inelastic models).
    fn fill_stresses(
        &self,
        wall: &Wall<N>,
        fluid: &Fluid<N>,
        sigma: &[Tensor<N>],
        tau_p: &[Tensor<N>],
        out: &mut [Tensor<N>],
    );

    /// Positions of the virtual particles placed at the last [`Boundary::place`], for output.
    fn positions(&self, wall: &Wall<N>) -> Vec<Vector<N>>;

    /// The fluid particle each virtual particle of the last [`Boundary::place`] continues across
    /// the wall, in the order of `place`, for a model whose virtual particles each follow one
    /// fluid particle (King & Lind 2021's mirror particles, section III.C). The incompressible
    /// scheme links a virtual particle's pressure and velocity to its parent's in its linear
    /// systems and gives it its parent's conformation. Empty (the default) for a model whose
    /// virtual particles interpolate several fluid particles (Fang's and Ren's walls): the
    /// incompressible scheme cannot take those.
    fn parents(&self) -> &[u32] {
        &[]
    }

    /// Append to `out`, per virtual particle of [`Boundary::parents`], the velocity of the wall's
    /// material at the point the particle is continued across: the no-slip continuation is
    /// `u_m = 2 u_wall - u_parent`, so a particle and its virtual twin average to the wall's
    /// velocity there. The default is the wall's rigid motion (the same at every point); a
    /// wall that rotates or deforms overrides it.
    fn wall_velocities(&self, wall: &Wall<N>, out: &mut Vec<Vector<N>>) {
        out.extend(std::iter::repeat_n(
            wall.wall_velocity(),
            self.parents().len(),
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ball;
    use crate::Vec2;

    /// `auto` is the paper's model on a straight wall and dummy or mirror particles on a curved
    /// one; a model the scheme or shape cannot take is refused, naming the parameter.
    #[test]
    fn wall_boundary_resolves_per_scheme_and_shape() {
        let straight = Wall::from(plate::Plate::new(0.0, 0.01));
        let circle = Wall::from(Ball::obstacle(Vec2::zeros(), 0.1));
        let auto = WallBoundary::Auto;
        for paper in [Model::Image, Model::Ghost, Model::Mirror] {
            assert_eq!(resolve(auto, paper, &straight), Ok(paper));
        }
        assert_eq!(resolve(auto, Model::Image, &circle), Ok(Model::Dummy));
        assert_eq!(resolve(auto, Model::Ghost, &circle), Ok(Model::Dummy));
        assert_eq!(resolve(auto, Model::Mirror, &circle), Ok(Model::Mirror));
        // Any weakly compressible model on a straight wall, under either weakly compressible
        // scheme.
        for (choice, model) in [
            (WallBoundary::Image, Model::Image),
            (WallBoundary::Ghost, Model::Ghost),
            (WallBoundary::Dummy, Model::Dummy),
        ] {
            assert_eq!(resolve(choice, Model::Ghost, &straight), Ok(model));
            let e = resolve(choice, Model::Mirror, &straight).unwrap_err();
            assert!(e.contains("wall_boundary") && e.contains("mirror"), "{e}");
        }
        assert_eq!(
            resolve(WallBoundary::Dummy, Model::Image, &circle),
            Ok(Model::Dummy)
        );
        for choice in [WallBoundary::Image, WallBoundary::Ghost] {
            let e = resolve(choice, Model::Image, &circle).unwrap_err();
            assert!(e.contains("wall_boundary") && e.contains("straight"), "{e}");
        }
        let e = resolve(WallBoundary::Mirror, Model::Image, &straight).unwrap_err();
        assert!(e.contains("wall_boundary = mirror"), "{e}");
        assert_eq!(
            resolve(WallBoundary::Mirror, Model::Mirror, &circle),
            Ok(Model::Mirror)
        );
    }
}
