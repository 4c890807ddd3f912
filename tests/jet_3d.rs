//! The round jet (`jet` under `dimension = 3`): a circular nozzle of diameter D = `jet_width`,
//! particles entering through it on the disc's lattice, under the weakly compressible schemes.
//! King & Lind 2021's fluid, Newtonian, 6 particles across, a short fall (2 D) so that each
//! run takes seconds; the arrival against the slender-thread model and the tall fall are
//! `validation/jet`'s.

mod common;

use common::{i, r, s};
use viscosph::dim::Vector;
use viscosph::scene::jet::{arrival, buckling, disc_lattice, inflow_log, Nozzle};
use viscosph::scene::{Outputs, SceneConfig};
use viscosph::simulation::Simulation;
use viscosph_reference::analytic::falling_thread;

const D: f64 = 0.006;
const U0: f64 = 0.2;
const RHO: f64 = 1023.0;

/// King & Lind's jet fluid (Newtonian) through a round nozzle, `n` across, the exit
/// `h_over_d` diameters above the plate.
fn cfg(scheme: &str, n: i64, h_over_d: f64) -> SceneConfig {
    let mut c = SceneConfig::default();
    for (k, v) in [
        ("scene", s("jet")),
        ("dimension", i(3)),
        ("scheme", s(scheme)),
        ("rheology", s("newtonian")),
        ("density", r(RHO)),
        ("viscosity", r(8.8)),
        ("jet_width", r(D)),
        ("jet_velocity", r(U0)),
        ("nozzle_height", r(h_over_d * D)),
        ("particles_per_diameter", i(n)),
    ] {
        c.set(k, v).unwrap();
    }
    Simulation::validate(&c).unwrap();
    c
}

#[test]
fn the_disc_lattice_holds_the_nozzles_area() {
    // The row is the disc's area to within half a particle (1 % from 8 across; 1.0 % at 6,
    // 1.3 % at 7), and the lattice lies inside the nozzle with its outer ring half a spacing
    // from the wall.
    for n in 4..=24 {
        let dx = D / n as f64;
        let p = disc_lattice(0.5 * D, dx);
        let area = std::f64::consts::FRAC_PI_4 * D * D;
        let err = p.len() as f64 * dx * dx / area - 1.0;
        assert!(err.abs() <= 0.5 * dx * dx / area + 1e-12, "n = {n}: {err}");
        if n >= 8 {
            assert!(err.abs() < 0.01, "n = {n}: {} points, {err}", p.len());
        }
        let centre = p.iter().filter(|q| q[0] == 0.0 && q[1] == 0.0).count();
        assert!(centre <= 1, "n = {n}: {centre} points at the centre");
        let r_max = p.iter().map(|q| q[0].hypot(q[1])).fold(0.0, f64::max);
        assert!((r_max - (0.5 * D - 0.5 * dx)).abs() < 1e-12, "n = {n}");
        // Nearest neighbours no closer than 0.8 dx (the innermost ring of three at dx/2:
        // sqrt(3)/2 dx), so no pair starts inside the other's core.
        for (a, pa) in p.iter().enumerate() {
            for pb in &p[a + 1..] {
                let d = (pa[0] - pb[0]).hypot(pa[1] - pb[1]);
                assert!(d > 0.8 * dx, "n = {n}: {pa:?} {pb:?} {d}");
            }
        }
    }
}

