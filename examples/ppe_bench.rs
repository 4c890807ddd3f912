//! Pressure Poisson solver comparison on realistic ISPH matrices (King & Lind 2021 eq. (25)):
//! BiCGStab with Jacobi (the paper's choice), SSOR and ILU(0), cold and warm started.
//!
//! `cargo run --release --example ppe_bench [threads]` prints one table row per case.
//! Cases: a disc of particles (quintic kernel, h = 1.3 dr) with its outer ring Dirichlet at about
//! 1,300 / 5,000 / 20,000 particles, on a lattice and displaced by up to +/-0.15 dr; a closed
//! channel (periodic in x, mirror walls, no Dirichlet row). The right-hand side is the SPH
//! divergence of a smooth velocity field plus 1 % noise; the "warm" solve is the next step
//! (positions moved by 0.01 dr, smooth velocity 1 % larger) started from the previous pressure.
//! Times include assembly of the matrix from given neighbour lists and Laplacian coefficients
//! and set-up of the preconditioner; best of three.
//! With `PPE_DUMP=dir` the matrices and right-hand sides are written for an external solver.

use std::io::Write;
use std::time::Instant;
use viscosph::kernel::{Kernel, QuinticSpline};
use viscosph::neighbors::Domain;
use viscosph::scheme::isph::ppe::*;
use viscosph::Vec2;
use viscosph_reference::fixtures::{channel, disc, splitmix, ParticleSet};

struct Case {
    name: String,
    set: ParticleSet,
    dirichlet: Vec<Option<f64>>,
}

fn rhs(set: &ParticleSet, k: &QuinticSpline, seed: u64, gain: f64) -> Vec<f64> {
    let nl = set.neighbours(k.radius());
    let scale = set.x[..set.n_fluid]
        .iter()
        .map(|x| x.norm())
        .fold(0.0, f64::max);
    let mut s = seed;
    let u: Vec<Vec2> = (0..set.n_fluid)
        .map(|i| {
            let x = set.x[i] / scale;
            gain * Vec2::new(
                x.x * x.y + (3.0 * x.y).sin(),
                -0.5 * x.y * x.y + (2.0 * x.x).cos(),
            ) + 0.01 * Vec2::new(splitmix(&mut s) - 0.5, splitmix(&mut s) - 0.5)
        })
        .collect();
    let ug = |j: usize| {
        if j < set.n_fluid {
            u[j]
        } else {
            let p = set.parent[j - set.n_fluid] as usize;
            if set.reflected[j - set.n_fluid] {
                -u[p]
            } else {
                u[p]
            }
        }
    };
    let v = set.dr * set.dr;
    (0..set.n_fluid)
        .map(|i| {
            nl.of(i)
                .iter()
                .map(|&j| {
                    let j = j as usize;
                    let xij = set.x[i] - set.x[j];
                    let g = xij * k.dw_over_r(xij.norm());
                    -v * (u[i] - ug(j)).dot(&g)
                })
                .sum::<f64>()
                / 1e-4
        })
        .collect()
}

/// Neighbour lists and Morris coefficients (given to the solver by the scheme: not timed).
fn coefficients(set: &ParticleSet) -> (viscosph::neighbors::NeighborList, Vec<f64>) {
    let k = QuinticSpline::new(1.3 * set.dr);
    let nl = set.neighbours(k.radius());
    let vol = vec![set.dr * set.dr; set.x.len()];
    let coef = morris_coefficients(&set.x, &vol, &nl, &k, &Domain::OPEN, None);
    (nl, coef)
}

fn assemble_case(
    c: &Case,
    set: &ParticleSet,
    (nl, coef): &(viscosph::neighbors::NeighborList, Vec<f64>),
    b: &[f64],
) -> LinearSystem {
    let ghosts = GhostLink {
        parent: &set.parent,
        sign: &[],
        offset: &[],
    };
    assemble_poisson(set.n_fluid, nl, coef, &ghosts, &c.dirichlet, b)
}

