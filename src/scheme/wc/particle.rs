//! What every dimension's passes do for one particle: pass 1's stresses from the velocity
//! gradient ([`particle_stress`]) and pass 2's booking of the momentum rate, the wall force and
//! each wall's share ([`book_particle`]), outside the pair loops of passes.rs.

use super::ArtificialStress;
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::operators::stress;
use crate::rheology::{Evss, Rheology};
use crate::scheme::params::Params;

/// What pass 1 derives for a particle of density `rho` from its velocity gradient `kappa`, its
/// polymer stress `tau` (elastic models) and its kernel Hessian sum `hess`: the viscosity of
/// Morris' Laplacian, the total stress (Fang 2006 eq. 8 with the pressure of the equation of
/// state) and the artificial stress. Every dimension's pass 1 ends with it.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn particle_stress<R: Rheology, const N: usize>(
    model: &R,
    p: &Params<N>,
    art: &ArtificialStress,
    evss: &Evss,
    laplacian: bool,
    kappa: &Tensor<N>,
    tau: Option<&Tensor<N>>,
    rho: f64,
    hess: &Tensor<N>,
) -> (f64, Tensor<N>, Tensor<N>)
where
    Const<N>: Dim,
{
    let eta = model.solvent_viscosity(kappa);
    let sigma = stress::assemble(
        p.eos.pressure(rho) + p.background_pressure,
        eta,
        kappa,
        tau,
        evss,
        laplacian,
    );
    let art = art.of_particle(&sigma, rho, hess);
    (evss.viscous_viscosity(eta), sigma, art)
}

/// What pass 2 books for one fluid particle from `sum(from, to)`, the momentum rate of its
/// cached pairs `from..to` (per unit mass; the fluid neighbours `0..split` of `jj`, then the
/// virtual ones, ascending): the walls' force on it `wall_i`, with more than one wall each
/// wall's share in `split_i` (the walls' virtual particles end at `wall_ends`), and its
/// acceleration `acc_i` with gravity. The total keeps its one run over the virtual pairs; the
/// shares sum the same pairs wall by wall.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn book_particle<const N: usize>(
    sum: impl Fn(usize, usize) -> Vector<N>,
    jj: &[u32],
    split: usize,
    wall_ends: &[u32],
    mass: f64,
    gravity: Vector<N>,
    (acc_i, wall_i, split_i): (&mut Vector<N>, &mut Vector<N>, &mut [Vector<N>]),
) {
    let a = sum(0, split);
    let aw = sum(split, jj.len());
    *wall_i = aw * mass;
    if wall_ends.len() > 1 {
        let mut from = split;
        for (s, &end) in split_i.iter_mut().zip(wall_ends) {
            let to = from + jj[from..].partition_point(|&j| j < end);
            *s = sum(from, to) * mass;
            from = to;
        }
    }
    *acc_i = (a + aw) * mass + gravity;
}
