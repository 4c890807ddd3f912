//! Unit tests of the weakly compressible rate evaluation.

use super::*;
use crate::kernel::CubicSpline;
use crate::rheology::OldroydB;
use crate::SceneConfig; // test code: the lib root re-export

fn params(dx: f64, evss_alpha: f64) -> Params {
    let cfg = {
        let mut c = SceneConfig::default();
        c.numerics.artificial_viscosity_alpha = 0.0;
        c.numerics.artificial_viscosity_beta = 0.0;
        c.numerics.artificial_stress_epsilon = 0.0;
        c.fluid.gravity = 0.0;
        c.numerics.evss_alpha = evss_alpha;
        c
    };
    let mut p = Params::new(
        &cfg.fluid,
        &cfg.numerics,
        cfg.dx(),
        cfg.resolved_sound_speed(),
    );
    p.dx = dx;
    p
}

/// Interior accelerations of a block under a smooth velocity field, with EVSS off and on.
fn interior_acc(v: impl Fn(Vec2) -> Vec2 + Copy) -> (Vec<Vec2>, Vec<Vec2>) {
    let (n, dx) = (40, 0.01);
    let f = lattice_block(n, dx, |_| 1000.0, v);
    let model = OldroydB::new(4.0, 0.1, 0.02);
    let run = |alpha| {
        let mut core = WcCore::new(
            CubicSpline::new(1.5 * dx),
            model.clone(),
            params(dx, alpha),
            Vec::new(),
        );
        core.refresh_neighbors(&f.x, &mut []);
        core.rates(&f, &[]);
        let margin = 6;
        (0..f.len())
            .filter(|&k| {
                let (i, j) = ((k as i64) % n, (k as i64) / n);
                i >= margin && j >= margin && i < n - margin && j < n - margin
            })
            .map(|k| core.acc[k])
            .collect::<Vec<_>>()
    };
    (run(0.0), run(1.0))
}

#[test]
fn evss_leaves_the_viscous_force_of_a_smooth_flow_unchanged() {
    // A shear wave and a compressing (divergent) flow: with EVSS the viscous force is split
    // between the nested first-derivative operator and Morris' Laplacian, and must add up to
    // the same force in the bulk (King & Lind eq. 7 is an identity).
    const K: f64 = 2.0 * std::f64::consts::PI / 0.4;
    for v in [
        (|x: Vec2| Vec2::new((K * x.y).sin(), 0.0)) as fn(Vec2) -> Vec2,
        |x: Vec2| Vec2::new((K * x.x).sin(), 0.5 * (K * x.y).cos()),
    ] {
        let (plain, evss) = interior_acc(v);
        // The force each operator carries: the whole viscosity eta0 = 4 Pa s times k^2 U / rho.
        let scale = 4.0 * K * K / 1000.0;
        let worst = plain
            .iter()
            .zip(&evss)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).norm()));
        let solvent = plain.iter().fold(0.0f64, |m, a| m.max(a.norm()));
        assert!(
            solvent > 0.05 * scale,
            "the flow has a viscous force: {solvent}"
        );
        assert!(worst < 0.01 * scale, "{worst} vs {scale}");
    }
}
