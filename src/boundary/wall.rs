//! A rigid wall of the simulation state: its shape, pose and motion. Straight walls are
//! [`Plate`]s (a frame and the columns of virtual particles built along it, for the wall models
//! of Fang 2006 and Ren 2015); a circle ([`CircleWall`]) bounds a cylinder or a circular tank.
//! Every wall is a [`Shape`] (signed distance, closest point, normal into the fluid), which is all
//! the shape-independent wall models (King & Lind 2021's mirrors) and the contact checks read.

use super::plate::{Motion, Plate};
use crate::dim::Vector;
use crate::geometry::{Ball, Shape};
use serde::{Deserialize, Serialize};

/// A circular wall (a sphere in 3D): a fixed cylinder (fluid outside) or circular container (fluid inside).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CircleWall<const N: usize = 2> {
    pub ball: Ball<N>,
}

/// One rigid wall.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Wall<const N: usize = 2> {
    /// A straight wall (the drop's plate, a channel wall, a container's side); a plane in 3D.
    Straight(Plate<N>),
    /// A circle (a sphere in 3D).
    Circle(CircleWall<N>),
}

impl<const N: usize> From<Plate<N>> for Wall<N> {
    fn from(p: Plate<N>) -> Self {
        Wall::Straight(p)
    }
}

impl<const N: usize> From<Ball<N>> for Wall<N> {
    fn from(ball: Ball<N>) -> Self {
        Wall::Circle(CircleWall { ball })
    }
}

impl<const N: usize> Wall<N> {
    /// The straight wall, if this is one.
    #[inline]
    pub fn plate(&self) -> Option<&Plate<N>> {
        match self {
            Wall::Straight(p) => Some(p),
            Wall::Circle(_) => None,
        }
    }

    /// The straight wall, mutably, if this is one.
    #[inline]
    pub fn plate_mut(&mut self) -> Option<&mut Plate<N>> {
        match self {
            Wall::Straight(p) => Some(p),
            Wall::Circle(_) => None,
        }
    }

    /// The straight wall of a wall model that is only defined on straight walls (Fang's and
    /// Ren's virtual particles, the channel's profile fits): configuration validation refuses
    /// those models on any other shape before a simulation is built.
    #[inline]
    pub fn straight(&self) -> &Plate<N> {
        self.plate()
            .expect("a straight-wall model on a curved wall (refused by validation)")
    }

    /// [`Wall::straight`], mutably.
    #[inline]
    pub fn straight_mut(&mut self) -> &mut Plate<N> {
        self.plate_mut()
            .expect("a straight-wall model on a curved wall (refused by validation)")
    }

    /// Distance moved since t = 0 (along -n for a plate; circles are fixed) \[m\].
    #[inline]
    pub fn displacement(&self) -> f64 {
        self.plate().map_or(0.0, |p| p.displacement)
    }

    /// What moves the wall.
    pub fn motion(&self) -> Motion {
        self.plate().map_or(Motion::Fixed, |p| p.motion)
    }

    /// Velocity of the wall's material points (a rigid translation) [m/s].
    #[inline]
    pub fn wall_velocity(&self) -> Vector<N> {
        self.plate().map_or(Vector::zeros(), |p| p.wall_velocity())
    }

    /// Move the wall over a step of `dt` that ended at `t` ([`Plate::advance`]).
    pub fn advance(&mut self, t: f64, dt: f64) {
        if let Some(p) = self.plate_mut() {
            p.advance(t, dt);
        }
    }
}

impl<const N: usize> Shape<N> for Wall<N> {
    #[inline]
    fn signed_distance(&self, x: &Vector<N>) -> f64 {
        match self {
            Wall::Straight(p) => p.shape().signed_distance(x),
            Wall::Circle(c) => c.ball.signed_distance(x),
        }
    }
    fn closest_point(&self, x: &Vector<N>) -> Vector<N> {
        match self {
            Wall::Straight(p) => p.shape().closest_point(x),
            Wall::Circle(c) => c.ball.closest_point(x),
        }
    }
    fn normal(&self, x: &Vector<N>) -> Vector<N> {
        match self {
            Wall::Straight(p) => p.n,
            Wall::Circle(c) => c.ball.normal(x),
        }
    }
    fn is_straight(&self) -> bool {
        matches!(self, Wall::Straight(_))
    }
    fn reflect(&self, x: &Vector<N>) -> Vector<N> {
        match self {
            Wall::Straight(p) => p.shape().reflect(x),
            Wall::Circle(c) => c.ball.reflect(x),
        }
    }
    fn reflection_jacobian(&self, x: &Vector<N>) -> f64 {
        match self {
            Wall::Straight(_) => 1.0,
            Wall::Circle(c) => c.ball.reflection_jacobian(x),
        }
    }
}
