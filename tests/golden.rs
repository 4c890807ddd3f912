//! Golden trajectories: short runs of every scheme and scene compared **bitwise** with reference
//! files in `tests/golden/`. They guard refactors: a move of code that changes any bit of any
//! output, or of the final particle state, fails here.
//!
//! Regenerate the references only on purpose (a change of the physics or of the summation order),
//! with `VISCOSPH_BLESS=1 cargo test --release --test golden`, and say why in the commit message.
//! Each file holds, per record time, the bit patterns of the time and of every output, then a hash
//! (FNV-1a 64) of the bit patterns of the final fluid state (positions, velocities, densities,
//! conformation tensors) and of the accumulated wall impulse.
//!
//! Every case fixes `sound_speed` (and every other setting it depends on) explicitly, so a change
//! of a default does not move a golden file.

mod common;

use common::{i, r, s};
use std::fmt::Write;
use viscosph::boundary::plate::{Motion, Prescribed};
use viscosph::config::Value;
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

struct Case {
    name: &'static str,
    settings: &'static [(&'static str, Setting)],
    t_end: f64,
    records: usize,
    /// Outputs recorded beyond [`RECORDED`] (the scene's own: channel, jet, moving plate).
    extra: &'static [&'static str],
}

#[derive(Clone, Copy)]
enum Setting {
    R(f64),
    I(i64),
    S(&'static str),
}

fn value(v: Setting) -> Value {
    match v {
        Setting::R(x) => r(x),
        Setting::I(x) => i(x),
        Setting::S(x) => s(x),
    }
}

use Setting::{I, R, S};

/// Drops start a few millimetres above the plate, so the walls act within a few milliseconds.
const CASES: &[Case] = &[
    Case {
        name: "wcsph_drop_oldroyd_b",
        settings: &[
            ("scheme", S("wcsph")),
            ("rheology", S("oldroyd_b")),
            ("sound_speed", R(12.5)),
            ("initial_drop_height", R(0.012)),
            ("particles_per_diameter", I(16)),
        ],
        t_end: 0.008,
        records: 8,
        extra: &[],
    },
    Case {
        name: "wcsph_drop_newtonian_30deg",
        settings: &[
            ("scheme", S("wcsph")),
            ("rheology", S("newtonian")),
            ("sound_speed", R(12.5)),
            ("plate_inclination", R(30.0)),
            ("initial_drop_height", R(0.018)),
            ("particles_per_diameter", I(16)),
        ],
        t_end: 0.008,
        records: 8,
        extra: &[],
    },
    Case {
        name: "wcsph_drop_giesekus_log_evss_ren_stress",
        settings: &[
            ("scheme", S("wcsph")),
            ("rheology", S("giesekus")),
            ("conformation_method", S("log")),
            ("evss_alpha", R(0.05)),
            ("artificial_stress_kind", S("ren")),
            ("sound_speed", R(12.5)),
            ("plate_inclination", R(15.0)),
            ("initial_drop_height", R(0.018)),
            ("particles_per_diameter", I(16)),
        ],
        t_end: 0.008,
        records: 8,
        extra: &[],
    },
    Case {
        name: "pdri_drop_oldroyd_b",
        settings: &[
            ("scheme", S("pdri")),
            ("rheology", S("oldroyd_b")),
            ("sound_speed", R(12.5)),
            ("initial_drop_height", R(0.012)),
            ("particles_per_diameter", I(16)),
            ("density_reinit_interval", I(5)),
        ],
        t_end: 0.006,
        records: 6,
        extra: &[],
    },
    Case {
        name: "pdri_drop_cross_30deg_tait",
        settings: &[
            ("scheme", S("pdri")),
            ("rheology", S("cross")),
            ("artificial_stress_kind", S("ren")),
            ("equation_of_state", S("tait")),
            ("sound_speed", R(12.5)),
            ("plate_inclination", R(30.0)),
            ("initial_drop_height", R(0.018)),
            ("particles_per_diameter", I(16)),
            ("density_reinit_interval", I(7)),
        ],
        t_end: 0.006,
        records: 6,
        extra: &[],
    },
    Case {
        name: "pdri_drop_fene_p_fang_walls_stress",
        settings: &[
            ("scheme", S("pdri")),
            ("rheology", S("fene_p")),
            ("artificial_stress_kind", S("fang")),
            ("sound_speed", R(12.5)),
            ("plate_inclination", R(45.0)),
            ("initial_drop_height", R(0.018)),
            ("particles_per_diameter", I(12)),
        ],
        t_end: 0.006,
        records: 6,
        extra: &[],
    },
    Case {
        name: "isph_drop_oldroyd_b_30deg",
        settings: &[
            ("scheme", S("isph")),
            ("rheology", S("oldroyd_b")),
            ("conformation_method", S("log")),
            ("isph_frame", S("lagrangian")),
            ("isph_viscous_step", S("implicit")),
            ("plate_inclination", R(30.0)),
            ("initial_drop_height", R(0.014)),
            ("particles_per_diameter", I(16)),
        ],
        t_end: 0.008,
        records: 8,
        extra: &[],
    },
    Case {
        name: "wcsph_elliptical_drop",
        settings: &[
            ("scene", S("elliptical_drop")),
            ("scheme", S("wcsph")),
            ("particles_per_diameter", I(20)),
        ],
        t_end: 0.002,
        records: 4,
        extra: &[],
    },
    Case {
        name: "pdri_elliptical_drop",
        settings: &[
            ("scene", S("elliptical_drop")),
            ("scheme", S("pdri")),
            ("particles_per_diameter", I(20)),
        ],
        t_end: 0.002,
        records: 4,
        extra: &[],
    },
    Case {
        name: "wcsph_channel_oldroyd_b",
        settings: &[
            ("scene", S("channel")),
            ("scheme", S("wcsph")),
            ("rheology", S("oldroyd_b")),
            ("sound_speed", R(2.0)),
            ("particles_per_diameter", I(10)),
        ],
        t_end: 0.004,
        records: 4,
        extra: CHANNEL,
    },
    Case {
        name: "pdri_channel_newtonian_tait",
        settings: &[
            ("scene", S("channel")),
            ("scheme", S("pdri")),
            ("rheology", S("newtonian")),
            ("equation_of_state", S("tait")),
            ("sound_speed", R(2.0)),
            ("particles_per_diameter", I(10)),
            ("density_reinit_interval", I(5)),
        ],
        t_end: 0.004,
        records: 4,
        extra: CHANNEL,
    },
    Case {
        name: "isph_channel_oldroyd_b_lagrangian",
        settings: &[
            ("scene", S("channel")),
            ("scheme", S("isph")),
            ("rheology", S("oldroyd_b")),
            ("isph_frame", S("lagrangian")),
            ("particles_per_diameter", I(10)),
        ],
        t_end: 0.01,
        records: 4,
        extra: CHANNEL,
    },
    Case {
        name: "isph_channel_giesekus_eulerian_explicit",
        settings: &[
            ("scene", S("channel")),
            ("scheme", S("isph")),
            ("rheology", S("giesekus")),
            ("isph_frame", S("eulerian")),
            ("isph_viscous_step", S("explicit")),
            ("particles_per_diameter", I(10)),
        ],
        t_end: 0.01,
        records: 4,
        extra: CHANNEL,
    },
    Case {
        name: "wcsph_jet_oldroyd_b",
        settings: &[
            ("scene", S("jet")),
            ("scheme", S("wcsph")),
            ("sound_speed", R(7.0)),
            ("nozzle_height", R(0.02)),
            ("container_width", R(0.05)),
            ("particles_per_diameter", I(4)),
        ],
        t_end: 0.08,
        records: 4,
        extra: JET,
    },
    Case {
        name: "isph_jet_oldroyd_b_normal_stress",
        settings: &[
            ("scene", S("jet")),
            ("scheme", S("isph")),
            ("nozzle_height", R(0.02)),
            ("particles_per_diameter", I(4)),
        ],
        t_end: 0.08,
        records: 4,
        extra: JET,
    },
    Case {
        name: "isph_drop_newtonian_explicit_zero_pressure",
        settings: &[
            ("scheme", S("isph")),
            ("rheology", S("newtonian")),
            ("isph_viscous_step", S("explicit")),
            ("isph_free_surface", S("zero_pressure")),
            ("initial_drop_height", R(0.012)),
            ("particles_per_diameter", I(12)),
        ],
        t_end: 0.006,
        records: 3,
        extra: &[],
    },
    Case {
        name: "isph_drop_ucm_evss_normal_stress",
        settings: &[
            ("scheme", S("isph")),
            ("rheology", S("ucm")),
            ("evss_alpha", R(0.05)),
            ("isph_free_surface", S("normal_stress")),
            ("initial_drop_height", R(0.012)),
            ("particles_per_diameter", I(12)),
        ],
        t_end: 0.006,
        records: 3,
        extra: &[],
    },
    Case {
        name: "wcsph_drop_plate_moving_in",
        settings: &[
            ("scheme", S("wcsph")),
            ("rheology", S("newtonian")),
            ("sound_speed", R(15.0)),
            ("plate_velocity", R(-0.3)),
            ("plate_inclination", R(20.0)),
            ("initial_drop_height", R(0.014)),
            ("particles_per_diameter", I(12)),
        ],
        t_end: 0.006,
        records: 3,
        extra: &["plate_displacement"],
    },
    Case {
        name: "isph_drop_plate_moving_out",
        settings: &[
            ("scheme", S("isph")),
            ("rheology", S("oldroyd_b")),
            ("plate_velocity", R(0.1)),
            ("initial_drop_height", R(0.012)),
            ("particles_per_diameter", I(12)),
        ],
        t_end: 0.006,
        records: 3,
        extra: &["plate_displacement"],
    },
];

/// The channel's own outputs.
const CHANNEL: &[&str] = &["centreline_velocity", "flow_rate", "wall_shear_stress"];
/// The jet's own outputs.
const JET: &[&str] = &["injected_mass", "jet_deflection"];

/// The outputs recorded, by name (outputs added later do not change the files).
const RECORDED: [&str; 13] = [
    "drop_width",
    "drop_height",
    "wall_force_normal",
    "wall_force_tangential",
    "spread_front",
    "spread_back",
    "kinetic_energy",
    "volume_error",
    "max_conformation_trace",
    "min_conformation_det",
    "time_step",
    "particle_count",
    "void_fraction",
];

/// FNV-1a over 64-bit words.
fn fnv(words: impl IntoIterator<Item = u64>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for w in words {
        for b in w.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

fn trajectory(case: &Case) -> String {
    trajectory_of(case, |_| {})
}

/// The trajectory of `case` with `prepare` applied to the simulation before its first step.
fn trajectory_of(case: &Case, prepare: impl FnOnce(&mut Simulation)) -> String {
    let mut cfg = SceneConfig::default();
    for (k, v) in case.settings {
        cfg.set(k, value(*v)).unwrap();
    }
    let mut sim = Simulation::new(cfg).unwrap();
    prepare(&mut sim);
    let mut text = String::new();
    let dt = case.t_end / case.records as f64;
    for k in 0..=case.records {
        if k > 0 {
            sim.advance_to(k as f64 * dt)
                .unwrap_or_else(|e| panic!("{}: {e}", case.name));
        }
        let o = sim.outputs();
        write!(text, "{:016x}", sim.time().to_bits()).unwrap();
        for name in RECORDED.iter().chain(case.extra) {
            let v = o.get(name).unwrap();
            write!(text, " {:016x}", v.to_bits()).unwrap();
        }
        text.push('\n');
    }
    let st = sim.state();
    let f = &st.fluid;
    let words =
        f.x.iter()
            .chain(&f.v)
            .flat_map(|p| [p.x, p.y])
            .chain(f.rho.iter().copied())
            .chain(
                f.conf
                    .iter()
                    .flat_map(|a| a.iter().copied().collect::<Vec<_>>()),
            )
            .chain([st.wall_impulse.x, st.wall_impulse.y, st.time])
            .map(f64::to_bits)
            .chain([st.step, f.len() as u64]);
    writeln!(text, "state {:016x}", fnv(words)).unwrap();
    text
}

#[test]
fn golden_trajectories_are_bitwise_unchanged() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let bless = std::env::var_os("VISCOSPH_BLESS").is_some();
    let mut failed = Vec::new();
    for case in CASES {
        let got = trajectory(case);
        let path = dir.join(format!("{}.txt", case.name));
        if bless {
            std::fs::write(&path, &got).unwrap();
            continue;
        }
        let want = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (VISCOSPH_BLESS=1 writes it)", path.display()));
        if got != want {
            failed.push(case.name);
        }
    }
    assert!(failed.is_empty(), "trajectories changed: {failed:?}");
}

/// A wall owns its motion: the drop's plate moved by a prescribed constant velocity instead of
/// the input `plate_velocity` follows the input-driven goldens bit for bit.
#[test]
fn prescribed_plate_motion_follows_the_input_driven_goldens() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    for name in ["wcsph_drop_plate_moving_in", "isph_drop_plate_moving_out"] {
        let case = CASES.iter().find(|c| c.name == name).unwrap();
        let v = case
            .settings
            .iter()
            .find_map(|(k, v)| match (k, v) {
                (&"plate_velocity", Setting::R(v)) => Some(*v),
                _ => None,
            })
            .unwrap();
        let settings: Vec<_> = case
            .settings
            .iter()
            .filter(|(k, _)| *k != "plate_velocity")
            .copied()
            .collect();
        let still = Case {
            settings: Box::leak(settings.into_boxed_slice()),
            ..*case
        };
        let got = trajectory_of(&still, |sim| {
            sim.set_wall_motion(0, Motion::Prescribed(Prescribed::constant(v)))
                .unwrap()
        });
        let want = std::fs::read_to_string(dir.join(format!("{name}.txt"))).unwrap();
        assert_eq!(got, want, "{name}");
    }
}
