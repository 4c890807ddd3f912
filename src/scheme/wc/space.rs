//! What the weakly compressible schemes need of a space dimension beyond [`crate::dim::Dim`]: the two gather
//! passes of a rate evaluation and the void fraction of the health check.
//!
//! Both dimensions run the same packed-record passes with the AVX2 build of the pair loops
//! (`passes.rs`, generic over N); two dimensions ([`crate::dim::D2`]) have the void fraction on
//! cells of the plate's frame ([`fluid_void_fraction`]), three have none yet, so the fracture
//! check does not act there. A further dimension is one more impl.

use super::WcCore;
use crate::boundary::wall::Wall;
use crate::dim::Const;
use crate::kernel::Kernel;
use crate::particles::Fluid;
use crate::rheology::Rheology;
use crate::scheme::health::fluid_void_fraction;

/// The dimension-specific parts of [`WcCore`] (module documentation). Implemented for
/// `Const<N>`; generic code asks for `Const<N>: Dim + WcSpace<N>`.
pub trait WcSpace<const N: usize> {
    /// Pass 1 (a gather): velocity gradient (Fang 2006 eq. 23), continuity (eq. 26), stresses,
    /// and the kernel values of every pair inside the support, cached for pass 2. The fluid's
    /// and the walls' positions, velocities, densities and volumes are in the work arrays.
    fn pass1<K: Kernel<N>, R: Rheology>(core: &mut WcCore<K, R, N>, fl: &Fluid<N>);

    /// Pass 2 (a gather over the cached pairs): momentum (Fang eq. 27, Ren eq. 21) with
    /// artificial viscosity and stress; with EVSS, Morris' viscous Laplacian. The virtual
    /// particles' stresses are in the work arrays.
    fn pass2<K: Kernel<N>, R: Rheology>(core: &mut WcCore<K, R, N>, fl: &Fluid<N>);

    /// Void fraction of the fluid on cells of two spacings `dx` (see [`crate::health`]), None
    /// where the dimension has none (the fracture check then does not act).
    fn void_fraction(
        fl: &Fluid<N>,
        plate: Option<usize>,
        walls: &[Wall<N>],
        dx: f64,
    ) -> Option<f64>;
}

impl WcSpace<2> for Const<2> {
    #[inline]
    fn pass1<K: Kernel, R: Rheology>(core: &mut WcCore<K, R, 2>, fl: &Fluid) {
        core.pack_kinematics();
        core.pass1_packed(fl);
    }

    #[inline]
    fn pass2<K: Kernel, R: Rheology>(core: &mut WcCore<K, R, 2>, fl: &Fluid) {
        core.pack_stresses();
        core.pass2_packed(fl)
    }

    fn void_fraction(fl: &Fluid, plate: Option<usize>, walls: &[Wall], dx: f64) -> Option<f64> {
        let plate = plate.and_then(|k| walls.get(k)).and_then(Wall::plate);
        Some(fluid_void_fraction(fl, plate, walls, dx))
    }
}

impl WcSpace<3> for Const<3> {
    #[inline]
    fn pass1<K: Kernel<3>, R: Rheology>(core: &mut WcCore<K, R, 3>, fl: &Fluid<3>) {
        core.pack_kinematics();
        core.pass1_packed(fl);
    }

    #[inline]
    fn pass2<K: Kernel<3>, R: Rheology>(core: &mut WcCore<K, R, 3>, fl: &Fluid<3>) {
        core.pack_stresses();
        core.pass2_packed(fl)
    }

    fn void_fraction(_: &Fluid<3>, _: Option<usize>, _: &[Wall<3>], _: f64) -> Option<f64> {
        None
    }
}
