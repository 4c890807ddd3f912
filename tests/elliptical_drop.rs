//! Monaghan's elliptical drop (Ren 2015 section 4.1) against its exact solution, at Ren's
//! resolution: 1961 particles (particles_per_diameter = 50), to t = 0.008 s.

use viscosph::config::Value;
use viscosph::scene::elliptical_drop::{self, semi_axes, SemiAxes};
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

/// Monaghan 1994's semi-major axis 1/a at t = 0.002, 0.004, 0.006, 0.008 and 0.0076 s (NOTES.md).
const NOTES: [(f64, f64); 5] = [
    (0.002, 1.2182847600),
    (0.004, 1.4647738180),
    (0.006, 1.7276845882),
    (0.008, 1.9993019547),
    (0.0076, 1.9445171907),
];

#[test]
fn exact_semi_axes_match_the_reference_values() {
    for (t, major) in NOTES {
        let e = elliptical_drop::exact(t);
        assert!(
            (1.0 / e.a - major).abs() < 2e-10,
            "t = {t}: 1/a = {:.10} vs {major}",
            1.0 / e.a
        );
    }
    // At t = 0 the drop is the unit circle stretching at A0.
    let e0 = elliptical_drop::exact(0.0);
    assert_eq!((e0.a, e0.big_a), (1.0, elliptical_drop::A0));
}

fn config(pairs: &[(&str, Value)]) -> SceneConfig {
    let mut c = SceneConfig::default();
    c.set("scene", Value::Text("elliptical_drop".into()))
        .unwrap();
    c.set("particles_per_diameter", Value::Integer(50)).unwrap();
    for (k, v) in pairs {
        c.set(k, v.clone()).unwrap();
    }
    c.validate().unwrap();
    c
}

/// Semi-axes and pressure roughness at t = 0.002, 0.004, 0.006, 0.008 s, and the run time.
fn run(c: SceneConfig) -> (Vec<(SemiAxes, f64)>, f64) {
    let mut sim = Simulation::new(c).unwrap();
    assert_eq!(sim.state().fluid.len(), 1961, "Ren's 1961 particles");
    let start = std::time::Instant::now();
    let mut out = Vec::new();
    for k in 1..=4 {
        sim.advance_to(0.002 * k as f64).unwrap();
        out.push((
            semi_axes(&sim.state().fluid, sim.state().time),
            sim.pressure_roughness(),
        ));
    }
    (out, start.elapsed().as_secs_f64())
}

#[test]
fn pdri_tracks_the_exact_semi_axis_better_than_wcsph() {
    let (wcsph, t_w) = run(config(&[("scheme", Value::Text("wcsph".into()))]));
    let w_end = wcsph[3].0;
    println!(
        "wcsph: semi-major error {:+.4} %, product (extents) {:.4}, product (fitted) {:.4}, \
         roughness {:.4}, {t_w:.2} s",
        100.0 * w_end.major_error,
        w_end.product,
        w_end.fitted_product,
        wcsph[3].1
    );
    for interval in [10, 20, 40] {
        let (pdri, t_p) = run(config(&[
            ("scheme", Value::Text("pdri".into())),
            ("density_reinit_interval", Value::Integer(interval)),
        ]));
        let p_end = pdri[3].0;
        println!(
            "pdri {interval}: semi-major error {:+.4} %, product (extents) {:.4}, product (fitted) \
             {:.4}, roughness {:.4}, {t_p:.2} s",
            100.0 * p_end.major_error,
            p_end.product,
            p_end.fitted_product,
            pdri[3].1
        );
        // Ren Fig. 4: reinitialisation improves the semi-axis; at 0.008 s and at 0.006 s.
        for k in [2, 3] {
            assert!(
                pdri[k].0.major_error.abs() < wcsph[k].0.major_error.abs(),
                "interval {interval}, t = {} s: pdri {:+.5} vs wcsph {:+.5}",
                0.002 * (k + 1) as f64,
                pdri[k].0.major_error,
                wcsph[k].0.major_error
            );
        }
        assert!(p_end.major_error.abs() < 0.002, "{}", p_end.major_error);
        // Ren Fig. 3: the pressure field is far smoother with reinitialisation.
        for k in 0..4 {
            assert!(
                pdri[k].1 < 0.5 * wcsph[k].1,
                "interval {interval}, t = {} s: roughness {} vs {}",
                0.002 * (k + 1) as f64,
                pdri[k].1,
                wcsph[k].1
            );
        }
        // Area conservation: the product of the fitted semi-axes stays within 1 % of 1 up to
        // t = 0.006 s. (At 0.008 s, where the drop is stretched 4:1, it is 1.017 for every scheme
        // and resolution we ran, and 1.03 from the extents: not within 1 %.)
        for (s, _) in &pdri[..3] {
            assert!((s.fitted_product - 1.0).abs() < 0.01, "{s:?}");
        }
    }
    assert!(w_end.major_error.abs() < 0.01);
    for (s, _) in &wcsph[..3] {
        assert!((s.fitted_product - 1.0).abs() < 0.01, "{s:?}");
    }
}
