//! Unit tests of the pressure Poisson machinery.

use super::*;
use crate::kernel::QuinticSpline;
use crate::operators::fixtures::{channel, disc, ParticleSet};
use crate::Vec2;
use std::f64::consts::PI;

fn kernel(dr: f64) -> QuinticSpline {
    QuinticSpline::new(1.3 * dr)
}

fn coefs(set: &ParticleSet) -> (NeighborList, Vec<f64>) {
    let k = kernel(set.dr);
    let nl = set.neighbours(k.radius());
    let vol = vec![set.dr * set.dr; set.x.len()];
    let c = morris_coefficients(&set.x, &vol, &nl, &k, &Domain::OPEN, None);
    (nl, c)
}

/// sum_j c_ij (phi_i - phi_j) evaluated directly from the pair coefficients.
fn laplacian(nl: &NeighborList, c: &[f64], phi: &dyn Fn(usize) -> f64, i: usize) -> f64 {
    let off = nl.offset(i);
    nl.of(i)
        .iter()
        .enumerate()
        .map(|(k, &j)| c[off + k] * (phi(i) - phi(j as usize)))
        .sum()
}

/// `f` run on a pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn all_options() -> [SolverOptions; 4] {
    [
        Preconditioner::Jacobi,
        Preconditioner::Ssor,
        Preconditioner::Ilu0,
        Preconditioner::Amg,
    ]
    .map(|p| SolverOptions {
        preconditioner: p,
        ..Default::default()
    })
}

/// Disc with the outer ring Dirichlet, p = x^2 + y^2 (lap p = 4): the solve reaches the
/// tolerance with every preconditioner, the solution satisfies the SPH equations row by row,
/// and it is the exact field to within the Morris Laplacian's discretisation error.
#[test]
fn dirichlet_disc_recovers_a_quadratic_pressure() {
    let dr = 0.05;
    let radius = 20.0 * dr;
    let set = disc(radius, dr, 0.1, 1);
    let (nl, c) = coefs(&set);
    let exact = |x: &Vec2| x.norm_squared();
    let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
        .iter()
        .map(|x| (x.norm() > radius - 3.0 * dr).then(|| exact(x)))
        .collect();
    let b = vec![4.0; set.n_fluid];
    let sys = assemble_poisson(set.n_fluid, &nl, &c, &GhostLink::NONE, &dir, &b);
    assert!(sys.anchor.is_none());
    for opts in all_options() {
        let mut p = vec![0.0; set.n_fluid];
        let st = solve(&sys, &mut p, &opts).unwrap();
        assert!(st.rel_residual <= 1e-8, "{st:?}");
        assert!(st.iterations > 1 && st.iterations < 200, "{st:?}");
        let mut worst = 0.0f64;
        for i in 0..set.n_fluid {
            if let Some(g) = dir[i] {
                assert_eq!(p[i], g);
                continue;
            }
            let full = |j: usize| p[j];
            let lap = laplacian(&nl, &c, &full, i);
            assert!((lap - 4.0).abs() < 1e-5, "row {i}: lap = {lap}");
            worst = worst.max((p[i] - exact(&set.x[i])).abs());
        }
        // Range of p is radius^2 = 1; the jittered lattice's Laplacian error is a few %.
        assert!(worst < 0.03 * radius * radius, "{worst}");
    }
}

/// With equal volumes and the uncorrected gradient, the assembled PPE matrix is symmetric
/// with a positive diagonal (Dirichlet columns moved to the right-hand side).
#[test]
fn poisson_matrix_is_symmetric() {
    let dr = 0.1;
    let set = disc(8.0 * dr, dr, 0.15, 2);
    let (nl, c) = coefs(&set);
    let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
        .iter()
        .map(|x| (x.norm() > 7.0 * dr).then_some(0.0))
        .collect();
    let sys = assemble_poisson(
        set.n_fluid,
        &nl,
        &c,
        &GhostLink::NONE,
        &dir,
        &vec![1.0; set.n_fluid],
    );
    let a = &sys.matrix;
    let get = |i: usize, j: usize| {
        let (cols, vals) = a.row(i);
        cols.iter()
            .position(|&c| c as usize == j)
            .map_or(0.0, |p| vals[p])
    };
    for i in 0..a.n() {
        assert!(a.val[a.diag[i]] > 0.0);
        let (cols, vals) = a.row(i);
        assert!(cols.windows(2).all(|w| w[0] < w[1]));
        for (&j, &v) in cols.iter().zip(vals) {
            let t = get(j as usize, i);
            assert!(
                (v - t).abs() <= 1e-12 * v.abs(),
                "A[{i},{j}] = {v}, A[{j},{i}] = {t}"
            );
        }
    }
}