#[test]
fn mass_enters_at_rho_times_the_nozzle_area_times_u0() {
    for scheme in ["wcsph", "pdri"] {
        let mut sim = Simulation::new(cfg(scheme, 6, 2.0)).unwrap();
        let eff = sim.effective_config().clone();
        let dx = eff.dx();
        let area = std::f64::consts::FRAC_PI_4 * D * D;
        let row = RHO * area * dx;
        let m0 = sim.fluid_mass();
        let n0 = sim.particle_count();
        // The nozzle's rows: rho0 A dx each, so the held fluid is rho0 A (rows dx).
        let rows = viscosph::scene::jet::buffer_rows(&eff) as f64;
        assert!(
            (m0 - row * rows).abs() < 1e-12 * m0,
            "{m0} vs {}",
            row * rows
        );
        let t_end = 0.06;
        let mut worst: f64 = 0.0;
        let mut steps = 0;
        while sim.state_time() < t_end {
            let t0 = sim.state_time();
            sim.advance_to(t0 + 1e-12).unwrap();
            steps += 1;
            let st = sim.state_3d().expect("a 3D run");
            let log = inflow_log(st);
            let injected = sim.scene().outputs_3d(st, &eff).jet.injected_mass;
            // Rows are emitted before a step for the inflow up to its start: the mass
            // is rho0 A U0 t0 less the part of a row not yet emitted (the log's phase).
            let exact = RHO * area * U0 * t0;
            assert!(
                (injected + RHO * area * log.phase - exact).abs() < 1e-9 * exact.max(row),
                "{scheme}: t = {t0}: {injected} kg + phase {} m, rho A U0 t = {exact} kg",
                log.phase
            );
            worst = worst.max((injected - exact).abs());
            // Nothing lost: the fluid is what the nozzle held and what entered since.
            assert!((sim.fluid_mass() - m0 - injected).abs() < 1e-9 * m0);
        }
        let t = sim.state_time();
        let exact = RHO * area * U0 * t;
        let injected = sim
            .scene()
            .outputs_3d(sim.state_3d().unwrap(), &eff)
            .jet
            .injected_mass;
        eprintln!(
            "{scheme}: {steps} steps, {} -> {} particles, injected {injected:.6e} kg, \
             rho A U0 t = {exact:.6e} kg, worst gap {worst:.3e} kg (one row {row:.3e} kg)",
            n0,
            sim.particle_count()
        );
        assert!(worst <= row * (1.0 + 1e-9), "{scheme}: within one row");
        // The particles below the exit have left the nozzle at U0, down the axis.
        let st = sim.state_3d().unwrap();
        let nz = viscosph::scene::jet::Nozzle::from_config(&eff);
        let free: Vec<usize> = (0..st.fluid.len())
            .filter(|&k| !nz.contains(&st.fluid.x[k]))
            .collect();
        assert!(!free.is_empty());
        let lowest = free
            .iter()
            .map(|&k| st.fluid.x[k].z)
            .fold(f64::INFINITY, f64::min);
        assert!(
            lowest < nz.exit - 5.0 * dx,
            "{scheme}: the jet left the nozzle"
        );
        let off = free
            .iter()
            .map(|&k| st.fluid.x[k].x.hypot(st.fluid.x[k].y))
            .fold(0.0, f64::max);
        assert!(off < D, "{scheme}: a round column, not a spray: {off}");
    }
}

#[test]
fn the_round_jet_refuses_a_container() {
    let mut c = cfg("wcsph", 6, 4.0);
    c.set("container_width", r(0.05)).unwrap();
    let e = Simulation::validate(&c).unwrap_err().to_string();
    assert!(
        e.contains("container_width") && e.contains("dimension = 3"),
        "{e}"
    );
}

