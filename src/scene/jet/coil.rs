//! The round jet's coil: how fast the column's lowest part turns about the nozzle axis.
//!
//! A viscous rope falling on a plate from high enough coils (liquid rope coiling, Ribe 2004):
//! its lowest part runs round a circle above the heap. `jet_coil_radius` is the distance from
//! the axis of the centre of the column one jet width above the heap (the band `jet_deflection`
//! measures), a property of one state. Its frequency is not: the fluid in a coiling rope moves
//! along the rope, so the particles' velocities do not show the rope's turning (where the rope
//! is laid on the heap they are nearly at rest while the rope turns). [`Coil`] therefore follows
//! the centre's azimuth at every step (the jet's part of the state, with the inflow's log) and
//! counts its turns.

use super::{band_centre, inflow_log, SceneConfig, ONSET_FRACTION};
use crate::state::{SceneState, State};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// The azimuth of the column's lowest part, followed from the time it last left the axis.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Coil {
    /// Whether the column is off the axis (its centre more than [`ONSET_FRACTION`] D off it).
    pub tracking: bool,
    /// Azimuth of the centre about the axis at the last sample, unwrapped (continuous over
    /// turns) \[rad\], and the time of that sample \[s\].
    pub azimuth: f64,
    pub time: f64,
    /// Time and azimuth when the column last left the axis.
    pub start_time: f64,
    pub start_azimuth: f64,
    /// Full turns completed since then, when the last one completed, and its period \[s\]
    /// (0 before the first).
    pub turns: u64,
    pub turn_time: f64,
    pub period: f64,
}

impl Coil {
    /// Take the sample `centre` (the column's horizontal centre, [x, y]) at time `t` of a jet of
    /// width `d`. Near the axis (within [`ONSET_FRACTION`] D) the azimuth says nothing: the coil
    /// is lost (a column back on the axis, or one that swings through it, folding, is not
    /// coiling) and its count starts again when the centre next leaves the axis. Otherwise the
    /// azimuth is unwrapped against the last sample (the centre turns by far less than half a
    /// turn between steps).
    pub fn sample(&mut self, t: f64, centre: [f64; 2], d: f64) {
        if centre[0].hypot(centre[1]) <= ONSET_FRACTION * d {
            *self = Coil::default();
            return;
        }
        let a = centre[1].atan2(centre[0]);
        if !self.tracking {
            *self = Coil {
                tracking: true,
                azimuth: a,
                time: t,
                start_time: t,
                start_azimuth: a,
                turns: 0,
                turn_time: t,
                period: 0.0,
            };
            return;
        }
        self.azimuth += (a - self.azimuth + PI).rem_euclid(TAU) - PI;
        self.time = t;
        let turns = ((self.azimuth - self.start_azimuth).abs() / TAU).floor() as u64;
        if turns > self.turns {
            self.period = (t - self.turn_time) / (turns - self.turns) as f64;
            self.turn_time = t;
            self.turns = turns;
        }
    }

    /// Turns per second \[Hz\]: the inverse of the last full turn's period; before the first
    /// full turn, the mean rate since the column left the axis; 0 while it is on the axis.
    pub fn frequency(&self) -> f64 {
        if self.period > 0.0 {
            1.0 / self.period
        } else if self.tracking && self.time > self.start_time {
            (self.azimuth - self.start_azimuth).abs() / (TAU * (self.time - self.start_time))
        } else {
            0.0
        }
    }
}

/// Before a step of the round jet: sample the column's centre ([`band_centre`]) into the coil
/// of the inflow's log.
pub fn follow(cfg: &SceneConfig, st: &mut State<3>) {
    if st.inflow.is_none() {
        return;
    }
    let Some(centre) = band_centre(st, cfg) else {
        return;
    };
    let mut log = inflow_log(st);
    log.coil.sample(st.time, centre, cfg.jet.jet_width);
    st.scene = SceneState::encode(&log);
}