/// Closed domain (periodic channel, Neumann walls through mirrors): p = cos(2 pi x / L)
/// cos(pi y / H) has zero normal derivative at the walls and lap p = -k^2 p. A constant is
/// added to the right-hand side (which an incompatible solve would turn into garbage): the
/// mean is removed, the null space pinned, the zero-mean solution matches the exact one.
#[test]
fn closed_channel_solution_is_the_exact_one_up_to_discretisation() {
    let error = |n: usize, opts: &SolverOptions| {
        let dr = 1.0 / n as f64;
        let (nx, ny) = (2 * n, n);
        let (l, h) = (nx as f64 * dr, ny as f64 * dr);
        let set = channel(nx, ny, dr, 0.0, 3.0 * 1.3 * dr, 3);
        let (nl, c) = coefs(&set);
        let k2 = (2.0 * PI / l).powi(2) + (PI / h).powi(2);
        let exact = |x: &Vec2| (2.0 * PI * x.x / l).cos() * (PI * x.y / h).cos();
        let b: Vec<f64> = set.x[..set.n_fluid]
            .iter()
            .map(|x| -k2 * exact(x) + 0.7)
            .collect();
        let ghosts = GhostLink {
            parent: &set.parent,
            sign: &[],
            offset: &[],
        };
        let sys = assemble_poisson(set.n_fluid, &nl, &c, &ghosts, &[], &b);
        assert!(sys.anchor.is_some());
        let mut p = vec![0.0; set.n_fluid];
        solve(&sys, &mut p, opts).unwrap();
        assert!(fixed_sum(&p).abs() < 1e-10 * set.n_fluid as f64);
        (0..set.n_fluid)
            .map(|i| (p[i] - exact(&set.x[i])).abs())
            .fold(0.0, f64::max)
    };
    for opts in all_options() {
        let (coarse, fine) = (error(20, &opts), error(40, &opts));
        // Second order: the Morris Laplacian's lattice error is O((k h)^2).
        assert!(coarse < 0.01 && fine < 0.3 * coarse, "{coarse} {fine}");
    }
}

/// Implicit viscosity with no-slip mirrors: a very large dt nu gives the steady Couette
/// profile u = U y / H (bottom wall at rest, top wall moving at U), which the mirrored Morris
/// Laplacian holds exactly on a lattice; dt nu -> 0 returns the right-hand side.
#[test]
fn implicit_viscous_step_reaches_couette_and_keeps_wall_velocity() {
    let dr = 0.1;
    let (nx, ny) = (12, 10);
    let h = ny as f64 * dr;
    let set = channel(nx, ny, dr, 0.0, 3.0 * 1.3 * dr, 4);
    let (nl, c) = coefs(&set);
    let u_top = Vec2::new(2.0, 0.0);
    let offset: Vec<Vec2> = (0..set.parent.len())
        .map(|m| {
            let y = set.x[set.n_fluid + m].y;
            if set.reflected[m] && y > h {
                2.0 * u_top
            } else {
                Vec2::zeros()
            }
        })
        .collect();
    let sign = set.signs_no_slip();
    let n = set.n_fluid;
    let rhs = vec![Vec2::new(0.3, -0.1); n];
    let opts = SolverOptions::default();
    // Steady limit: dt nu = 1e8 h^2.
    let mut u = vec![Vec2::zeros(); n];
    let st = solve_viscous(
        n,
        &nl,
        &c,
        1e8 * dr * dr,
        &set.parent,
        &sign,
        &offset,
        &rhs,
        &mut u,
        &opts,
    )
    .unwrap();
    assert!(
        st[0].rel_residual <= 1e-8 && st[1].rel_residual <= 1e-8,
        "{st:?}"
    );
    for (x, u) in set.x[..n].iter().zip(&u) {
        let exact = u_top.x * x.y / h;
        assert!((u.x - exact).abs() < 1e-5 * u_top.x, "{} vs {exact}", u.x);
        assert!(u.y.abs() < 1e-5 * u_top.x, "{}", u.y);
    }
    // dt nu = 0: the identity.
    let mut u = vec![Vec2::zeros(); n];
    solve_viscous(
        n,
        &nl,
        &c,
        0.0,
        &set.parent,
        &sign,
        &offset,
        &rhs,
        &mut u,
        &opts,
    )
    .unwrap();
    assert!(u.iter().zip(&rhs).all(|(a, b)| (a - b).norm() < 1e-12));
}

