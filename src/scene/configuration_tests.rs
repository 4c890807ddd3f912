//! Tests of the configuration: table defaults, ranges, scene files, String twins.

use super::*;
use crate::config::RheologyKind;
use crate::scene::{name_variable, name_variables};

#[test]
fn defaults_are_fang_oldroyd_b() {
    let c = SceneConfig::default();
    assert_eq!(c.fluid.rheology, RheologyKind::OldroydB);
    assert_eq!(c.drop.drop_diameter, 0.02);
    assert_eq!(c.fluid.viscosity_ratio, 0.1);
    assert_eq!(c.numerics.sound_speed, 0.0, "automatic by default");
    c.validate().unwrap();
}

#[test]
fn automatic_sound_speed_follows_the_impact_and_the_plate_inputs() {
    // Fang's drop: V = 1 m/s, centre 4 cm above the plate, so 3 cm of free fall before the
    // drop touches: U = sqrt(1 + 2 * 9.81 * 0.03) = 1.2604 m/s. The plate inputs may drive the
    // plate into it at max_plate_speed = 1 m/s: c = 10 (U + 1 m/s) = 22.60 m/s.
    let mut c = SceneConfig::default();
    let u = (1.0f64 + 2.0 * 9.81 * 0.03).sqrt();
    assert_eq!(c.plate.max_plate_speed, 1.0);
    assert!((c.max_expected_speed() - (u + 1.0)).abs() < 1e-12);
    assert!((c.resolved_sound_speed() - 10.0 * (u + 1.0)).abs() < 1e-12);
    // A fixed plate: Fang's 12.5 m/s, within 1 %.
    c.plate.max_plate_speed = 0.0;
    assert!((c.resolved_sound_speed() - 12.5).abs() / 12.5 < 0.01);
    // Five times faster: five times the sound speed, nearly.
    c.drop.impact_velocity = 5.0;
    assert!((c.resolved_sound_speed() - 10.0 * (25.0f64 + 0.5886).sqrt()).abs() < 1e-9);
    // A plate driven at up to 5 m/s adds its speed.
    c.plate.max_plate_speed = 5.0;
    assert!((c.resolved_sound_speed() - 10.0 * ((25.0f64 + 0.5886).sqrt() + 5.0)).abs() < 1e-9);
    // On an inclined plate the drop meets the plate earlier: less free fall.
    c.plate.max_plate_speed = 0.0;
    c.drop.impact_velocity = 0.0;
    c.plate.plate_inclination = 60.0;
    let fall: f64 = 0.04 - 0.01 / 0.5;
    assert!((c.max_expected_speed() - (2.0 * 9.81 * fall).sqrt()).abs() < 1e-12);
    // An explicit value wins.
    c.numerics.sound_speed = 30.0;
    assert_eq!(c.resolved_sound_speed(), 30.0);
}

#[test]
fn the_jets_automatic_sound_speed_covers_its_largest_inflow() {
    let mut c = SceneConfig::for_scene(SceneKind::Jet);
    let fall = 2.0 * 9.81 * c.jet.nozzle_height;
    // 0 = the start value of jet_velocity.
    assert_eq!(c.jet.max_jet_velocity, 0.0);
    assert!((c.max_expected_speed() - (0.04 + fall).sqrt()).abs() < 1e-12);
    c.jet.max_jet_velocity = 2.0;
    assert!((c.max_expected_speed() - (4.0 + fall).sqrt()).abs() < 1e-12);
}

#[test]
fn out_of_range_names_variable_value_and_range() {
    let mut c = SceneConfig::default();
    let e = c.set("plate_inclination", Value::Real(90.0)).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("plate_inclination") && msg.contains("90") && msg.contains("[0, 90)"),
        "{msg}"
    );
    let e = c
        .set("drop_diameter", Value::Real(-1.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("drop_diameter") && e.contains("-1"), "{e}");
    let e = c
        .set("viscosity_ratio", Value::Real(f64::NAN))
        .unwrap_err()
        .to_string();
    assert!(e.contains("viscosity_ratio") && e.contains("NaN"), "{e}");
    assert!(matches!(
        c.set("nonsense", Value::Real(1.0)),
        Err(ConfigError::Unknown(_))
    ));
}

#[test]
fn toml_round_trip_and_unknown_key() {
    let mut c = SceneConfig::default();
    c.set("rheology", Value::Text("newtonian".into())).unwrap();
    c.set("plate_inclination", Value::Real(30.0)).unwrap();
    let back = SceneConfig::from_toml_str(&c.to_toml_string()).unwrap();
    assert_eq!(back, c);
    let e = SceneConfig::from_toml_str("drop_diametr = 0.1")
        .unwrap_err()
        .to_string();
    assert!(e.contains("drop_diametr"), "{e}");
    let e = SceneConfig::from_toml_str("rheology = \"honey\"")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("rheology") && e.contains("honey") && e.contains("oldroyd_b"),
        "{e}"
    );
}