#[test]
fn a_short_fall_stays_straight_and_lands_between_free_fall_and_the_thread_model() {
    // H = 4 D: the round column falls straight down its axis (no buckling onset: the seed
    // along x does not make it lean), and reaches the plate (the first output, every 2 ms,
    // with a heap) later than a free fall (viscosity holds it back) but before the
    // slender-thread model's free end: the SPH head, a blob about D long, slows within a
    // kernel support of the plate, which the model's free end does not have (measured at
    // 6 across under WCSPH: 0.096 s against the model's 0.1046 s, -8 %; the 12 D fall, where
    // that reach is a smaller share of the fall, is validation/jet's).
    for scheme in ["wcsph", "pdri"] {
        let c = cfg(scheme, 6, 4.0);
        let model = falling_thread::arrival(&c, falling_thread::ELEMENTS_PER_DIAMETER, 1.0)
            .expect("the thread arrives")
            .time;
        let (g, h) = (9.81, 4.0 * D);
        let free = (-U0 + (U0 * U0 + 2.0 * g * h).sqrt()) / g;
        let mut sim = Simulation::new(c).unwrap();
        let (series, err) = sim.record(1.25 * model, 0.002);
        assert!(err.is_none(), "{scheme}: {err:?}");
        let b = buckling(&series, D);
        let impact = b.impact.expect("the jet reaches the plate");
        let deflection = series
            .iter()
            .map(|s| s.1.jet.jet_deflection.abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{scheme}: arrival {impact:.4} s, thread model {model:.4} s ({:+.2} %), free fall \
             {free:.4} s, {} particles, |deflection| <= {:.4} D",
            100.0 * (impact / model - 1.0),
            sim.particle_count(),
            deflection / D,
        );
        assert!(
            free < impact && impact <= model,
            "{scheme}: {impact} vs {free}, {model}"
        );
        assert!(b.onset.is_none(), "{scheme}: {b:?}");
        assert!(deflection < 0.05 * D, "{scheme}: {deflection}");
        // The fall itself, where the plate is not yet felt: the lowest point passes D/2 above
        // the plate a little before the thread's free end has fallen as far (the SPH column,
        // 6 particles across, stretches more easily than the model's: measured 5.85 % early
        // under WCSPH and 6.35 % under PDRI here, WCSPH 3.0 % at 10 across: validation/jet),
        // and after a free fall.
        let mut above = sim.effective_config().clone();
        above.jet.nozzle_height -= 0.5 * D;
        let model_half =
            falling_thread::arrival(&above, falling_thread::ELEMENTS_PER_DIAMETER, 1.0)
                .expect("the thread arrives")
                .time;
        let t_half = arrival(&series, 0.5 * D).expect("the lowest point passes D/2");
        let contact = arrival(&series, 0.5 * D / 6.0).expect("the lowest point reaches the plate");
        let free_half = (-U0 + (U0 * U0 + 2.0 * g * (h - 0.5 * D)).sqrt()) / g;
        eprintln!(
            "{scheme}: lowest point at D/2 {t_half:.4} s, the model's {model_half:.4} s \
             ({:+.2} %), free fall {free_half:.4} s; contact {contact:.4} s",
            100.0 * (t_half / model_half - 1.0)
        );
        assert!(
            free_half < t_half && t_half < model_half && t_half > 0.93 * model_half,
            "{scheme}: {t_half} vs {free_half}, {model_half}"
        );
        assert!(
            t_half < contact && contact < 1.25 * model,
            "{scheme}: {contact}"
        );
    }
}

/// A synthetic round column, falling at 1 m/s (no heap) from the nozzle of `c` to the plate, its
/// cross-section the nozzle's disc lattice centred on the helix of radius `radius` and pitch
/// 100 D that turns at `frequency` [Hz] (negative: clockwise seen from above): its particles at
/// time t, appended to `st`'s nozzle.
fn helix(st: &mut viscosph::state::State<3>, c: &SceneConfig, radius: f64, frequency: f64, t: f64) {
    let nz = Nozzle::from_config(c);
    let dx = nz.dx;
    let rows = (nz.exit / dx).floor() as usize;
    for k in 0..rows {
        let z = (k as f64 + 0.5) * dx;
        let phi = std::f64::consts::TAU * (frequency * t + z / (100.0 * D));
        for p in disc_lattice(0.5 * D, dx) {
            st.fluid.x.push(Vector::<3>::new(
                radius * phi.cos() + p[0],
                radius * phi.sin() + p[1],
                z,
            ));
            st.fluid.v.push(Vector::<3>::new(0.0, 0.0, -1.0));
            st.fluid.rho.push(RHO);
        }
    }
}