/// The coupled (both components, interleaved) viscous solve without a surface term is the
/// per-component one: the Couette profile between mirror walls, to the solver's tolerance, with
/// the ghosts' signs and offsets applied to both components.
#[test]
fn coupled_viscous_solve_without_surface_term_is_the_componentwise_one() {
    let dr = 0.1;
    let (nx, ny) = (12, 10);
    let h = ny as f64 * dr;
    let set = channel(nx, ny, dr, 0.0, 3.0 * 1.3 * dr, 4);
    let (nl, c) = coefs(&set);
    let u_top = Vec2::new(2.0, 0.0);
    let offset: Vec<Vec2> = (0..set.parent.len())
        .map(|m| {
            let y = set.x[set.n_fluid + m].y;
            if set.reflected[m] && y > h {
                2.0 * u_top
            } else {
                Vec2::zeros()
            }
        })
        .collect();
    let sign = set.signs_no_slip();
    let n = set.n_fluid;
    let rhs = vec![Vec2::new(0.3, -0.1); n];
    let opts = SolverOptions::default();
    let dt_nu = 1e8 * dr * dr;
    let zeros_k = vec![Vec2::zeros(); n];
    let w = vec![Vec2::new(1.0, 0.5); nl.pairs()];
    let surf = SurfaceTraction {
        k: &zeros_k,
        w: &w,
        along: 1.0,
        transposed: 1.0,
    };
    let mut u = vec![Vec2::zeros(); n];
    let st = solve_viscous_coupled(
        n,
        &nl,
        &c,
        dt_nu,
        &set.parent,
        &sign,
        &offset,
        &rhs,
        &mut u,
        &surf,
        &opts,
    )
    .unwrap();
    assert!(st.rel_residual <= 1e-8, "{st:?}");
    for (x, u) in set.x[..n].iter().zip(&u) {
        let exact = u_top.x * x.y / h;
        assert!((u.x - exact).abs() < 1e-5 * u_top.x, "{} vs {exact}", u.x);
        assert!(u.y.abs() < 1e-5 * u_top.x, "{}", u.y);
    }
}

#[test]
fn results_are_bitwise_independent_of_thread_count() {
    let dr = 0.05;
    let set = disc(40.0 * dr, dr, 0.15, 5);
    let run = |threads| {
        on_threads(threads, || {
            let (nl, c) = coefs(&set);
            let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
                .iter()
                .map(|x| (x.norm() > 39.0 * dr).then_some(0.0))
                .collect();
            let b: Vec<f64> = set.x[..set.n_fluid]
                .iter()
                .map(|x| (7.0 * x.x).sin() + x.y)
                .collect();
            let sys = assemble_poisson(set.n_fluid, &nl, &c, &GhostLink::NONE, &dir, &b);
            all_options()
                .iter()
                .map(|o| {
                    let mut p = vec![0.0; set.n_fluid];
                    let st = solve(&sys, &mut p, o).unwrap();
                    (
                        st.iterations,
                        p.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    )
                })
                .collect::<Vec<_>>()
        })
    };
    assert!(set.n_fluid > 2 * DOT_CHUNK, "several reduction chunks");
    assert_eq!(run(1), run(2));
}

