//! How much work one request may do: the budget of one [`crate::simulation::Simulation::advance_within`] call (the
//! FMU's `fmi2DoStep`), and the run-length rule that refuses a run of more than [`MAX_STEPS`]
//! steps before it starts (the CLI's `viscosph run` and the FMU's `stopTime`).
//!
//! Why both: the run-length rule catches a typo (a stop time in milliseconds given as seconds)
//! before any work, from the scheme's first stable time step; the budget bounds a call whose
//! length could not be known in advance (an FMU master with no stop time asking for one step of
//! 10^9 s, or a time step that collapses during the run), so that no call runs unbounded.

use std::time::{Duration, Instant};

/// Estimated step counts above this are refused (the CLI's `--force` overrides it): at about
/// 10^4 steps per second for the default drop, 10^8 steps are days of computing, almost surely a
/// typo.
pub const MAX_STEPS: f64 = 1.0e8;

/// The most one call may do: solver steps and wall-clock time, each checked before every step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Budget {
    /// Most solver steps (`None`: no limit).
    pub max_steps: Option<u64>,
    /// Most wall-clock time (`None`: no limit).
    pub max_time: Option<Duration>,
}

impl Budget {
    /// No limit: [`crate::simulation::Simulation::advance_to`].
    pub const UNLIMITED: Budget = Budget {
        max_steps: None,
        max_time: None,
    };

    /// Why a call that has taken `steps` steps since `started` must not take another one, if it
    /// must not.
    pub fn exceeded(&self, steps: u64, started: Instant) -> Option<String> {
        if let Some(n) = self.max_steps {
            if steps >= n {
                return Some(format!("{n} solver steps"));
            }
        }
        if let Some(t) = self.max_time {
            let spent = started.elapsed();
            if spent >= t {
                return Some(format!(
                    "{:.3} s of wall-clock time ({} steps)",
                    spent.as_secs_f64(),
                    steps
                ));
            }
        }
        None
    }
}

/// How many steps a run of `duration` seconds would take at the time step `dt`.
#[derive(Debug, Clone, Copy)]
pub struct RunLength {
    pub duration: f64,
    pub dt: f64,
    pub steps: f64,
    pub particles: usize,
}

impl RunLength {
    /// The length of a run of `duration` seconds at time step `dt` with `particles` particles.
    pub fn at_step(duration: f64, dt: f64, particles: usize) -> RunLength {
        let duration = duration.max(0.0);
        RunLength {
            duration,
            dt,
            steps: duration / dt.max(1e-300),
            particles,
        }
    }

    /// The refusal of a run over [`MAX_STEPS`] steps, `what` naming the duration ("t_end = 5 s"),
    /// with the estimate; `None` if the run is within the rule.
    pub fn too_long(&self, what: &str) -> Option<String> {
        if self.steps <= MAX_STEPS {
            return None;
        }
        let hours = self.steps * self.particles as f64 / 1.0e6 / 3600.0;
        Some(format!(
            "{what} would take about {:.2e} steps (time step {:.3e} s), more than {MAX_STEPS:.0e}: \
             about {hours:.0} hours at 10^6 particle-steps/s",
            self.steps, self.dt
        ))
    }
}
