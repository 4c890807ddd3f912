//! `fmi2DoStep`: one communication step within the step budget, and what a discarded one
//! leaves.

use super::*;

impl Instance {
    /// `fmi2DoStep` (FMI 2.0 section 4.2.2): advance from `t` to exactly `t + h` with the
    /// scheme's own adaptive sub-steps, so the outputs at a communication point do not depend
    /// on the communication step size beyond the shortened last sub-step.
    ///
    /// Bounded: a step whose estimated step count breaks the run-length rule is discarded before
    /// any work, and the sub-steps run within the budget `max_steps_per_do_step` /
    /// `max_seconds_per_do_step`. Past the budget, or at a numerical breakdown, the call answers
    /// `fmi2Discard` with the simulation at its last good sub-step: the outputs are those of that
    /// state, `fmi2LastSuccessfulTime` is its time, and an FMU state taken now continues from
    /// there once set ([`Instance::get_state`]). After a breakdown `fmi2Terminated` becomes true
    /// as well, because a smaller communication step would not help.
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        self.call(
            "fmi2DoStep",
            mask::DO_STEP,
            || format!("currentCommunicationPoint={t}, communicationStepSize={h}"),
            |s| {
                if !h.is_finite() {
                    return error(format!("communicationStepSize = {h} must be finite"));
                }
                if h <= 0.0 {
                    return error(format!("communicationStepSize = {h} must be > 0"));
                }
                let tol = 1e-9 * s.t_comm.abs().max(1.0);
                if !t.is_finite() || (t - s.t_comm).abs() > tol {
                    return error(format!(
                        "currentCommunicationPoint = {t} does not continue from the last communication point {} (tolerance {tol:e})",
                        s.t_comm
                    ));
                }
                let target = t + h;
                if let Some(stop) = s.stop_time {
                    if target > stop + 1e-9 * stop.abs().max(1.0) {
                        return error(format!(
                            "the step to t = {target} goes past stopTime = {stop} given to fmi2SetupExperiment"
                        ));
                    }
                }
                let start = s.start_time;
                let budget = s.budget();
                let sim = s.sim.as_mut().expect("a simulation exists in StepComplete");
                // Inputs set beyond the run's range (fmi2SetReal answered fmi2Warning) are
                // refused here, before any work; so is a plate position the plate cannot reach
                // within max_plate_speed.
                let inputs = s.cfg.inputs();
                let refusal = if sim.inputs() != inputs {
                    sim.set_inputs(inputs).err()
                } else {
                    None
                };
                if let Some(e) = refusal.or_else(|| sim.check_step(target - start).err()) {
                    return match e {
                        SimError::InputOutOfRange(m) => {
                            s.phase = Phase::StepFailed;
                            s.resumable = true;
                            s.wants_to_terminate = false;
                            Err(Fail::Discard(format!(
                                "{m}. Nothing was computed (the outputs and fmi2LastSuccessfulTime stay at t = {t} s)"
                            )))
                        }
                        e => error(e.to_string()),
                    };
                }
                let dt = Some(sim.last_dt()).filter(|&dt| dt > 0.0).or(s.first_dt);
                if let Some(dt) = dt {
                    let what = format!("communicationStepSize = {h} s");
                    let length = RunLength::at_step(target - start - sim.time(), dt, sim.particle_count());
                    if let Some(refusal) = length.too_long(&what) {
                        s.phase = Phase::StepFailed;
                        s.resumable = true;
                        return Err(Fail::Discard(format!(
                            "{refusal}; nothing was computed (the outputs and fmi2LastSuccessfulTime stay at t = {t} s). \
                             Use smaller communication steps"
                        )));
                    }
                }
                match sim.advance_within(target - start, &budget) {
                    Ok(()) => {
                        let outputs = sim.outputs();
                        if let Some(bad) = non_finite(&outputs) {
                            s.phase = Phase::StepFailed;
                            s.wants_to_terminate = true;
                            s.resumable = false;
                            return Err(Fail::Discard(format!(
                                "output '{bad}' became non-finite in the step from t = {t} s to {target} s; \
                                 the outputs keep their values at t = {t} s"
                            )));
                        }
                        s.outputs = outputs;
                        s.t_comm = target;
                        s.last_successful_time = target;
                        Ok(Status::Ok)
                    }
                    Err(e @ (SimError::Breakdown { .. } | SimError::OverBudget { .. })) => {
                        let reached = start + sim.time();
                        let outputs = sim.outputs();
                        s.resumable = non_finite(&outputs).is_none();
                        if s.resumable {
                            s.outputs = outputs;
                            s.last_successful_time = reached;
                        }
                        s.phase = Phase::StepFailed;
                        let over_budget = matches!(e, SimError::OverBudget { .. });
                        s.wants_to_terminate = !over_budget;
                        let advice = if over_budget {
                            "that is the budget max_steps_per_do_step / max_seconds_per_do_step of one fmi2DoStep: \
                             raise it or use smaller communication steps"
                        } else {
                            "the slave cannot continue with these inputs (fmi2Terminated)"
                        };
                        Err(Fail::Discard(format!(
                            "{e}; {advice}. The outputs hold the last good state, at t = {} s \
                             (fmi2LastSuccessfulTime); fmi2GetFMUstate now saves it, and fmi2SetFMUstate of that \
                             state continues from there",
                            s.last_successful_time
                        )))
                    }
                    Err(e) => error(e.to_string()),
                }
            },
        )
    }

    /// The budget of one `fmi2DoStep`, from the parameters.
    fn budget(&self) -> Budget {
        let n = &self.cfg.numerics;
        Budget {
            max_steps: Some(n.max_steps_per_do_step.max(1) as u64),
            max_time: (n.max_seconds_per_do_step > 0.0)
                .then(|| Duration::from_secs_f64(n.max_seconds_per_do_step)),
        }
    }
}
