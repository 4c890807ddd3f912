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

#[test]
fn the_n_dimensional_ode_is_monaghans_in_2d_and_conserves_volume_in_3d() {
    for t in [0.001, 0.004, 0.008] {
        let (e, e2) = (
            elliptical_drop::exact(t),
            elliptical_drop::exact_axes::<2>(t),
        );
        assert!((e2.a[0] - e.a).abs() < 1e-12 && (e2.a[1] - 1.0 / e.a).abs() < 1e-12);
        assert!((e2.rates[1] - e.big_a).abs() < 1e-9 * elliptical_drop::A0);
        let e3 = elliptical_drop::exact_axes::<3>(t);
        assert!((e3.a.iter().product::<f64>() - 1.0).abs() < 1e-12, "{e3:?}");
        assert!(e3.rates.iter().sum::<f64>().abs() < 1e-9 * elliptical_drop::A0);
        // The z axis, not strained at t = 0, stretches under the pressure alone.
        assert!(e3.a[2] > 1.0 && e3.rates[2] > 0.0, "{e3:?}");
    }
}

/// The 3D elliptical drop (`dimension = 3`, u = A0 (-x, y, 0)) at `ppd` particles across the
/// diameter: the semi-axes at t = 0 and at 0.002 s steps up to `t_end`.
fn run_3d(scheme: &str, ppd: i64, t_end: f64) -> Vec<elliptical_drop::Axes<3>> {
    let c = config(&[
        ("scheme", Value::Text(scheme.into())),
        ("dimension", Value::Integer(3)),
        ("particles_per_diameter", Value::Integer(ppd)),
    ]);
    let mut sim = Simulation::new(c).unwrap();
    let st = sim.state_3d().unwrap();
    let mut out = vec![elliptical_drop::axes(&st.fluid, st.time)];
    let steps = (t_end / 0.002).round() as usize;
    for k in 1..=steps {
        sim.advance_to(0.002 * k as f64).unwrap();
        let st = sim.state_3d().unwrap();
        out.push(elliptical_drop::axes(&st.fluid, st.time));
    }
    out
}

#[test]
fn the_3d_drop_follows_its_exact_semi_axes() {
    for scheme in ["wcsph", "pdri"] {
        let a = run_3d(scheme, 20, 0.004);
        // The lattice sphere of 20 per diameter: 4169 particles, the tips on the sphere.
        assert!((a[0].extent_error()) < 1e-12, "{:?}", a[0]);
        for (k, x) in a.iter().enumerate().skip(1) {
            let moments = x.moment_error(&a[0]);
            println!(
                "{scheme}, t = {:.3} s: semi-axes (moments) {:?}, exact {:?}, error {:.4}; \
                 (extents) {:?}",
                0.002 * k as f64,
                x.moment_axes(&a[0]),
                x.exact,
                moments,
                x.extent
            );
            assert!(
                moments < 0.01,
                "{scheme} t = {}: {moments}",
                0.002 * k as f64
            );
            // The volume (product of the fitted semi-axes) is kept within 1 %.
            let volume = x.fitted_product() / a[0].fitted_product();
            assert!((volume - 1.0).abs() < 0.01, "{volume}");
        }
        // Well beyond the tolerance: the drop did deform (x by 34 %, z by 5 %).
        let end = a.last().unwrap();
        assert!(end.exact[0] < 0.7 && end.exact[2] > 1.04, "{end:?}");
    }
}