#[test]
fn failures_are_errors_with_their_cause() {
    let dr = 0.05;
    let set = disc(20.0 * dr, dr, 0.1, 6);
    let (nl, c) = coefs(&set);
    let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
        .iter()
        .map(|x| (x.norm() > 19.0 * dr).then_some(0.0))
        .collect();
    let sys = assemble_poisson(
        set.n_fluid,
        &nl,
        &c,
        &GhostLink::NONE,
        &dir,
        &vec![1.0; set.n_fluid],
    );
    let opts = SolverOptions {
        max_iter: 3,
        preconditioner: Preconditioner::Jacobi,
        ..Default::default()
    };
    let mut p = vec![0.0; set.n_fluid];
    match solve(&sys, &mut p, &opts) {
        Err(SolveError::NotConverged {
            iterations,
            rel_residual,
        }) => {
            assert_eq!(iterations, 3);
            assert!(rel_residual > 1e-8 && rel_residual.is_finite());
        }
        other => panic!("{other:?}"),
    }
    // [[1, -1], [-1, 1]] with b = (1, 1): rhat . A r = 0 at the first iteration.
    let a = CsrMatrix::from_rows(vec![vec![(0, 1.0), (1, -1.0)], vec![(0, -1.0), (1, 1.0)]]);
    let m = Factor::new(&a, Preconditioner::Jacobi).unwrap();
    let mut x = vec![0.0; 2];
    let e = bicgstab(&a, &m, &[1.0, 1.0], &mut x, &SolverOptions::default()).unwrap_err();
    assert!(
        matches!(
            e,
            SolveError::Breakdown {
                quantity: "rho",
                iteration: 1,
                ..
            }
        ),
        "{e}"
    );
    // A zero diagonal cannot be Jacobi-preconditioned; a NaN right-hand side is refused.
    let z = CsrMatrix::from_rows(vec![vec![(1, 1.0)], vec![(0, 1.0)]]);
    assert_eq!(
        Factor::new(&z, Preconditioner::Jacobi).unwrap_err(),
        SolveError::ZeroPivot { row: 0 }
    );
    let e = bicgstab(&a, &m, &[f64::NAN, 1.0], &mut x, &SolverOptions::default()).unwrap_err();
    assert_eq!(e, SolveError::NonFinite { iteration: 0 });
}

/// A warm start from the solution of a nearby system needs fewer iterations for the same
/// absolute accuracy.
#[test]
fn warm_start_saves_iterations() {
    let dr = 0.05;
    let set = disc(20.0 * dr, dr, 0.1, 7);
    let (nl, c) = coefs(&set);
    let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
        .iter()
        .map(|x| (x.norm() > 19.0 * dr).then_some(0.0))
        .collect();
    let b1: Vec<f64> = set.x[..set.n_fluid].iter().map(|x| 1.0 + x.x).collect();
    let b2: Vec<f64> = b1.iter().zip(&set.x).map(|(b, x)| b + 0.01 * x.y).collect();
    let s1 = assemble_poisson(set.n_fluid, &nl, &c, &GhostLink::NONE, &dir, &b1);
    let s2 = assemble_poisson(set.n_fluid, &nl, &c, &GhostLink::NONE, &dir, &b2);
    for o in all_options() {
        let mut p = vec![0.0; set.n_fluid];
        solve(&s1, &mut p, &o).unwrap();
        let warm = solve(&s2, &mut p, &o).unwrap();
        let mut q = vec![0.0; set.n_fluid];
        let cold = solve(&s2, &mut q, &o).unwrap();
        assert!(warm.iterations < cold.iterations, "{warm:?} {cold:?}");
    }
}

/// The Morris Laplacian through mirror ghosts (Neumann walls) converges at second order on a
/// lattice: relative error of lap cos(2 pi x / L) cos(pi y / H) at 20 and 40 particles per H.
#[test]
fn morris_laplacian_is_second_order_with_mirror_walls() {
    let err = |n: usize| {
        let dr = 1.0 / n as f64;
        let (l, h) = (2.0, 1.0);
        let set = channel(2 * n, n, dr, 0.0, 3.0 * 1.3 * dr, 3);
        let (nl, c) = coefs(&set);
        let k2 = (2.0 * PI / l).powi(2) + (PI / h).powi(2);
        let f = |x: &Vec2| (2.0 * PI * x.x / l).cos() * (PI * x.y / h).cos();
        let phi = |j: usize| {
            let k = if j < set.n_fluid {
                j
            } else {
                set.parent[j - set.n_fluid] as usize
            };
            f(&set.x[k])
        };
        (0..set.n_fluid)
            .map(|i| (laplacian(&nl, &c, &phi, i) + k2 * f(&set.x[i])).abs() / k2)
            .fold(0.0, f64::max)
    };
    let (coarse, fine) = (err(20), err(40));
    assert!(
        coarse < 1e-2 && fine < 0.3 * coarse,
        "{coarse:.3e} {fine:.3e}"
    );
}

