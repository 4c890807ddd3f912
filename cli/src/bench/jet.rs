//! `viscosph bench jet`: King & Lind 2021 section IV.D's buckling jet (D = 6 mm, U0 = 0.2 m/s,
//! eta0 = 8.8 Pa s, rho = 1023 kg/m3, Re = 0.14, beta = 0.2) swept as in their Figs. 18-21:
//! Oldroyd-B at Wi = lambda U0 / D = 1/3, 5/3, 10/3, 20/3; FENE-P and FENE-CR with L^2 = 10 and
//! 100 and Giesekus with alpha = 0, 0.1, 0.2 at Wi = 10/3; and the Newtonian jet from nozzle
//! heights of 2 to 12 D, for the planar buckling criterion (H/D above about pi at low Re, as
//! quoted from Cruickshank & Munson 1981), the 2 D jet also for a long run. Every case runs
//! under ISPH (King & Lind's scheme; the jet's default is WCSPH, for the reasons in
//! [`viscosph::scene::jet::DEFAULTS`]); the cases that carry King &
//! Lind's trends (the Wi sweep, FENE-P against FENE-CR at L^2 = 10) also under WCSPH, side by
//! side. Each run is tabulated by the time the slender-sheet model of its fluid reaches the
//! plate ([`viscosph_reference::analytic::falling_sheet`], the reference for the arrival), the
//! time the jet does, and its buckling onset, frequency and amplitude
//! ([`viscosph::scene::jet::buckling`]).

use crate::run::{run, RunOptions};
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::Value;
use viscosph::scene::jet::{arrival, buckling};
use viscosph::scene::{SceneConfig, SceneKind};
use viscosph_reference::analytic::falling_sheet;

const D: f64 = 0.006;
const U0: f64 = 0.2;

/// King & Lind's jet (the scene's defaults) under `scheme` with `model` settings and the
/// nozzle `h_over_d` widths above the plate.
fn jet(scheme: &str, h_over_d: f64, model: &[(&str, Value)]) -> SceneConfig {
    let mut c = SceneConfig::for_scene(SceneKind::Jet);
    let mut pairs: Vec<(&str, Value)> = vec![
        ("scheme", Value::Text(scheme.into())),
        ("nozzle_height", Value::Real(h_over_d * D)),
    ];
    pairs.extend(model.iter().cloned());
    for (k, v) in pairs {
        c.set(k, v)
            .unwrap_or_else(|e| panic!("benchmark case: {e}"));
    }
    c
}

/// lambda for a Weissenberg number Wi = lambda U0 / D.
fn lambda(wi: f64) -> Value {
    Value::Real(wi * D / U0)
}

fn text(s: &str) -> Value {
    Value::Text(s.into())
}

/// One case: label, configuration and its end time (None: the sweep's).
pub type Case = (String, SceneConfig, Option<f64>);

/// The cases.
pub fn cases() -> Vec<Case> {
    // King & Lind's trends first, the fall-height sweep last.
    let mut v: Vec<Case> = Vec::new();
    for scheme in ["isph", "wcsph"] {
        for (wi, name) in [
            (1.0 / 3.0, "1/3"),
            (5.0 / 3.0, "5/3"),
            (10.0 / 3.0, "10/3"),
            (20.0 / 3.0, "20/3"),
        ] {
            v.push((
                format!("{scheme}, Oldroyd-B, Wi = {name}"),
                jet(
                    scheme,
                    12.0,
                    &[
                        ("rheology", text("oldroyd_b")),
                        ("relaxation_time", lambda(wi)),
                    ],
                ),
                None,
            ));
        }
        for model in ["fene_p", "fene_cr"] {
            let l2s: &[f64] = if scheme == "isph" {
                &[10.0, 100.0]
            } else {
                &[10.0]
            };
            for &l2 in l2s {
                v.push((
                    format!("{scheme}, {model}, L^2 = {l2}, Wi = 10/3"),
                    jet(
                        scheme,
                        12.0,
                        &[
                            ("rheology", text(model)),
                            ("relaxation_time", lambda(10.0 / 3.0)),
                            ("fene_L2", Value::Real(l2)),
                        ],
                    ),
                    None,
                ));
            }
        }
    }
    for alpha in [0.0, 0.1, 0.2] {
        v.push((
            format!("isph, Giesekus, alpha = {alpha}, Wi = 10/3"),
            jet(
                "isph",
                12.0,
                &[
                    ("rheology", text("giesekus")),
                    ("relaxation_time", lambda(10.0 / 3.0)),
                    ("giesekus_alpha", Value::Real(alpha)),
                ],
            ),
            None,
        ));
    }
    for h in [2.0, 3.0, 4.0, 6.0, 12.0] {
        v.push((
            format!("isph, Newtonian, H = {h} D"),
            jet("isph", h, &[("rheology", text("newtonian"))]),
            None,
        ));
    }
    // The 2 D jet long enough for a buckle to show if there is one: 2 s, about 30 periods of
    // the 12 D jet's folding.
    v.push((
        "isph, Newtonian, H = 2 D, to 2 s".into(),
        jet("isph", 2.0, &[("rheology", text("newtonian"))]),
        Some(2.0),
    ));
    v
}

