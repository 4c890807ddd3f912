//! `viscosph bench rheologies`: Fang's drop (De = 1, beta = 0.1) with every rheology under every
//! scheme: W*(t*) and H*(t*) overlaid, like King & Lind 2021 Fig. 16.

use super::built_schemes;
use crate::run::{run, time_scale, RunOptions};
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::{RheologyKind, RHEOLOGIES};
use viscosph::scene::Outputs;
use viscosph::scene::SceneConfig;

/// Fang's drop with each rheology in `RHEOLOGIES` (model parameters at their defaults).
pub fn rheology_cases() -> Vec<(RheologyKind, SceneConfig)> {
    RHEOLOGIES
        .iter()
        .filter_map(|(n, _)| RheologyKind::parse(n))
        .map(|r| {
            let c = {
                let mut c = SceneConfig::default();
                c.fluid.rheology = r;
                c
            };
            (r, c)
        })
        .collect()
}

/// Fang's drop (De = 1, beta = 0.1) with every rheology under every scheme the solver builds
/// (issue 11: ISPH in the rheology benchmark like the other schemes): one table with a scheme
/// column, one CSV, and one W*(t*)/H*(t*) figure per scheme (`rheologies_<scheme>.png`, like
/// King & Lind 2021 Fig. 16).
pub fn bench_rheologies(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let ppd = if quick { 12 } else { 30 };
    let mut md = format!(
        "Every rheology under every scheme on Fang's drop (D = 20 mm, V = 1 m/s, eta0 = 4 Pa s, \
         De = 1, beta = 0.1) at {ppd} particles per diameter to t* = 8: the first peak of W*, W* \
         and H* at the end, the largest tr(A), breakdowns (King & Lind 2021 Fig. 16 shows the same \
         comparison for their scheme).\n\n"
    );
    md.push_str("| scheme | rheology | first peak W* | t* of peak | W* at t* = 8 | H* at t* = 8 | max tr(A) | wall time [s] | breakdown |\n|---|---|---|---|---|---|---|---|---|\n");
    let mut csv = String::from("scheme,rheology,time,t_star,w_star,h_star\n");
    for scheme in built_schemes() {
        let mut runs = Vec::new();
        for (r, mut c) in rheology_cases() {
            c.numerics.particles_per_diameter = ppd;
            c.scheme = scheme;
            let opts = RunOptions::for_scene(&c);
            eprintln!("bench rheologies: {scheme} {r} ...");
            let res = run(&c, &opts, &crate::predictions::ReferenceModels)?;
            let ts = time_scale(&c);
            let d = c.drop.drop_diameter;
            let w: Vec<(f64, f64)> = res
                .series
                .iter()
                .map(|(t, o)| (t / ts, o.shared.drop_width / d))
                .collect();
            let (peak_w, peak_t) = match first_peak(&w) {
                Some((t, w)) => (format!("{w:.3}"), format!("{t:.2}")),
                None => ("none (keeps spreading)".to_string(), "-".to_string()),
            };
            let last = res.series.last().expect("series").1;
            writeln!(
                md,
                "| {scheme} | {r} | {peak_w} | {peak_t} | {:.3} | {:.3} | {} | {:.2} | {} |",
                last.shared.drop_width / d,
                last.shared.drop_height / d,
                res.max_trace_text(),
                res.wall_seconds,
                res.error_text()
            )?;
            for (t, o) in &res.series {
                writeln!(
                    csv,
                    "{scheme},{r},{t:.6e},{:.4},{:.5},{:.5}",
                    t / ts,
                    o.shared.drop_width / d,
                    o.shared.drop_height / d
                )?;
            }
            let label = match res.error {
                Some(_) => format!("{r} (broke down)"),
                None => r.to_string(),
            };
            runs.push((label, res.series));
        }
        let cfg = SceneConfig {
            scheme,
            ..Default::default()
        };
        let refs: Vec<(String, &[(f64, Outputs)])> =
            runs.iter().map(|(n, s)| (n.clone(), &s[..])).collect();
        crate::run::plot_width_height(&out.join(format!("rheologies_{scheme}.png")), &cfg, &refs)?;
    }
    std::fs::write(out.join("rheologies.csv"), &csv)?;
    std::fs::write(out.join("rheologies.md"), &md)?;
    Ok(md)
}

/// The first spreading peak of W*: the first point, once the curve has risen 1 % above its
/// start, after which the curve falls by 1 % of it before it rises above it again (a retraction,
/// not a wiggle of one particle spacing). `None` if the drop never retracts (a Newtonian drop
/// keeps spreading): its largest W* is then its last, which is no peak.
pub fn first_peak(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let start = points.first()?.1;
    for (i, p) in points.iter().enumerate() {
        if p.1 <= 1.01 * start {
            continue;
        }
        for q in &points[i + 1..] {
            if q.1 > p.1 {
                break;
            }
            if q.1 < 0.99 * p.1 {
                return Some(*p);
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_curve_that_keeps_rising_has_no_first_peak() {
        // A Newtonian drop: W* rises, with a wiggle smaller than 1 %, to its last value.
        let rising: Vec<(f64, f64)> = (0..50)
            .map(|k| {
                let t = k as f64 * 0.1;
                (t, 1.0 + t - if k == 20 { 0.005 } else { 0.0 })
            })
            .collect();
        assert_eq!(first_peak(&rising), None);
        // An Oldroyd-B drop: up to 2.1 at t* = 2.2, retracts to 1.7, spreads again past 2.1.
        let retracting: Vec<(f64, f64)> = (0..80)
            .map(|k| {
                let t = k as f64 * 0.1;
                let w = if t <= 2.2 {
                    1.0 + 0.5 * t
                } else if t <= 4.0 {
                    2.1 - 0.4 * (t - 2.2) / 1.8
                } else {
                    1.7 + 0.3 * (t - 4.0)
                };
                (t, w)
            })
            .collect();
        let (t, w) = first_peak(&retracting).unwrap();
        assert!((t - 2.2).abs() < 1e-9 && (w - 2.1).abs() < 1e-9, "{t} {w}");
        assert!(
            retracting.last().unwrap().1 > w,
            "the final value is larger: not the peak"
        );
    }
}