/// The implicit viscous step damps a Fourier mode by the backward-Euler factor
/// 1 / (1 + dt nu k^2) at any step size: the mode cos(2 pi x / L), uniform across a periodic
/// channel with Neumann (sign +1) mirrors, at dt nu k^2 = 0.05, 0.5 and 50 (1000 times the
/// explicit limit dt nu <= h^2 / 4 or so): amplitude within 0.5 % of the factor, no
/// overshoot, the y component untouched.
#[test]
fn implicit_viscous_step_damps_a_mode_by_the_backward_euler_factor() {
    let dr = 0.02;
    let (nx, ny) = (50, 10);
    let l = nx as f64 * dr;
    let set = channel(nx, ny, dr, 0.0, 3.0 * 1.3 * dr, 8);
    let (nl, c) = coefs(&set);
    let n = set.n_fluid;
    let k = 2.0 * PI / l;
    let rhs: Vec<Vec2> = set.x[..n]
        .iter()
        .map(|x| Vec2::new((k * x.x).cos(), 0.25))
        .collect();
    for a in [0.05, 0.5, 50.0] {
        let dt_nu = a / (k * k);
        let mut u = rhs.clone();
        solve_viscous(
            n,
            &nl,
            &c,
            dt_nu,
            &set.parent,
            &[],
            &[],
            &rhs,
            &mut u,
            &SolverOptions::default(),
        )
        .unwrap();
        let factor = 1.0 / (1.0 + a);
        for (ui, ri) in u.iter().zip(&rhs) {
            assert!(
                (ui.x - factor * ri.x).abs() < 5e-3 * factor,
                "a = {a}: {} vs {}",
                ui.x,
                factor * ri.x
            );
            assert!((ui.y - 0.25).abs() < 1e-9);
        }
    }
}

/// `solve_viscous` assembles the matrix once and gives the second component only its right-hand
/// side (`helmholtz_rhs`): its velocities must be bitwise those of assembling and solving each
/// component on its own, with moving walls (nonzero ghost offsets in both components) and a
/// disordered set, so that a change to `assemble` that `helmholtz_rhs` does not follow fails here.
#[test]
fn viscous_components_share_the_matrix_bitwise() {
    let dr = 0.1;
    let (nx, ny) = (12, 10);
    let h = ny as f64 * dr;
    let set = channel(nx, ny, dr, 0.12, 3.0 * 1.3 * dr, 9);
    let (nl, c) = coefs(&set);
    let wall = Vec2::new(1.5, -0.4);
    let offset: Vec<Vec2> = (0..set.parent.len())
        .map(|m| {
            if set.reflected[m] && set.x[set.n_fluid + m].y > h {
                2.0 * wall
            } else {
                Vec2::zeros()
            }
        })
        .collect();
    assert!(offset.iter().any(|o| o.x != 0.0 && o.y != 0.0));
    let sign = set.signs_no_slip();
    let n = set.n_fluid;
    let rhs: Vec<Vec2> = (0..n)
        .map(|i| Vec2::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos()))
        .collect();
    let opts = SolverOptions::default();
    let dt_nu = 2.0 * dr * dr;
    let mut u = rhs.clone();
    solve_viscous(
        n,
        &nl,
        &c,
        dt_nu,
        &set.parent,
        &sign,
        &offset,
        &rhs,
        &mut u,
        &opts,
    )
    .unwrap();
    for comp in 0..2 {
        let off: Vec<f64> = offset.iter().map(|o| o[comp]).collect();
        let b: Vec<f64> = rhs.iter().map(|r| r[comp]).collect();
        let ghosts = GhostLink {
            parent: &set.parent,
            sign: &sign,
            offset: &off,
        };
        let sys = assemble_helmholtz(n, &nl, &c, dt_nu, &ghosts, &b);
        assert_eq!(
            helmholtz_rhs(n, &nl, &c, -dt_nu, &ghosts, &b)
                .iter()
                .map(|v| v.to_bits())
                .collect::<Vec<_>>(),
            sys.rhs.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            "component {comp}: right-hand side"
        );
        let mut x = b.clone();
        solve(&sys, &mut x, &opts).unwrap();
        for (i, (xi, ui)) in x.iter().zip(&u).enumerate() {
            assert_eq!(
                xi.to_bits(),
                ui[comp].to_bits(),
                "component {comp}, row {i}"
            );
        }
    }
}