#[test]
fn the_coil_outputs_read_a_helix_of_known_radius_and_frequency() {
    // The column's lowest part runs round a circle of radius R = D/2 at f: jet_coil_radius
    // reads R and jet_coil_frequency f (the turns counted by the azimuth followed before every
    // step, here every millisecond), in either sense; the seed's lean is jet_deflection, the
    // centre's x. A straight column reads 0 for both.
    let c = cfg("wcsph", 6, 4.0);
    let sim = Simulation::new(c).unwrap();
    let eff = sim.effective_config().clone();
    let base = sim.state_3d().unwrap().clone();
    let scene = sim.scene();
    for (radius, frequency) in [(0.5 * D, 4.0), (0.5 * D, -2.5), (0.0, 3.0)] {
        let mut log = base.scene.clone();
        let mut last = Default::default();
        let dt = 1e-3;
        for k in 0..=1000 {
            let t = k as f64 * dt;
            let mut st = base.clone();
            st.time = t;
            st.scene = log;
            helix(&mut st, &eff, radius, frequency, t);
            scene.before_step_3d(&eff, &mut st);
            log = st.scene.clone();
            let o = scene.outputs_3d(&st, &eff).jet;
            // The band one D above the plate: the helix's centre there.
            let phi = std::f64::consts::TAU * (frequency * t + 0.01);
            assert!(
                (o.jet_coil_radius - radius).abs() < 1e-3 * D,
                "t = {t}: {} vs {radius}",
                o.jet_coil_radius
            );
            assert!((o.jet_deflection - radius * phi.cos()).abs() < 1e-3 * D);
            if k == 100 && radius > 0.0 {
                // Before a full turn: the mean rate since the column left the axis.
                let f = o.jet_coil_frequency;
                assert!((f - frequency.abs()).abs() < 0.01 * frequency.abs(), "{f}");
            }
            last = o;
        }
        // Back on the axis, the coil is lost: no frequency.
        let mut st = base.clone();
        st.time = 1.001;
        st.scene = log;
        helix(&mut st, &eff, 0.0, 0.0, 1.001);
        scene.before_step_3d(&eff, &mut st);
        assert_eq!(scene.outputs_3d(&st, &eff).jet.jet_coil_frequency, 0.0);
        let expect = if radius > 0.0 { frequency.abs() } else { 0.0 };
        eprintln!(
            "helix R = {radius} m, f = {frequency} Hz: jet_coil_radius {:.4e} m, \
             jet_coil_frequency {:.4} Hz",
            last.jet_coil_radius, last.jet_coil_frequency
        );
        // A turn's period is known to a step (1 ms of 0.25-0.4 s).
        assert!(
            (last.jet_coil_frequency - expect).abs() <= 0.01 * expect.max(1.0),
            "{radius}, {frequency}: {last:?}"
        );
    }
    // In 2D the coil outputs are 0.
    let mut c2 = cfg("wcsph", 6, 4.0);
    c2.set("dimension", i(2)).unwrap();
    let mut sim2 = Simulation::new(c2).unwrap();
    let (series, err) = sim2.record(0.02, 0.01);
    assert!(err.is_none());
    assert!(series
        .iter()
        .all(|(_, o)| o.jet.jet_coil_radius == 0.0 && o.jet.jet_coil_frequency == 0.0));
}

#[test]
fn the_arrival_is_when_the_lowest_point_comes_within_a_height_of_the_plate() {
    // jet_tip_height falling at 1 m/s from 10 mm, outputs every 1 ms: it comes within 0.5 mm
    // (half a spacing at dx = 1 mm) at 9.5 ms, between two outputs (interpolated).
    let series: Vec<(f64, Outputs)> = (0..20)
        .map(|k| {
            let t = k as f64 * 1e-3;
            let mut o = Outputs::default();
            o.jet.jet_tip_height = (0.01 - t).max(0.0);
            (t, o)
        })
        .collect();
    let a = arrival(&series, 0.5e-3).unwrap();
    assert!((a - 9.5e-3).abs() < 1e-12, "{a}");
    assert_eq!(arrival(&series[..9], 0.5e-3), None);
    assert!((arrival(&series, 3e-3).unwrap() - 7e-3).abs() < 1e-12);
}