fn moved(set: &ParticleSet) -> ParticleSet {
    let mut m = set.clone();
    let d = 0.01 * set.dr;
    for (i, x) in m.x.iter_mut().enumerate().take(set.n_fluid) {
        let a = i as f64 * 0.618;
        *x += d * Vec2::new(a.sin(), a.cos());
    }
    // Ghosts follow their parents (mirrors and images of the moved fluid) in the channel.
    if !set.parent.is_empty() {
        let h = set.x[..set.n_fluid].iter().map(|x| x.y).fold(0.0, f64::max) + 0.5 * set.dr;
        let lx = set.x[..set.n_fluid].iter().map(|x| x.x).fold(0.0, f64::max) + 0.5 * set.dr;
        for g in 0..set.parent.len() {
            let p = set.parent[g] as usize;
            let (old_p, new_p) = (set.x[p], m.x[p]);
            let old_g = set.x[set.n_fluid + g];
            let dx = (old_g.x - old_p.x) / lx;
            let mut q = Vec2::new(new_p.x + dx.round() * lx, new_p.y);
            if set.reflected[g] {
                q.y = if old_g.y < 0.0 {
                    -new_p.y
                } else {
                    2.0 * h - new_p.y
                };
            }
            m.x[set.n_fluid + g] = q;
        }
    }
    m
}

fn main() {
    let threads: usize = std::env::args()
        .nth(1)
        .map_or(2, |a| a.parse().expect("threads"));
    let dump = std::env::var("PPE_DUMP").ok();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| run(dump.as_deref()));
}

