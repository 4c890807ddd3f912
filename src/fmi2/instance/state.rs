//! FMU states (FMI 2.0 section 2.1.8): what a snapshot of an instance holds, its bytes, and
//! `fmi2GetFMUstate`/`fmi2SetFMUstate`.

use super::*;

/// Everything of an instance that an FMU state holds (FMI 2.0 section 2.1.8): no pointers, so a
/// serialized state restores in another process.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Snapshot {
    /// The interface the state belongs to; a state of another interface is refused.
    guid: String,
    phase: Phase,
    cfg: SceneConfig,
    /// [`Simulation::save_state`] once initialized.
    sim: Option<Vec<u8>>,
    start_time: f64,
    stop_time: Option<f64>,
    t_comm: f64,
    last_successful_time: f64,
    wants_to_terminate: bool,
    outputs: Outputs,
}

impl Snapshot {
    /// The bytes of `fmi2SerializeFMUstate`: a tag and a bincode body.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = SNAPSHOT_TAG.to_vec();
        out.extend(bincode::serialize(self).expect("snapshot serialises"));
        out
    }

    /// Inverse of [`Snapshot::to_bytes`]; the message says what is wrong with the bytes.
    pub fn from_bytes(bytes: &[u8]) -> Result<Snapshot, String> {
        let body = bytes.strip_prefix(SNAPSHOT_TAG).ok_or_else(|| {
            format!(
                "the {} bytes are not a serialized ViscoSPH FMU state",
                bytes.len()
            )
        })?;
        let snap: Snapshot =
            bincode::deserialize(body).map_err(|e| format!("corrupt serialized FMU state: {e}"))?;
        let ours = guid();
        if snap.guid != ours {
            return Err(format!(
                "the serialized FMU state belongs to the interface {} but this FMU is {ours}",
                snap.guid
            ));
        }
        Ok(snap)
    }
}

const SNAPSHOT_TAG: &[u8] = b"ViscoSPH FMU state v1\n";

impl Instance {
    /// `fmi2GetFMUstate`: a snapshot of everything that evolves.
    ///
    /// After an `fmi2DoStep` that was discarded with the simulation at its last good sub-step
    /// (the budget, a breakdown, a refused step size), the snapshot is that last good state, a
    /// completed step at `fmi2LastSuccessfulTime`: setting it lets the master go on from there
    /// (FMI 2.0 section 4.2.2 expects a master to redo a discarded step from a saved state).
    pub fn get_state(&mut self, out: &mut Option<Snapshot>) -> Status {
        self.call("fmi2GetFMUstate", mask::ANY, String::new, |s| {
            let resume = s.phase == Phase::StepFailed && s.resumable;
            *out = Some(Snapshot {
                guid: guid(),
                phase: if resume { Phase::StepComplete } else { s.phase },
                cfg: s.cfg.clone(),
                sim: s.sim.as_ref().map(|m| m.save_state()),
                start_time: s.start_time,
                stop_time: s.stop_time,
                t_comm: if resume {
                    s.last_successful_time
                } else {
                    s.t_comm
                },
                last_successful_time: s.last_successful_time,
                wants_to_terminate: s.wants_to_terminate && !resume,
                outputs: s.outputs,
            });
            Ok(Status::Ok)
        })
    }

    /// `fmi2SetFMUstate`: restore a snapshot, phase included.
    pub fn set_state(&mut self, snap: &Snapshot) -> Status {
        self.call("fmi2SetFMUstate", mask::ANY, String::new, |s| {
            if snap.guid != guid() {
                return error(format!(
                    "the FMU state belongs to the interface {} but this FMU is {}",
                    snap.guid,
                    guid()
                ));
            }
            match (&snap.sim, s.sim.as_mut()) {
                (None, _) => s.sim = None,
                (Some(bytes), Some(sim)) => sim
                    .restore_state(bytes)
                    .map_err(|e| Fail::Error(e.to_string()))?,
                (Some(bytes), None) => {
                    let mut sim = Simulation::new(snap.cfg.clone())
                        .map_err(|e| Fail::Error(e.to_string()))?;
                    sim.restore_state(bytes)
                        .map_err(|e| Fail::Error(e.to_string()))?;
                    s.sim = Some(sim);
                }
            }
            s.phase = snap.phase;
            s.cfg = snap.cfg.clone();
            s.preview = None;
            s.start_time = snap.start_time;
            s.stop_time = snap.stop_time;
            s.t_comm = snap.t_comm;
            s.last_successful_time = snap.last_successful_time;
            s.wants_to_terminate = snap.wants_to_terminate;
            s.outputs = snap.outputs;
            s.resumable = false;
            s.first_dt = None;
            s.error_cause = (s.phase == Phase::Error)
                .then(|| "fmi2SetFMUstate restored a state taken in the Error state".to_string());
            s.log(
                Category::Events,
                Status::Ok,
                &format!(
                    "FMU state restored: t = {} s, phase {}",
                    s.t_comm,
                    s.phase.name()
                ),
            );
            Ok(Status::Ok)
        })
    }

    /// Check that an FMU-state call is allowed now (for the calls that only touch the
    /// snapshot itself: free, size, serialize, deserialize), and report `problem` if any.
    pub fn state_call(&mut self, func: &'static str, problem: Option<String>) -> Status {
        self.call(func, mask::ANY, String::new, move |_| match problem {
            Some(p) => error(p),
            None => Ok(Status::Ok),
        })
    }
}