/// The coupled viscous system with a surface term on a disc of `cells` spacings `dr` in
/// radius (positions displaced by up to 0.15 dr), `dt_nu` the scale of its Laplacian, solved
/// on `threads` threads with preconditioner `p`: the solver's statistics and the solution.
/// The surface ring (3 dr deep) has an outward `k` and gradient weights `c_ij (x_j - x_i)`, so
/// its 2 x 2 blocks are not diagonal.
fn coupled_disc_solve(
    cells: f64,
    dr: f64,
    dt_nu: f64,
    threads: usize,
    p: Preconditioner,
) -> (SolveStats, Vec<Vec2>) {
    let radius = cells * dr;
    let set = disc(radius, dr, 0.15, 9);
    let n = set.n_fluid;
    on_threads(threads, || {
        let (nl, c) = coefs(&set);
        let k: Vec<Vec2> = set.x[..n]
            .iter()
            .map(|x| {
                if x.norm() > radius - 3.0 * dr {
                    x / x.norm() * (0.2 * dr)
                } else {
                    Vec2::zeros()
                }
            })
            .collect();
        let mut w = vec![Vec2::zeros(); nl.pairs()];
        for i in 0..n {
            let off = nl.offset(i);
            for (kk, &j) in nl.of(i).iter().enumerate() {
                w[off + kk] = (set.x[j as usize] - set.x[i]) * (-c[off + kk]);
            }
        }
        let surf = SurfaceTraction {
            k: &k,
            w: &w,
            along: 1.0,
            transposed: 1.0,
        };
        let rhs: Vec<Vec2> = set.x[..n]
            .iter()
            .map(|x| Vec2::new((5.0 * x.y).sin(), x.x * x.y))
            .collect();
        let mut u = rhs.clone();
        let opts = SolverOptions {
            preconditioner: p,
            ..Default::default()
        };
        let st =
            solve_viscous_coupled(n, &nl, &c, dt_nu, &[], &[], &[], &rhs, &mut u, &surf, &opts)
                .unwrap();
        (st, u)
    })
}

/// `a` and `b` agree to `tol` of `b`'s largest velocity.
fn assert_close(a: &[Vec2], b: &[Vec2], tol: f64) {
    let scale = b.iter().map(|v| v.norm()).fold(0.0, f64::max);
    for (a, b) in a.iter().zip(b) {
        assert!((a - b).norm() < tol * scale, "{a} vs {b}");
    }
}

/// The same bits in both solutions.
fn bitwise(a: &[Vec2], b: &[Vec2]) -> bool {
    a.iter()
        .zip(b)
        .all(|(a, b)| a.x.to_bits() == b.x.to_bits() && a.y.to_bits() == b.y.to_bits())
}

/// Block Jacobi on the coupled viscous system with a surface term (2 x 2 blocks that are not
/// diagonal at the surface): each block's inverse is the inverse, the solve reaches the
/// tolerance and agrees with ILU(0)'s to it, and its iterations and bits do not depend on the
/// thread count.
#[test]
fn block_jacobi_solves_the_coupled_viscous_system_on_any_thread_count() {
    let run = |threads, p| coupled_disc_solve(30.0, 0.05, 0.02, threads, p);
    let (st_b, u_b) = run(1, Preconditioner::BlockJacobi(2));
    let (st_i, u_i) = run(1, Preconditioner::Ilu0);
    assert!(st_b.rel_residual <= 1e-8 && st_i.rel_residual <= 1e-8);
    assert_close(&u_b, &u_i, 1e-6);
    let (st_2, u_2) = run(2, Preconditioner::BlockJacobi(2));
    assert_eq!(st_b.iterations, st_2.iterations);
    assert!(bitwise(&u_b, &u_2));
}

/// Nodal smoothed-aggregation AMG on the coupled viscous system, refined three times at a
/// fixed disc radius with the step proportional to the spacing (as ISPH's CFL step), so the
/// Laplacian's weight against the identity grows like 1 / dr: block Jacobi's iterations grow
/// with it, the multigrid's stay flat (less than 1.5 times), its solution agrees with
/// ILU(0)'s to the tolerance, and its iterations and bits do not depend on the thread count.
#[test]
fn nodal_amg_keeps_the_coupled_viscous_iterations_flat() {
    let radius = 1.5;
    let mut its = Vec::new();
    for cells in [15.0, 45.0] {
        let dr = radius / cells;
        let dt_nu = 0.02 * dr / 0.05;
        let run = |threads, p| coupled_disc_solve(cells, dr, dt_nu, threads, p);
        let (st_a, u_a) = run(1, Preconditioner::AmgNodal(2));
        let (st_b, _) = run(1, Preconditioner::BlockJacobi(2));
        let (_, u_i) = run(1, Preconditioner::Ilu0);
        assert!(st_a.rel_residual <= 1e-8);
        assert_close(&u_a, &u_i, 1e-6);
        let (st_2, u_2) = run(2, Preconditioner::AmgNodal(2));
        assert_eq!(st_a.iterations, st_2.iterations);
        assert!(bitwise(&u_a, &u_2), "{cells} cells: 1 and 2 threads differ");
        its.push((st_a.iterations, st_b.iterations));
    }
    eprintln!("iterations (nodal AMG, block Jacobi) at 15 and 45 cells: {its:?}");
    let ((a0, b0), (a1, b1)) = (its[0], its[1]);
    assert!(b1 as f64 > 1.5 * b0 as f64, "block Jacobi: {b0} -> {b1}");
    assert!((a1 as f64) < 1.5 * a0 as f64, "nodal AMG: {a0} -> {a1}");
    assert!(a1 < b1 / 3, "nodal AMG {a1} against block Jacobi {b1}");
}

