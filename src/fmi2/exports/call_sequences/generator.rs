//! The random calls ([`Call`]) and their strategies: value references of every kind of
//! variable and of none, values within and outside the ranges, special step sizes, and chunks
//! of calls that reach the stepping states.

use super::SLOTS;
use crate::config::Kind;
use crate::scene::{param_spec, OUTPUTS, OUTPUT_ARRAYS};
use proptest::prelude::*;

#[derive(Debug, Clone)]
pub(super) enum Call {
    Setup {
        start: f64,
        stop: Option<f64>,
    },
    Enter,
    Exit,
    Terminate,
    Reset,
    /// `fmi2DoStep(t + offset, h)` where `t` is the model's communication point.
    DoStep {
        offset: f64,
        h: f64,
    },
    GetReal(Vec<u32>),
    /// The flag: through FMI 3.0's Int64 rather than Int32 (FMI 2.0 has one integer type).
    GetInteger(Vec<u32>, bool),
    GetBoolean(Vec<u32>),
    GetString(Vec<u32>),
    SetReal(Vec<(u32, f64)>),
    SetInteger(Vec<(u32, i32)>, bool),
    SetBoolean(Vec<u32>),
    SetString(Vec<(u32, String)>),
    GetState(usize),
    SetState(usize),
    FreeState(usize),
    /// Serialize the slot's state and deserialize it into the slot.
    Reserialize(usize),
    Status(u32),
    Logging(bool),
    /// `fmi2FreeInstance` and `fmi2Instantiate` again (the slots' states stay valid).
    Reinstantiate,
}

pub(super) fn vr(name: &str) -> u32 {
    param_spec(name)
        .map(|p| p.value_reference)
        .unwrap_or_else(|| panic!("{name}"))
}

/// Value references: some of every kind of variable, and some of none.
pub(super) fn any_vr() -> impl Strategy<Value = u32> + Clone {
    let named: Vec<u32> = [
        "scene",
        "scheme",
        "rheology",
        "impact_velocity",
        "drop_diameter",
        "viscosity",
        "relaxation_time",
        "sound_speed",
        "time_step_factor",
        "particles_per_diameter",
        "max_steps_per_do_step",
        "max_seconds_per_do_step",
        "threads",
        "equation_of_state",
        "plate_velocity",
        "plate_position",
        "plate_coupling",
        "max_plate_speed",
        "jet_velocity",
    ]
    .iter()
    .map(|n| vr(n))
    .chain([1001, 1003, 1031]) // String twins
    .collect();
    let others: Vec<u32> = OUTPUTS
        .iter()
        .take(4)
        .map(|o| o.value_reference)
        .chain(OUTPUT_ARRAYS.iter().map(|a| a.value_reference)) // FMI 3.0 only
        .chain([0, 35, 100, 999, 5000, u32::MAX]) // nobody's (0: time in FMI 3.0)
        .collect();
    prop_oneof![
        9 => prop::sample::select(named),
        1 => prop::sample::select(others),
    ]
}

/// A special value, or `None` for one within the variable's range.
pub(super) fn real_value() -> impl Strategy<Value = Option<f64>> {
    prop_oneof![
        12 => Just(None),
        1 => Just(Some(f64::NAN)),
        1 => Just(Some(f64::INFINITY)),
        1 => Just(Some(f64::NEG_INFINITY)),
        1 => Just(Some(-1.0)),
        1 => Just(Some(1e300)),
    ]
}

/// A Real value for `vr`, kept small where a large one would make the case slow (a parameter
/// that scales the particle count or the threads is never raised: those are Integers).
pub(super) fn set_real() -> impl Strategy<Value = (u32, f64)> {
    (any_vr(), real_value(), 0.0..1.0f64).prop_map(|(v, special, frac)| {
        let x = special.unwrap_or_else(|| match crate::scene::param_by_vr(v).map(|p| p.kind) {
            Some(Kind::Real { min, max, .. }) => min + frac * (max - min),
            _ => frac,
        });
        // A wall-clock budget of at most 0.05 s per step keeps a case short.
        if v == vr("max_seconds_per_do_step") && x.is_finite() && x > 0.05 {
            (v, 0.05)
        } else {
            (v, x)
        }
    })
}