#[test]
fn both_names_of_the_drop_height_are_refused() {
    let c = SceneConfig::from_toml_str("drop_height = 0.05\n").unwrap();
    assert_eq!(
        c.drop.initial_drop_height, 0.05,
        "the older name still works alone"
    );
    let e = SceneConfig::from_toml_str("drop_height = 0.05\ninitial_drop_height = 0.06\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("drop_height") && e.contains("initial_drop_height") && e.contains("0.05"),
        "{e}"
    );
}

#[test]
fn model_specific_ranges_are_refused_with_the_parameter_named() {
    let mut c = {
        let mut c = SceneConfig::default();
        c.fluid.rheology = RheologyKind::PttLinear;
        c.fluid.ptt_epsilon = 0.6;
        c
    };
    let e = c.validate().unwrap_err().to_string();
    assert!(e.contains("ptt_epsilon") && e.contains("0.6"), "{e}");
    c.fluid.rheology = RheologyKind::PttExponential;
    c.validate().unwrap();
    c.fluid.rheology = RheologyKind::Cross;
    c.fluid.cross_viscosity_inf = 5.0;
    let e = c.validate().unwrap_err().to_string();
    assert!(
        e.contains("cross_viscosity_inf") && e.contains("viscosity"),
        "{e}"
    );
}

#[test]
fn huge_resolution_is_refused() {
    let c = {
        let mut c = SceneConfig::default();
        c.numerics.particles_per_diameter = 4000;
        c
    };
    let e = c.validate().unwrap_err().to_string();
    assert!(
        e.contains("particles_per_diameter") && e.contains("memory"),
        "{e}"
    );
}

#[test]
fn string_twins_set_the_enumeration_by_name() {
    let mut c = SceneConfig::default();
    c.set("rheology_name", Value::Text("giesekus".into()))
        .unwrap();
    assert_eq!(c.fluid.rheology, RheologyKind::Giesekus);
    assert_eq!(c.item_name("rheology").unwrap(), "giesekus");
    let e = c
        .set("scheme_name", Value::Text("sph".into()))
        .unwrap_err()
        .to_string();
    assert!(e.contains("scheme") && e.contains("'wcsph'"), "{e}");
    let e = c
        .set("rheology_name", Value::Integer(8))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("rheology_name") && e.contains("'giesekus'"),
        "{e}"
    );
    let twins: Vec<String> = name_variables().map(|(_, n, _)| n).collect();
    assert_eq!(
        twins,
        [
            "scene_name",
            "scheme_name",
            "rheology_name",
            "conformation_method_name",
            "artificial_stress_kind_name",
            "equation_of_state_name",
            "viscous_operator_name",
            "isph_frame_name",
            "isph_viscous_step_name",
            "isph_free_surface_name",
            "wall_boundary_name",
            "plate_coupling_name",
            "drop_shape_name",
        ]
    );
    assert!(name_variable("plate_inclination_name").is_none());
}

#[test]
fn every_row_default_round_trips_through_its_field() {
    // A field whose Rust type does not match its row's kind would panic here.
    let c = SceneConfig::default();
    for p in PARAMS.iter() {
        let v = c.get(p.name).unwrap();
        let mut d = c.clone();
        d.set(p.name, v.clone()).unwrap();
        assert_eq!(d.get(p.name).unwrap(), v, "{}", p.name);
        assert_eq!(
            p.kind.check(p.name, v).unwrap(),
            p.kind.default_value(),
            "{}",
            p.name
        );
    }
}

#[test]
fn inputs_are_the_input_rows_and_are_checked() {
    let mut c = SceneConfig::default();
    let i = c.inputs();
    assert_eq!(
        i.iter().map(|(n, _)| n).collect::<Vec<_>>(),
        ["plate_velocity", "plate_position", "jet_velocity"]
    );
    c.apply_inputs(&i.clone().with("plate_velocity", 0.5))
        .unwrap();
    assert_eq!(c.plate.plate_velocity, 0.5);
    let e = c
        .apply_inputs(&i.clone().with("plate_velocity", f64::NAN))
        .unwrap_err();
    assert!(e.to_string().contains("plate_velocity"), "{e}");
    let e = c.apply_inputs(&i.clone().with("density", 1.0)).unwrap_err();
    assert!(e.to_string().contains("not an input"), "{e}");
    assert_eq!(c.plate.plate_velocity, 0.5, "a refused set changes nothing");
}