/// The blocks' inverses: block times inverse is the identity, for blocks of 1, 2 and 3 with
/// off-diagonal entries and a row order that needs pivoting.
#[test]
fn block_inverses_invert_the_diagonal_blocks() {
    for k in 1..=3usize {
        let nb = 5;
        let mut rows = Vec::new();
        for b in 0..nb {
            for r in 0..k {
                let mut row = Vec::new();
                for c in 0..k {
                    // Small diagonal, large off-diagonal in the first row: pivoting needed.
                    let v = if r == c {
                        0.1 + b as f64
                    } else {
                        2.0 + (r + 2 * c) as f64
                    };
                    row.push(((k * b + c) as u32, v));
                }
                if b + 1 < nb {
                    row.push(((k * (b + 1)) as u32, -0.7));
                }
                rows.push(row);
            }
        }
        let a = CsrMatrix::from_rows(rows);
        let f = Factor::new(&a, Preconditioner::BlockJacobi(k)).unwrap();
        // Apply to each unit vector within block 2: M^-1 e_c, then the block times it.
        for c in 0..k {
            let mut e = vec![0.0; k * nb];
            e[2 * k + c] = 1.0;
            let mut z = vec![0.0; k * nb];
            f.apply(&a, &e, &mut z);
            for r in 0..k {
                let (cols, vals) = a.row(2 * k + r);
                let s: f64 = cols
                    .iter()
                    .zip(vals)
                    .filter(|(&j, _)| (j as usize) / k == 2)
                    .map(|(&j, &v)| v * z[j as usize])
                    .sum();
                let want = if r == c { 1.0 } else { 0.0 };
                assert!((s - want).abs() < 1e-12, "k {k}: {s} vs {want}");
            }
        }
    }
}

/// The coupled viscous system as its definition reads: each particle's rows as per-entry
/// (column, value) lists in neighbour order, merged by [`CsrMatrix::from_rows`].
#[allow(clippy::too_many_arguments)]
fn coupled_by_entries<const N: usize>(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    dt_nu: f64,
    parent: &[u32],
    sign: &[f64],
    offset: &[Vector<N>],
    rhs: &[Vector<N>],
    surf: &SurfaceTraction<N>,
) -> (CsrMatrix, Vec<f64>) {
    let mut rows = Vec::new();
    let mut b = Vec::new();
    for (i, &rhs_i) in rhs.iter().enumerate().take(n_fluid) {
        let off = nl.offset(i);
        let mut r: Vec<Vec<(u32, f64)>> = vec![Vec::new(); N];
        let mut bi = rhs_i;
        let mut diag = 1.0;
        let with_surface = surf.k[i] != Vector::<N>::zeros();
        let mut e_ii = Tensor::<N>::zeros();
        for (kk, &j) in nl.of(i).iter().enumerate() {
            let j = j as usize;
            if j == i {
                continue;
            }
            let a = -dt_nu * coef[off + kk];
            let e = if with_surface {
                surf.pair(i, off + kk)
            } else {
                Tensor::<N>::zeros()
            };
            let (col, s, shift) = if j < n_fluid {
                (j, 1.0, Vector::<N>::zeros())
            } else {
                let m = j - n_fluid;
                (parent[m] as usize, sign[m], offset[m])
            };
            diag += a;
            e_ii += e;
            bi += shift * a + e * shift;
            for (c, row) in r.iter_mut().enumerate() {
                if col == i || a != 0.0 {
                    row.push(((N * col + c) as u32, -a * s));
                }
                for d in 0..N {
                    if with_surface && e[(c, d)] != 0.0 {
                        row.push(((N * col + d) as u32, -e[(c, d)] * s));
                    }
                }
            }
        }
        for (c, row) in r.iter_mut().enumerate() {
            row.push(((N * i + c) as u32, diag));
            for d in 0..N {
                if with_surface {
                    row.push(((N * i + d) as u32, e_ii[(c, d)]));
                }
            }
        }
        rows.extend(r);
        b.extend(bi.iter().copied());
    }
    (CsrMatrix::from_rows(rows), b)
}

