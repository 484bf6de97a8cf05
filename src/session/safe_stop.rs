//! The end of every run: `on_fault` after a fault, then the brake of a drive still turning
//! (setpoint 0, wait for standstill; `brake.rs`) and `finally` (or the default safe stop:
//! setpoint 0, wait for standstill, disable operation, shutdown), then a verification
//! that reads the state and the speed back, escalates (quick stop, then disable voltage)
//! when the drive did not obey, and records the truth for the last lines. A lost port is
//! reopened first. Nothing here may give up silently: what could not be confirmed ends in
//! CHECK THE DRIVE BY HAND.

use super::brake::StopStep;
use super::session::Session;
use super::stop::{outcome, Stop};
use super::{DriveEnd, EndState, ObjectRef, RunReport, StepInfo, Verdict};
use crate::dictionary::Role;
use crate::drive::{DeviceCommand, DeviceState, DriveError};
use crate::stop_request::StopSignal;
use std::time::Duration;

/// How often the safe stop polls the speed or the state while it waits.
pub(super) const STOP_POLL: Duration = Duration::from_millis(100);
/// How long disable voltage may take to show in the status word.
const DISABLE_VOLTAGE_WAIT: Duration = Duration::from_secs(1);

impl Session<'_> {
    /// The standstill threshold in the speed object's own unit.
    pub(super) fn standstill_in(&self, object: &ObjectRef) -> f64 {
        let q = self.settings.standstill;
        object
            .unit
            .as_deref()
            .and_then(crate::dictionary::Unit::from_symbol)
            .and_then(|u| q.value_in(u))
            .unwrap_or(q.value)
            .abs()
    }

    /// A note for the summary (the console prints them with the final lines).
    pub fn note(&mut self, text: String) {
        self.report.safe_stop.push(text);
    }

    /// Ends the run: `on_fault` after a drive fault, then `finally` (`None`: the default
    /// safe stop), the emergency off on a second stop request, and the verification; a
    /// panic in any of it still ends in the emergency off and the truth. `ended` is why
    /// the operations stopped (`None`: they all ran). Returns the finished report.
    pub fn end(
        mut self,
        ended: Option<Stop>,
        leave_enabled: bool,
        on_fault: Option<&mut dyn FnMut(&mut Session)>,
        finally: Option<&mut dyn FnMut(&mut Session)>,
    ) -> RunReport {
        let ended = self.with_pending_fault(ended);
        if let (Some(Stop::Fault(_)), Some(on_fault)) = (&ended, on_fault) {
            self.stop.enter_safe_stop();
            self.in_safe_stop = true;
            let result = self.guarded(|s| {
                on_fault(s);
                Ok(())
            });
            if let Err(e) = result {
                let (_, why) = outcome(&Err(e));
                self.note(format!("on_fault ended early: {why}"));
            }
        }
        let link_lost = matches!(ended, Some(Stop::LinkLost(_)));
        self.report.verdict = match &ended {
            None if self.failed_checks => Verdict::Failed,
            None => Verdict::Passed,
            Some(Stop::Failed(_) | Stop::Unanswered(_) | Stop::OtherUnit(_) | Stop::StoppedOnFailure(_)) => {
                Verdict::Failed
            }
            Some(Stop::Fault(m) | Stop::Error(m) | Stop::LinkLost(m)) => Verdict::Error(m.clone()),
            Some(Stop::Interrupted) => Verdict::Interrupted(self.stop.first().unwrap_or(StopSignal::INT)),
            Some(Stop::Panicked(m)) => Verdict::Panicked(m.clone()),
        };
        self.run_safe_stop(finally, link_lost, leave_enabled);
        // A check in `on_fault` or `finally` is a check like any other: a run that would
        // have passed fails with it (before, the verdict was taken before they ran and read
        // `PASSED … 1 failed`).
        if self.report.verdict == Verdict::Passed && self.failed_checks {
            self.report.verdict = Verdict::Failed;
        }
        self.report.duration = self.clock.now().saturating_sub(self.run_start);
        if let Some((object, series)) = &self.setpoints {
            self.report.setpoints = Some(super::Track {
                object: object.name.clone(),
                unit: object.unit.clone(),
                points: series.points(),
            });
        }
        let mut csv_files: Vec<String> = self.csv_files.iter().map(|p| p.display().to_string()).collect();
        csv_files.sort();
        self.report.csv_files = csv_files;
        let mut objects: Vec<String> = self
            .report
            .checks
            .iter()
            .filter_map(|c| c.object.clone())
            .collect();
        objects.extend(self.report.series.iter().map(|s| s.object.clone()));
        objects.sort();
        objects.dedup();
        self.report.resolutions = objects
            .into_iter()
            .filter_map(|o| self.scale_of(&o).map(|scale| (o, scale)))
            .collect();
        // The run layer settles the verdict and then tells the observers the run finished.
        self.report
    }

    /// `finally` (or the default), the emergency off on a second stop request, and the
    /// verification; a panic in any of it still ends in the emergency off and the truth.
    fn run_safe_stop(
        &mut self,
        finally: Option<&mut dyn FnMut(&mut Session)>,
        link_lost: bool,
        leave_enabled: bool,
    ) {
        self.stop.enter_safe_stop();
        self.in_safe_stop = true;
        let keep = leave_enabled && self.report.verdict == Verdict::Passed;
        let mut kept = false;
        let result = self.guarded(|r| {
            kept = r.safe_stop(finally, link_lost, keep);
            Ok(())
        });
        if let Err(e) = result {
            let (_, why) = outcome(&Err(e));
            self.note(format!("the safe stop itself failed: {why}"));
            // Every drive, each on its own: one that fails must not keep the others on.
            for i in self.stop_order() {
                self.current = i;
                let last_resort = self.guarded(|r| {
                    r.emergency_off();
                    r.verify(false);
                    Ok(())
                });
                if last_resort.is_err() {
                    self.report.end.stop_confirmed = false;
                }
            }
        }
        // A stop request that lands after the drives were read back as kept (between that
        // check and here) still stops them: a run that says it stopped its drives must have.
        if kept && self.stop.count_at(self.clock.now()) > 0 {
            self.note(
                "a stop request arrived as the run ended: the drives left enabled are stopped after all"
                    .to_string(),
            );
            let again = self.guarded(|r| {
                r.safe_stop_drives(None, link_lost, false);
                Ok(())
            });
            if again.is_err() {
                self.report.end.stop_confirmed = false;
            }
            kept = false;
        }
        self.stop.leave_safe_stop();
        // A stop signal that arrived only during the safe stop still ends the run as
        // interrupted: CI and supervisors must not read a pass from a killed run.
        if let (Some(signal), Verdict::Passed | Verdict::Failed) = (self.stop.first(), &self.report.verdict) {
            self.report.verdict = Verdict::Interrupted(signal);
        }
        // What the drive's end makes of the verdict is the run layer's one rule
        // (`run::verdict_rule`), not decided here.
        self.say_reported_in_stop();
        self.report.kept_enabled = kept;
        self.release_drives(kept);
    }

    /// Whether the drives were left enabled (`keep`, and nothing since asked to stop them).
    fn safe_stop(
        &mut self,
        finally: Option<&mut dyn FnMut(&mut Session)>,
        link_lost: bool,
        keep: bool,
    ) -> bool {
        if keep {
            self.safe_stop_drives(None, link_lost, true);
            // Keeping the drives was decided before; a stop request that arrived since
            // (while they were read back), or a fault a drive reported meanwhile, asks for
            // them to be stopped after all.
            let why = if self.stop.count_at(self.clock.now()) > 0 {
                "a stop request arrived"
            } else if self.keep_faults_reported_since() {
                "a drive reported a fault"
            } else {
                return true;
            };
            self.note(format!(
                "{why} as the run ended: the drives left enabled are stopped after all"
            ));
        }
        self.safe_stop_drives(finally, link_lost, false);
        false
    }

    fn safe_stop_drives(
        &mut self,
        finally: Option<&mut dyn FnMut(&mut Session)>,
        link_lost: bool,
        keep: bool,
    ) {
        if self.several_drives() {
            self.safe_stop_all(finally, link_lost, keep);
        } else {
            self.safe_stop_one(finally, link_lost, keep);
        }
    }

    /// Reopens the current drive's link after it was lost; `false` (and a note saying to
    /// check the drive by hand) when it cannot be reached.
    fn reach_again(&mut self) -> bool {
        if self.restore_link() {
            return true;
        }
        let called = self.cur().called();
        self.note(format!(
            "{called} could not be reached to stop it; it may still be running. CHECK THE DRIVE BY HAND"
        ));
        false
    }

    /// The safe stop of a run with several drives: every drive reached again after a lost
    /// link, every turning drive braked together, the recipe's `finally` once (its steps
    /// name their drives) or the default for each drive, last enabled first, then each
    /// drive verified as a single drive is, and one line per drive for the end.
    fn safe_stop_all(&mut self, finally: Option<&mut dyn FnMut(&mut Session)>, link_lost: bool, keep: bool) {
        let order = self.stop_order();
        self.note_coasting_by_design(&order);
        let mut reachable = vec![true; self.drives.len()];
        // Every drive is reached again first: the recipe's `finally` names its drives in
        // any order, and the brake below takes them all together.
        if link_lost {
            for &i in &order {
                self.current = i;
                reachable[i] = self.reach_again();
            }
        }
        // A run that succeeded with `leave_enabled: true` keeps its drives as the steps
        // left them: neither the brake nor any finally; the verification still reads each
        // back.
        if !keep {
            // Every turning drive brakes together (all setpoints to 0, then each waited
            // for), so no drive keeps its setpoint while another brakes and a second stop
            // request cannot skip a later drive's brake.
            self.brake_before_finally(&order, &reachable);
            match finally {
                Some(finally) => finally(self),
                // The default then disables and shuts down each drive, last enabled first.
                None => {
                    let mut number = 0;
                    for &i in &order {
                        self.current = i;
                        if reachable[i] && self.has_device_control() && !self.interrupted() {
                            number = self.default_finally(number, false);
                        }
                    }
                }
            }
        }
        let emergency = self.interrupted();
        let mut ends = Vec::new();
        for &i in &order {
            self.current = i;
            self.report.end = EndState::default();
            if !reachable[i] {
                // Said above; the end line says the state is not known.
            } else if !self.has_device_control() {
                self.without_device_control();
            } else {
                if emergency {
                    self.emergency_off();
                }
                self.verify(keep);
            }
            ends.push(DriveEnd {
                name: self.drives[i].name.clone(),
                end: self.report.end.clone(),
            });
        }
        let r = &mut self.report;
        r.end.stop_confirmed = ends.iter().all(|e| e.end.stop_confirmed);
        r.end.coasting = ends.iter().any(|e| e.end.coasting);
        r.end.no_device_control = ends.iter().all(|e| e.end.no_device_control);
        r.end.speed_unread = ends.iter().any(|e| e.end.speed_unread);
        r.end.final_state = ends.first().and_then(|e| e.end.final_state);
        r.end.final_speed = ends.first().and_then(|e| e.end.final_speed);
        r.end.speed_unit = ends.first().and_then(|e| e.end.speed_unit.clone());
        r.drive_ends = ends;
    }

    fn safe_stop_one(&mut self, finally: Option<&mut dyn FnMut(&mut Session)>, link_lost: bool, keep: bool) {
        if link_lost && !self.restore_link() {
            self.report.end.stop_confirmed = false;
            self.note(
                "the drive could not be reached to stop it; it may still be running. CHECK THE DRIVE BY HAND"
                    .to_string(),
            );
            return;
        }
        self.note_coasting_by_design(&[self.current]);
        let device_control = self.has_device_control();
        match finally {
            _ if keep => {}
            Some(finally) => {
                let reachable = vec![true; self.drives.len()];
                self.brake_before_finally(&[self.current], &reachable);
                finally(self)
            }
            None if device_control => {
                self.default_finally(0, true);
            }
            None => {}
        }
        if !device_control {
            self.without_device_control();
            return;
        }
        if self.interrupted() {
            self.emergency_off();
        }
        self.verify(keep);
    }

    /// Whether the dictionary has a device-control profile. Without one drivescript can
    /// neither command the drive nor read its state, so it cannot have enabled it either.
    pub(super) fn has_device_control(&self) -> bool {
        self.drive_ref().profile().is_ok()
    }

    /// The end of a run on a drive without device control: no stop command exists and no
    /// state can be read back, which is said plainly instead of failing commands that the
    /// dictionary does not have. The drive answered (a lost link is restored first, or the
    /// run ends in CHECK THE DRIVE BY HAND before this), so the stop counts as confirmed.
    fn without_device_control(&mut self) {
        self.report.end.final_state = None;
        self.report.end.stop_confirmed = true;
        self.report.end.no_device_control = true;
        self.note(format!(
            "the {} dictionary has no device-control profile: there is no stop command to send; \
             the drive's power stage is as its terminals or PLC left it",
            self.drive_ref().dictionary().name()
        ));
    }

    /// The default `finally` of the current drive: with `brake`, the brake (the speed
    /// setpoint to 0 and a wait for standstill, where the profile names the speed objects
    /// and the recipe does not opt out), then disable operation and shutdown; numbered
    /// after `done` earlier steps (of other drives); returns the number of the last.
    fn default_finally(&mut self, done: usize, brake: bool) -> usize {
        // `drivescript stop` runs these steps as its own, numbered `stop N`, not as some
        // recipe's default `finally`.
        let (phase, suffix) = match self.run.kind {
            "stop" => ("stop", " (stop)"),
            _ => ("finally", " (default finally)"),
        };
        let mut steps = Vec::new();
        if brake && self.settings.brake_to_standstill {
            steps.extend(self.setpoint_zero_step());
            steps.extend(self.standstill_step(phase));
        }
        for c in crate::drive::stop_direction::DEFAULT_STOP {
            steps.push(StopStep {
                drive: self.current,
                label: c.id().to_string(),
                op: Box::new(move |s| s.command_down(c)),
            });
        }
        self.perform_stop_steps(steps, phase, suffix, done)
    }

    /// Runs one step of the safe stop whatever happens: a lost port is reopened and the
    /// step tried once more; a failure is noted for the summary.
    pub fn perform_best_effort(
        &mut self,
        info: &StepInfo,
        op: impl Fn(&mut Session) -> Result<String, Stop>,
    ) {
        let mut result = self.perform(info, &op);
        if matches!(result, Err(Stop::LinkLost(_))) && self.restore_link() {
            result = self.perform(info, &op);
        }
        if let Err(e) = result {
            let (_, detail) = outcome(&Err(e));
            let n = info.number.rsplit('.').next().unwrap_or(&info.number);
            self.note(format!(
                "{} step {n} ({}) failed: {detail}",
                info.phase, info.label
            ));
        }
    }

    /// The last resort: disable voltage, which nothing may interrupt.
    fn emergency_off(&mut self) {
        self.stop.enter_final_stage();
        let mut result = self.drive().command(DeviceCommand::DisableVoltage);
        if matches!(&result, Err(e) if e.is_link_lost()) && self.restore_link() {
            result = self.drive().command(DeviceCommand::DisableVoltage);
        }
        match (result, self.same_stop_as_disable_operation(DeviceCommand::DisableVoltage)) {
            (Ok(()), None) => self.note("power stage switched off at once (disable voltage)".into()),
            (Ok(()), Some(write)) => self.note(format!(
                "disable voltage sent ({write}, the same stop as disable_operation: the {} dictionary has no command that switches the power stage off)",
                self.drive_ref().dictionary().name()
            )),
            (Err(e), _) => self.note(format!("disable voltage failed: {e}")),
        }
    }

    /// What `command` writes when it is the same write as `disable_operation` (an inverter
    /// whose one stop code stands for every stop): `control word 3`; `None` otherwise.
    fn same_stop_as_disable_operation(&self, command: DeviceCommand) -> Option<String> {
        let profile = self.drive_ref().profile().ok()?;
        let (this, stop) = (
            profile.command(command)?,
            profile.command(DeviceCommand::DisableOperation)?,
        );
        (this.object == stop.object && this.value == stop.value).then(|| profile.command_text(command))
    }

    /// A drive stopped in switched on because its shutdown is only its stop again says so:
    /// "switched on" is as low as its commands go, not a shutdown that did not happen.
    fn note_lowest_state(&mut self, state: DeviceState) {
        if state != DeviceState::SwitchedOn {
            return;
        }
        if let Some(write) = self.same_stop_as_disable_operation(DeviceCommand::Shutdown) {
            let called = self.cur().called();
            let dictionary = self.drive_ref().dictionary().name().to_string();
            self.note(format!(
                "{called} is stopped in {state}, as low as the {dictionary} dictionary's commands go: its shutdown writes {write}, the same stop as disable_operation, so there is no command to a lower state"
            ));
        }
    }

    fn state_with_reconnect(&mut self) -> Result<DeviceState, DriveError> {
        match self.drive().state() {
            Err(e) if e.is_link_lost() && self.restore_link() => self.drive().state(),
            other => other,
        }
    }

    /// Reads the state back; escalates while the drive is still enabled; records the state,
    /// the speed and whether the spindle coasts.
    fn verify(&mut self, keep: bool) {
        let mut state = match self.state_with_reconnect() {
            Ok(s) => s,
            Err(e) => {
                self.report.end.stop_confirmed = false;
                self.report.end.final_state = None;
                self.note(format!(
                    "could not read the drive's state after the safe stop: {e}; CHECK THE DRIVE BY HAND"
                ));
                self.read_final_speed();
                return;
            }
        };
        if !keep {
            if state == DeviceState::FaultReactionActive {
                // The drive brakes by itself and then enters fault.
                state =
                    self.wait_for_state(DeviceState::FaultReactionActive, self.settings.standstill_timeout);
            }
            if matches!(
                state,
                DeviceState::OperationEnabled | DeviceState::QuickStopActive
            ) {
                state = self.escalate(state);
            }
        }
        self.report.end.final_state = Some(state);
        let enabled = matches!(
            state,
            DeviceState::OperationEnabled | DeviceState::QuickStopActive
        );
        self.report.end.stop_confirmed = keep || !enabled;
        if !self.report.end.stop_confirmed {
            self.note(format!(
                "the drive still reports {state} after quick stop and disable voltage; CHECK THE DRIVE BY HAND"
            ));
        } else if !keep {
            self.note_lowest_state(state);
            self.wait_for_coasting(state);
        }
        self.read_final_speed();
        // A drive can trip while its spindle coasts down or between the reads: the state
        // told at the end is read last, after the speed.
        if !keep {
            self.confirm_final_state();
        }
    }

    /// Quick stop, then disable voltage, each verified by reading the state back.
    fn escalate(&mut self, state: DeviceState) -> DeviceState {
        self.report.disobeyed = true;
        self.note(format!(
            "the drive still reports {state} after the stop commands: it did not obey; escalating to quick stop"
        ));
        let mut state = state;
        if state == DeviceState::OperationEnabled {
            match self.drive().command(DeviceCommand::QuickStop) {
                Ok(()) => {
                    state = self.wait_for_state(DeviceState::OperationEnabled, DISABLE_VOLTAGE_WAIT);
                    if state == DeviceState::QuickStopActive {
                        state = self
                            .wait_for_state(DeviceState::QuickStopActive, self.settings.standstill_timeout);
                    }
                }
                Err(e) => self.note(format!("quick stop failed: {e}")),
            }
        }
        if matches!(
            state,
            DeviceState::OperationEnabled | DeviceState::QuickStopActive
        ) {
            self.note(format!(
                "still {state} after quick stop; switching the power stage off"
            ));
            self.emergency_off();
            state = self.wait_for_state(state, DISABLE_VOLTAGE_WAIT);
        } else {
            self.note(format!("after quick stop the drive reports {state}"));
        }
        state
    }

    /// Polls the state until it is no longer `from` or `timeout` has passed; returns the
    /// last state read (`from` when it could not be read).
    fn wait_for_state(&mut self, from: DeviceState, timeout: Duration) -> DeviceState {
        let give_up = self.clock.now().saturating_add(timeout);
        loop {
            let state = match self.drive().state() {
                Ok(s) => s,
                Err(e) => {
                    self.note(format!("reading the state failed: {e}"));
                    return from;
                }
            };
            if state != from || self.clock.now() >= give_up {
                return state;
            }
            // Only the final stage (disable voltage) is shielded from stop requests; a
            // further request here just ends the wait early.
            if self
                .wait(self.clock.now().saturating_add(STOP_POLL).min(give_up))
                .is_err()
            {
                return state;
            }
        }
    }

    fn read_final_speed(&mut self) {
        let Some(object) = self.role_ref(Role::SpeedActual) else {
            return;
        };
        match self.drive().read_number(&object.name) {
            Ok(v) => {
                let powered = self.report.end.final_state.is_some_and(DeviceState::is_powered);
                self.report.end.final_speed = Some(v);
                self.report.end.speed_unit = object.unit.clone();
                self.report.end.coasting = !powered && v.abs() > self.standstill_in(&object);
            }
            Err(e) => {
                self.report.end.speed_unread = true;
                self.note(format!("could not read {} after the safe stop: {e}", object.name))
            }
        }
    }
}