fn run(dump: Option<&str>) {
    let mut cases = Vec::new();
    for (r_over_dr, label) in [(20.3, "1.3k"), (39.9, "5k"), (79.8, "20k"), (159.6, "80k")] {
        for jitter in [0.0, 0.15] {
            let dr = 1.0;
            let radius = r_over_dr * dr;
            let set = disc(radius, dr, jitter, 11);
            let dirichlet = set.x[..set.n_fluid]
                .iter()
                .map(|x| (x.norm() > radius - dr).then_some(0.0))
                .collect();
            cases.push(Case {
                name: format!(
                    "disc {label} {}",
                    if jitter > 0.0 {
                        "disordered"
                    } else {
                        "lattice"
                    }
                ),
                set,
                dirichlet,
            });
        }
    }
    for (nx, ny, jitter) in [(100, 50, 0.0), (100, 50, 0.15)] {
        let set = channel(nx, ny, 1.0, jitter, 3.0 * 1.3, 12);
        cases.push(Case {
            name: format!(
                "channel 5k {}",
                if jitter > 0.0 {
                    "disordered"
                } else {
                    "lattice"
                }
            ),
            set,
            dirichlet: Vec::new(),
        });
    }
    println!(
        "| case | N | nnz/row | Jacobi | Jacobi warm | SSOR | ILU(0) | ILU(0) warm | AMG | AMG warm | assembly |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for c in &cases {
        let k = QuinticSpline::new(1.3 * c.set.dr);
        let b1 = rhs(&c.set, &k, 1, 1.0);
        let set2 = moved(&c.set);
        let b2 = rhs(&set2, &k, 1, 1.01);
        let (c1, c2) = (coefficients(&c.set), coefficients(&set2));
        let t = Instant::now();
        let s1 = assemble_case(c, &c.set, &c1, &b1);
        let t_asm = t.elapsed().as_secs_f64() * 1e3;
        let s2 = assemble_case(c, &set2, &c2, &b2);
        if let Some(dir) = dump {
            std::fs::create_dir_all(dir).expect("dump dir");
            let name = c.name.replace(' ', "_");
            write_system(&format!("{dir}/{name}_1.bin"), &s1);
            write_system(&format!("{dir}/{name}_2.bin"), &s2);
        }
        let n = c.set.n_fluid;
        {
            let t = Instant::now();
            let amg = Amg::new(&s2.matrix).unwrap();
            let ts = t.elapsed().as_secs_f64() * 1e3;
            let mut z = vec![0.0; n];
            let t = Instant::now();
            for _ in 0..10 {
                amg.apply(&s2.matrix, &s2.rhs, &mut z);
            }
            let tc = t.elapsed().as_secs_f64() * 1e2;
            let t = Instant::now();
            for _ in 0..10 {
                s2.matrix.matvec(&s2.rhs, &mut z);
            }
            let tm = t.elapsed().as_secs_f64() * 1e2;
            // Cold solves with the V- and the W-cycle (iterations, and ms with set-up).
            let cycles: Vec<String> = [1, 2]
                .iter()
                .map(|&visits| {
                    let t = Instant::now();
                    let m = Factor::Amg(Box::new(Amg::with_visits(&s2.matrix, visits).unwrap()));
                    let mut p = vec![0.0; n];
                    let st = bicgstab(&s2.matrix, &m, &s2.rhs, &mut p, &SolverOptions::default());
                    let it = st.map_or(usize::MAX, |s| s.iterations);
                    format!(
                        "{visits} visits: {it} it {:.1} ms",
                        t.elapsed().as_secs_f64() * 1e3
                    )
                })
                .collect();
            eprintln!(
                "{}: sizes {:?} nnz {:?} setup {ts:.2} ms cycle {tc:.2} ms matvec {tm:.2} ms; {}",
                c.name,
                amg.sizes(&s2.matrix),
                amg.nnz(&s2.matrix),
                cycles.join(", ")
            );
        }
        let mut cells = Vec::new();
        for (pc, warm) in [
            (Preconditioner::Jacobi, false),
            (Preconditioner::Jacobi, true),
            (Preconditioner::Ssor, false),
            (Preconditioner::Ilu0, false),
            (Preconditioner::Ilu0, true),
            (Preconditioner::Amg, false),
            (Preconditioner::Amg, true),
        ] {
            let opts = SolverOptions {
                preconditioner: pc,
                ..Default::default()
            };
            let mut best = f64::INFINITY;
            let mut iters = 0;
            let mut err = None;
            for _ in 0..3 {
                let mut p = vec![0.0; n];
                if warm {
                    if let Err(e) = solve(&s1, &mut p, &opts) {
                        err = Some(e);
                        break;
                    }
                }
                let t = Instant::now();
                // Assembly counted in every solve: the matrix changes every step.
                let s = assemble_case(c, &set2, &c2, &b2);
                match solve(&s, &mut p, &opts) {
                    Ok(st) => iters = st.iterations,
                    Err(e) => {
                        err = Some(e);
                        break;
                    }
                }
                best = best.min(t.elapsed().as_secs_f64() * 1e3);
                assert!(s.rhs == s2.rhs);
            }
            cells.push(match err {
                None => format!("{iters} / {best:.1} ms"),
                Some(e) => format!("failed: {e}"),
            });
        }
        println!(
            "| {} | {} | {:.1} | {} | {:.1} ms |",
            c.name,
            n,
            s1.matrix.nnz() as f64 / n as f64,
            cells.join(" | "),
            t_asm
        );
    }
}

fn write_system(path: &str, s: &LinearSystem) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).expect("create"));
    let n = s.matrix.n() as u64;
    let nnz = s.matrix.nnz() as u64;
    f.write_all(&n.to_le_bytes()).expect("write");
    f.write_all(&nnz.to_le_bytes()).expect("write");
    for &r in &s.matrix.row_ptr {
        f.write_all(&(r as u64).to_le_bytes()).expect("write");
    }
    for &c in &s.matrix.col {
        f.write_all(&c.to_le_bytes()).expect("write");
    }
    for &v in &s.matrix.val {
        f.write_all(&v.to_le_bytes()).expect("write");
    }
    for &v in &s.rhs {
        f.write_all(&v.to_le_bytes()).expect("write");
    }
}