/// A jittered box of particles above a no-slip wall at x_last = 0 (mirror ghosts, sign -1, so
/// particles next to the wall see their own mirror) and a second image of the lowest layer
/// shifted sideways (sign +1: a parent reached through two ghosts), with pair coefficients of
/// which some are zero, surface weights with zero components and a surface term on a third of
/// the particles: the block-by-block assembly stores the same entries as the per-entry lists
/// and sums each in the same order, bit for bit, in 2D and 3D.
fn coupled_assembly_matches_the_entry_lists<const N: usize>(per_side: usize) {
    let dr = 0.1;
    let mut seed = 12345u64;
    let mut rnd = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut x: Vec<Vector<N>> = Vec::new();
    let cells = per_side.pow(N as u32);
    for c in 0..cells {
        let mut p = Vector::<N>::zeros();
        let mut rest = c;
        for d in 0..N {
            p[d] = ((rest % per_side) as f64 + 0.5 + 0.3 * rnd()) * dr;
            rest /= per_side;
        }
        x.push(p);
    }
    let n = x.len();
    let radius = 2.6 * dr;
    let (mut parent, mut sign, mut offset) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        if x[i][N - 1] < radius {
            let mut g = x[i];
            g[N - 1] = -g[N - 1];
            x.push(g);
            parent.push(i as u32);
            sign.push(-1.0);
            offset.push(Vector::<N>::from_fn(|d, _| 0.1 * (d + 1) as f64));
        }
    }
    for i in 0..n {
        if x[i][N - 1] < dr {
            let mut g = x[i];
            g[0] += 0.3 * dr;
            g[N - 1] = -g[N - 1] - 0.2 * dr;
            x.push(g);
            parent.push(i as u32);
            sign.push(1.0);
            offset.push(Vector::<N>::zeros());
        }
    }
    let grid = crate::neighbors::Grid::build(&x, radius, &Domain::OPEN);
    let nl = NeighborList::build(&grid, &x, &x[..n], radius, &Domain::OPEN);
    let mut coef = vec![0.0; nl.pairs()];
    let mut w = vec![Vector::<N>::zeros(); nl.pairs()];
    for i in 0..n {
        let off = nl.offset(i);
        for (kk, &j) in nl.of(i).iter().enumerate() {
            let p = off + kk;
            if j as usize != i && p % 7 != 3 {
                coef[p] = -(1.0 + rnd()) / (dr * dr);
            }
            w[p] = Vector::<N>::from_fn(|d, _| {
                if (p + d).is_multiple_of(5) {
                    0.0
                } else {
                    rnd() / dr
                }
            });
        }
    }
    let k: Vec<Vector<N>> = (0..n)
        .map(|i| {
            if i.is_multiple_of(3) {
                Vector::<N>::from_fn(|_, _| 0.05 * rnd() * dr)
            } else {
                Vector::<N>::zeros()
            }
        })
        .collect();
    let surf = SurfaceTraction {
        k: &k,
        w: &w,
        along: 0.7,
        transposed: 1.0,
    };
    let rhs: Vec<Vector<N>> = (0..n).map(|_| Vector::<N>::from_fn(|_, _| rnd())).collect();
    let dt_nu = 0.3 * dr * dr;
    let (want, want_b) =
        coupled_by_entries(n, &nl, &coef, dt_nu, &parent, &sign, &offset, &rhs, &surf);
    let got = assemble_coupled(n, &nl, &coef, dt_nu, &parent, &sign, &offset, &rhs, &surf);
    // The case exercises what it claims: self mirrors and a parent reached twice.
    assert!((0..n).any(|i| nl
        .of(i)
        .iter()
        .any(|&j| j as usize >= n && parent[j as usize - n] as usize == i)));
    assert!(want.nnz() > N * N * n);
    assert_eq!(got.matrix.row_ptr, want.row_ptr);
    assert_eq!(got.matrix.col, want.col);
    assert_eq!(got.matrix.diag, want.diag);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&got.matrix.val), bits(&want.val));
    assert_eq!(bits(&got.rhs), bits(&want_b));
}

#[test]
fn coupled_assembly_is_the_entry_lists_bitwise_in_2d_and_3d() {
    coupled_assembly_matches_the_entry_lists::<2>(14);
    coupled_assembly_matches_the_entry_lists::<3>(7);
}
