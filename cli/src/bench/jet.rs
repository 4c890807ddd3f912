//! `viscosph bench jet`: King & Lind 2021 section IV.D's buckling jet (D = 6 mm, U0 = 0.2 m/s,
//! eta0 = 8.8 Pa s, rho = 1023 kg/m3, Re = 0.14, beta = 0.2) swept as in their Figs. 18-21:
//! Oldroyd-B at Wi = lambda U0 / D = 1/3, 5/3, 10/3, 20/3; FENE-P and FENE-CR with L^2 = 10 and
//! 100 and Giesekus with alpha = 0, 0.1, 0.2 at Wi = 10/3; and the Newtonian jet from nozzle
//! heights of 2 to 12 D, for the planar buckling criterion (H/D above about pi at low Re, as
//! quoted from Cruickshank & Munson 1981). Each run is tabulated by the time the jet reaches the
//! plate and its buckling onset, frequency and amplitude
//! ([`viscosph::scene::jet::buckling`]).

use super::case;
use crate::run::{run, RunOptions};
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::{SceneConfig, Value};
use viscosph::scene::jet::buckling;

const D: f64 = 0.006;
const U0: f64 = 0.2;

/// King & Lind's jet with `model` settings and the nozzle `h_over_d` widths above the plate.
fn jet(h_over_d: f64, model: &[(&str, Value)]) -> SceneConfig {
    let mut pairs: Vec<(&str, Value)> = vec![
        ("scene", Value::Text("jet".into())),
        ("density", Value::Real(1023.0)),
        ("viscosity", Value::Real(8.8)),
        ("viscosity_ratio", Value::Real(0.2)),
        ("jet_width", Value::Real(D)),
        ("jet_velocity", Value::Real(U0)),
        ("nozzle_height", Value::Real(h_over_d * D)),
    ];
    pairs.extend(model.iter().cloned());
    case(&pairs)
}

/// lambda for a Weissenberg number Wi = lambda U0 / D.
fn lambda(wi: f64) -> Value {
    Value::Real(wi * D / U0)
}

fn text(s: &str) -> Value {
    Value::Text(s.into())
}

/// The cases: (label, configuration).
pub fn cases() -> Vec<(String, SceneConfig)> {
    let mut v = Vec::new();
    for h in [2.0, 3.0, 4.0, 6.0, 12.0] {
        v.push((
            format!("Newtonian, H = {h} D"),
            jet(h, &[("rheology", text("newtonian"))]),
        ));
    }
    for (wi, name) in [
        (1.0 / 3.0, "1/3"),
        (5.0 / 3.0, "5/3"),
        (10.0 / 3.0, "10/3"),
        (20.0 / 3.0, "20/3"),
    ] {
        v.push((
            format!("Oldroyd-B, Wi = {name}"),
            jet(
                12.0,
                &[
                    ("rheology", text("oldroyd_b")),
                    ("relaxation_time", lambda(wi)),
                ],
            ),
        ));
    }
    for model in ["fene_p", "fene_cr"] {
        for l2 in [10.0, 100.0] {
            v.push((
                format!("{model}, L^2 = {l2}, Wi = 10/3"),
                jet(
                    12.0,
                    &[
                        ("rheology", text(model)),
                        ("relaxation_time", lambda(10.0 / 3.0)),
                        ("fene_L2", Value::Real(l2)),
                    ],
                ),
            ));
        }
    }
    for alpha in [0.0, 0.1, 0.2] {
        v.push((
            format!("Giesekus, alpha = {alpha}, Wi = 10/3"),
            jet(
                12.0,
                &[
                    ("rheology", text("giesekus")),
                    ("relaxation_time", lambda(10.0 / 3.0)),
                    ("giesekus_alpha", Value::Real(alpha)),
                ],
            ),
        ));
    }
    v
}

/// Run every case (`quick`: 4 particles across to 0.4 s, else 6 across to 0.7 s, King & Lind's
/// last figure time) and tabulate it.
pub fn bench_jet(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let (ppd, t_end) = if quick { (4, 0.4) } else { (6, 0.7) };
    let mut md = format!(
        "King & Lind's jet, {ppd} particles across, to t = {t_end} s, outputs every 5 ms \
         (buckling onset: |jet_deflection| > 0.1 D; amplitude: half the range of jet_deflection \
         over the second half of the record after impact).\n\n\
         | case | impact [s] | onset [s] | frequency [Hz] | amplitude / D | max tr(A) | steps | wall time [s] | breakdown |\n\
         |---|---|---|---|---|---|---|---|---|\n"
    );
    let mut csv = String::from("case,time,jet_deflection,drop_width,drop_height,injected_mass\n");
    for (label, mut c) in cases() {
        c.particles_per_diameter = ppd;
        let mut opts = RunOptions::for_scene(&c);
        opts.t_end = t_end;
        opts.output_interval = 0.005;
        eprintln!("bench jet: {label} ...");
        let res = run(&c, &opts)?;
        let b = buckling(&res.series, D);
        let opt = |x: Option<f64>| x.map_or("-".to_string(), |t| format!("{t:.3}"));
        writeln!(
            md,
            "| {label} | {} | {} | {} | {:.3} | {} | {} | {:.1} | {} |",
            opt(b.impact),
            opt(b.onset),
            if b.frequency > 0.0 {
                format!("{:.2}", b.frequency)
            } else {
                "-".into()
            },
            b.amplitude / D,
            res.max_trace_text(),
            res.steps,
            res.wall_seconds,
            res.error_text()
        )?;
        for (t, o) in &res.series {
            writeln!(
                csv,
                "{label},{t:.5e},{:.5e},{:.5e},{:.5e},{:.5e}",
                o.jet_deflection, o.drop_width, o.drop_height, o.injected_mass
            )?;
        }
    }
    std::fs::write(out.join("jet.csv"), &csv)?;
    std::fs::write(out.join("jet.md"), &md)?;
    Ok(md)
}
