//! Unit tests of the fused pair passes.

use super::*;
use crate::config::ArtificialStressKind;
use crate::kernel::CubicSpline;
use rand::{Rng, SeedableRng};

/// Pairs at random separations across the support (including r = 0 and the skin, where the
/// kernel's outer piece divides by zero or the select drops it), random approach speeds
/// and densities: the array loop, portable and AVX2, gives bitwise the values of the
/// kernel and the operators called pair by pair.
#[test]
fn pair_loop_is_bitwise_the_pairwise_operators_portable_and_avx2() {
    let dx = 0.01;
    let kernel = CubicSpline::new(1.3 * dx);
    let k = PairConst {
        alpha: 0.3,
        beta: 0.6,
        c: 12.6,
        h: kernel.h(),
        eta2: 0.0,
        dom: Domain::OPEN,
    };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(16);
    let n = 1003; // not a multiple of the vector width
    let xij: Vec<Vec2> = (0..n)
        .map(|s| {
            if s == 0 {
                return Vec2::zeros();
            }
            let r = rng.gen_range(0.0..1.2 * kernel.radius());
            let a: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
            Vec2::new(r * a.cos(), r * a.sin())
        })
        .collect();
    let vij: Vec<Vec2> = (0..n)
        .map(|_| Vec2::new(rng.gen_range(-2.0..2.0), rng.gen_range(-2.0..2.0)))
        .collect();
    let rho: Vec<f64> = (0..n).map(|_| rng.gen_range(950.0..1050.0)).collect();
    for kind in [ArtificialStressKind::Fang, ArtificialStressKind::Ren] {
        let art = ArtificialStress::new(&kernel, kind, 0.2, dx);
        let fill = || {
            (
                xij.clone(),
                vij.iter()
                    .zip(&xij)
                    .map(|(v, x)| v.dot(x))
                    .collect::<Vec<f64>>(),
                rho.clone(),
            )
        };
        let (mut g, mut pi, mut f) = fill();
        pair_kernels_dispatch(&kernel, Some(&art), &k, (&mut g, &mut pi, &mut f), false);
        for s in 0..n {
            let r2 = xij[s].norm_squared();
            let (wv, dw_r) = (kernel.w(r2.sqrt()), kernel.dw_over_r(r2.sqrt()));
            let pis =
                artificial::viscosity(k.alpha, k.beta, k.h, k.c, rho[s], &vij[s], &xij[s], r2);
            if s > 0 {
                // At r = 0 the kernel gradient is 0 either way (x_ij = 0).
                assert_eq!(
                    g[s].x.to_bits(),
                    (xij[s].x * dw_r).to_bits(),
                    "grad, slot {s}"
                );
                assert_eq!(
                    g[s].y.to_bits(),
                    (xij[s].y * dw_r).to_bits(),
                    "grad, slot {s}"
                );
            }
            assert_eq!(pi[s].to_bits(), pis.to_bits(), "Pi, slot {s}");
            if r2 < kernel.radius().powi(2) {
                assert_eq!(
                    f[s].to_bits(),
                    art.pair_factor(wv, r2).to_bits(),
                    "f, slot {s}"
                );
            }
        }
        assert!(pi.iter().any(|&p| p > 0.0) && f.iter().any(|&x| x > 0.0));
        // Without artificial stress f carries r^2 (read by nothing, but defined).
        let (mut g0, mut pi0, mut f0) = fill();
        pair_kernels_dispatch(&kernel, None, &k, (&mut g0, &mut pi0, &mut f0), false);
        for s in 0..n {
            assert_eq!(f0[s].to_bits(), xij[s].norm_squared().to_bits());
            assert_eq!(pi0[s].to_bits(), pi[s].to_bits());
        }
        if has_avx2() {
            let (mut g2, mut pi2, mut f2) = fill();
            pair_kernels_dispatch(&kernel, Some(&art), &k, (&mut g2, &mut pi2, &mut f2), true);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            let gbits = |v: &[Vec2]| {
                v.iter()
                    .flat_map(|x| [x.x.to_bits(), x.y.to_bits()])
                    .collect::<Vec<_>>()
            };
            assert_eq!(gbits(&g), gbits(&g2));
            assert_eq!(bits(&pi), bits(&pi2));
            assert_eq!(bits(&f), bits(&f2));
        }
    }
}