/// Wall force [N/m] above which the plate counts as feeling the jet: ISPH's implicit viscous
/// solve leaves a residual force of 1e-9 to 1e-7 N/m before any fluid is near; the first
/// contact of the jet's head is above 1 N/m (the weight of the first D of fluid is 0.36 N/m).
pub const CONTACT_FORCE: f64 = 1e-3;

/// When the plate first felt the jet (the first output with a wall force above
/// [`CONTACT_FORCE`], i.e. the leading edge within the kernel support of the plate): the
/// arrival King & Lind's "reaches the plate earlier" compares, sharper than
/// [`viscosph::scene::jet::Buckling::impact`] (the first output with a heap, which waits for
/// fluid to slow down on the plate). None if never.
pub fn contact(series: &[(f64, viscosph::scene::Outputs)]) -> Option<f64> {
    series
        .iter()
        .find(|(_, o)| o.shared.wall_force_normal.abs() > CONTACT_FORCE)
        .map(|(t, _)| *t)
}

/// Run every case (`quick`: 4 particles across to 0.4 s, else 6 across to 0.7 s, King & Lind's
/// last figure time) and tabulate it.
pub fn bench_jet(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let (ppd, t_end) = if quick { (4, 0.4) } else { (6, 0.7) };
    // The quick mode's 4-across jets reach the plate within a fraction of a millisecond of
    // each other (FENE-P 0.3 ms before FENE-CR at Wi = 10/3): outputs every 0.1 ms there.
    let dt_out = if quick { 1e-4 } else { 1e-3 };
    let mut md = format!(
        "King & Lind's jet, {ppd} particles across, to t = {t_end} s unless stated, outputs every \
         {} ms (sheet model: when the slender-sheet model of the same fluid has fallen the nozzle height, \
         viscosph_reference::analytic::falling_sheet; contact: first output with a wall force; D/2: when the fluid's lowest point passed D/2 above the plate, interpolated between outputs, which resolves arrivals closer than a step; impact: first output with a heap; \
         buckling onset: |jet_deflection| > 0.1 D; amplitude: half the range of jet_deflection \
         over the second half of the record after impact).\n\n\
         | case | sheet model [s] | contact [s] | D/2 [s] | impact [s] | onset [s] | frequency [Hz] | amplitude / D | max tr(A) | steps | wall time [s] | breakdown |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
        dt_out * 1e3
    );
    let mut csv = String::from("case,time,jet_deflection,drop_width,drop_height,injected_mass\n");
    for (label, mut c, end) in cases() {
        c.numerics.particles_per_diameter = ppd;
        let mut opts = RunOptions::for_scene(&c);
        opts.t_end = if quick { t_end } else { end.unwrap_or(t_end) };
        opts.output_interval = dt_out;
        eprintln!("bench jet: {label} ...");
        let res = run(&c, &opts, &crate::predictions::ReferenceModels)?;
        let b = buckling(&res.series, D);
        let opt = |x: Option<f64>| x.map_or("-".to_string(), |t| format!("{t:.4}"));
        writeln!(
            md,
            "| {label} | {} | {} | {} | {} | {} | {} | {:.3} | {} | {} | {:.1} | {} |",
            opt(
                falling_sheet::arrival(&c, falling_sheet::ELEMENTS_PER_WIDTH, 10.0).map(|a| a.time)
            ),
            opt(contact(&res.series)),
            opt(arrival(&res.series, 0.5 * D)),
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
                o.jet.jet_deflection,
                o.shared.drop_width,
                o.shared.drop_height,
                o.jet.injected_mass
            )?;
        }
    }
    std::fs::write(out.join("jet.csv"), &csv)?;
    std::fs::write(out.join("jet.md"), &md)?;
    Ok(md)
}