/// An Integer value for `vr`: never more than 8 particles across, 40 steps a call or 2 threads.
pub(super) fn set_integer() -> impl Strategy<Value = (u32, i32)> {
    (any_vr(), -3..12i32, prop::bool::weighted(0.1)).prop_map(|(v, x, extreme)| {
        let x = if extreme { i32::MIN } else { x };
        let x = if v == vr("particles_per_diameter") {
            x.min(8)
        } else if v == vr("max_steps_per_do_step") {
            x.min(40)
        } else if v == vr("threads") {
            x.min(2)
        } else {
            x
        };
        (v, x)
    })
}

pub(super) fn step_size() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => 1e-6..2e-3f64,
        1 => Just(0.0),
        1 => Just(-1e-3),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(1e9),
        1 => Just(1e300),
    ]
}

/// A few calls: a random one, or the usual setup-enter-exit, or a few ordinary steps, so that
/// the cases reach the stepping states as well as the refusals.
pub(super) fn chunk() -> impl Strategy<Value = Vec<Call>> {
    let start = |stop| vec![Call::Setup { start: 0.0, stop }, Call::Enter, Call::Exit];
    prop_oneof![
        6 => call().prop_map(|c| vec![c]),
        2 => prop::option::of(1e-3..0.05f64).prop_map(start),
        2 => prop::option::of(1e-3..0.05f64).prop_map(move |stop| {
            let mut v = vec![Call::Reset];
            v.extend(start(stop));
            v
        }),
        3 => (1..4usize, 1e-5..1e-3f64)
            .prop_map(|(n, h)| vec![Call::DoStep { offset: 0.0, h }; n]),
        // A step far past the budget, then the master goes on from the last good state.
        2 => (0..SLOTS, 1e-5..1e-3f64).prop_map(|(k, h)| vec![
            Call::DoStep { offset: 0.0, h: 0.02 },
            Call::GetState(k),
            Call::SetState(k),
            Call::DoStep { offset: 0.0, h },
        ]),
        // An input changed between steps.
        1 => (-0.5..0.5f64, 1e-5..1e-3f64).prop_map(|(v, h)| vec![
            Call::SetReal(vec![(vr("plate_velocity"), v)]),
            Call::DoStep { offset: 0.0, h },
        ]),
    ]
}

pub(super) fn call() -> impl Strategy<Value = Call> {
    let slot = 0..SLOTS;
    let vrs = prop::collection::vec(any_vr(), 0..4);
    let text = prop::sample::select(vec![
        "drop", "channel", "jet", "wcsph", "pdri", "isph", "giesekus", "tait", "", "bogus%s",
    ])
    .prop_map(String::from);
    prop_oneof![
        2 => (prop_oneof![4 => Just(0.0), 2 => Just(0.5), 1 => Just(f64::NAN)],
              prop::option::of(prop_oneof![Just(0.01), Just(1e9), Just(f64::NAN), Just(-1.0)]))
            .prop_map(|(start, stop)| Call::Setup { start, stop: stop.map(|s| if s > 0.0 { start + s } else { s }) }),
        3 => Just(Call::Enter),
        3 => Just(Call::Exit),
        1 => Just(Call::Terminate),
        3 => Just(Call::Reset),
        8 => (prop_oneof![8 => Just(0.0), 1 => Just(1e-3), 1 => Just(f64::NAN)], step_size())
            .prop_map(|(offset, h)| Call::DoStep { offset, h }),
        2 => vrs.clone().prop_map(Call::GetReal),
        1 => (vrs.clone(), any::<bool>()).prop_map(|(v, w)| Call::GetInteger(v, w)),
        1 => vrs.clone().prop_map(Call::GetBoolean),
        1 => vrs.clone().prop_map(Call::GetString),
        3 => prop::collection::vec(set_real(), 0..3).prop_map(Call::SetReal),
        2 => (prop::collection::vec(set_integer(), 0..3), any::<bool>())
            .prop_map(|(v, w)| Call::SetInteger(v, w)),
        1 => vrs.prop_map(Call::SetBoolean),
        1 => prop::collection::vec((any_vr(), text), 0..3).prop_map(Call::SetString),
        2 => slot.clone().prop_map(Call::GetState),
        2 => slot.clone().prop_map(Call::SetState),
        1 => slot.clone().prop_map(Call::FreeState),
        1 => slot.prop_map(Call::Reserialize),
        1 => (0..6u32).prop_map(Call::Status),
        1 => any::<bool>().prop_map(Call::Logging),
        1 => Just(Call::Reinstantiate),
    ]
}
