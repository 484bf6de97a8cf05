//! The first part of every safe stop: a drive still enabled and turning gets the speed
//! setpoint 0 and is waited for until it stands still (bounded by the standstill timeout)
//! before anything disables it — a recipe's or script's own `finally` included, since a
//! spindle disabled at speed coasts for minutes. Also the runner of the safe stop's own
//! numbered steps. It must not disable, escalate or verify (that is `safe_stop.rs`).

use super::safe_stop::STOP_POLL;
use super::session::show_duration;
use super::session::{round, secs, Session};
use super::stop::Stop;
use super::{number, ObjectRef, SetValue, StepInfo, StepOrigin};
use crate::dictionary::Role;
use crate::drive::DeviceState;
use std::time::Duration;

/// What one step of the safe stop does to the drive it names.
pub(super) type StopOp = Box<dyn Fn(&mut Session) -> Result<String, Stop>>;

/// One step of the safe stop: the drive (its index in the session), what it reads as, and
/// what it does.
pub(super) struct StopStep {
    pub drive: usize,
    pub label: String,
    pub op: StopOp,
}

impl Session<'_> {
    /// `set speed_setpoint = 0 rpm`, or nothing when the profile names no setpoint.
    pub(super) fn setpoint_zero_step(&self) -> Option<StopStep> {
        let object = self.role_ref(Role::SpeedSetpoint)?;
        let label = format!("set {} = 0{}", object.name, unit_suffix(&object));
        Some(StopStep {
            drive: self.current,
            label,
            op: Box::new(move |s| s.set(&[(object.clone(), SetValue::number(0.0))])),
        })
    }

    /// The wait for standstill of the current drive, or nothing when the profile names no
    /// actual speed.
    pub(super) fn standstill_step(&self, phase: &'static str) -> Option<StopStep> {
        let object = self.role_ref(Role::SpeedActual)?;
        let below = self.standstill_in(&object);
        let timeout = self.settings.standstill_timeout;
        let label = format!(
            "wait for standstill: {} within ±{}{}, at most {}",
            object.name,
            number(below),
            unit_suffix(&object),
            show_duration(timeout)
        );
        Some(StopStep {
            drive: self.current,
            label,
            op: Box::new(move |s| s.standstill(below, timeout, phase)),
        })
    }

    /// Whether the current drive is in operation enabled and turns, or is told to turn (a
    /// setpoint beyond standstill): only then is there something to brake. A speed that
    /// cannot be read counts as turning, since braking an enabled drive is always safe;
    /// so does a state that cannot be read (a lost link is reopened by the brake's steps).
    fn turning(&mut self) -> bool {
        if matches!(self.drive().state(), Ok(s) if s != DeviceState::OperationEnabled) {
            return false;
        }
        [Role::SpeedActual, Role::SpeedSetpoint].into_iter().any(|role| {
            self.role_ref(role).is_some_and(|object| {
                let below = self.standstill_in(&object);
                self.drive()
                    .read_number(&object.name)
                    .map_or(true, |v| v.abs() > below)
            })
        })
    }

    /// Before a recipe's or script's own `finally`: every drive of `order` that is enabled
    /// and turning gets the setpoint 0 (all of them first, so they brake together), then
    /// each is waited for until it stands still. Nothing when the recipe opts out
    /// (`safe_stop: { brake_to_standstill: false }`) or a second stop request came.
    pub(super) fn brake_before_finally(&mut self, order: &[usize], reachable: &[bool]) {
        if !self.settings.brake_to_standstill {
            return;
        }
        let mut zero = Vec::new();
        let mut wait = Vec::new();
        for &i in order {
            self.current = i;
            if !reachable.get(i).copied().unwrap_or(false) || self.drive_ref().profile().is_err() {
                continue;
            }
            if self.interrupted() || !self.turning() {
                continue;
            }
            zero.extend(self.setpoint_zero_step());
            wait.extend(self.standstill_step("brake"));
        }
        zero.append(&mut wait);
        self.perform_stop_steps(zero, "brake", " (before finally)", 0);
    }

    /// What the safe stop says first of every drive of `order` a coast-down left coasting:
    /// its power stage is off on purpose and nothing can brake it.
    pub(super) fn note_coasting_by_design(&mut self, order: &[usize]) {
        for &i in order {
            if self.drives.get(i).is_some_and(|d| d.coasting_by_design) {
                let called = self.drives[i].called();
                self.note(format!(
                    "{called} coasts by design (a coast-down switched its power stage off): nothing can brake it; keep clear until it stands still"
                ));
            }
        }
    }

    /// While the drive is in operation enabled, polls the actual speed until it is within
    /// ±`below` (its unit) or `timeout` has passed, showing the speed.
    pub fn standstill(&mut self, below: f64, timeout: Duration, number: &str) -> Result<String, Stop> {
        let Some(object) = self.role_ref(Role::SpeedActual) else {
            return Ok("skipped: the profile names no actual speed".into());
        };
        let state = self.drive().state()?;
        if state != DeviceState::OperationEnabled {
            return Ok(format!(
                "skipped: the drive is in {state}, where the setpoint does not brake it; a spindle still turning is waited for at the end of the stop"
            ));
        }
        let unit = object.unit.clone().map(|u| format!(" {u}")).unwrap_or_default();
        let started = self.clock.now();
        let give_up = started.saturating_add(timeout);
        loop {
            let v = self.drive().read_number(&object.name)?;
            let waited = self.clock.now().saturating_sub(started);
            if v.abs() <= below {
                return Ok(format!("{}{unit} after {}", round(v), secs(waited)));
            }
            if waited >= timeout {
                return Err(Stop::Failed(format!(
                    "still at {}{unit} after {}; disabling it anyway, it will coast",
                    round(v),
                    show_duration(timeout)
                )));
            }
            let live = format!("{} {}{unit}", object.name, round(v));
            self.observer.step_progress(number, waited, Some(timeout), &live);
            self.wait(self.clock.now().saturating_add(STOP_POLL).min(give_up))?;
        }
    }

    /// Performs the safe stop's own steps in order, each on its drive and numbered
    /// `phase.N` after `done` earlier ones, each recorded, a failure noted and the next
    /// tried; a second stop request abandons the rest. Returns the number of the last.
    pub(super) fn perform_stop_steps(
        &mut self,
        steps: Vec<StopStep>,
        phase: &'static str,
        suffix: &str,
        done: usize,
    ) -> usize {
        let origin = StepOrigin {
            path: self.report.recipe_path.clone(),
            line: 0,
            column: 0,
        };
        let count = steps.len();
        for (i, step) in steps.into_iter().enumerate() {
            let i = done + i;
            if self.interrupted() {
                self.note(format!(
                    "{phase} abandoned at step {} (a second stop request)",
                    i + 1
                ));
                return i;
            }
            self.current = step.drive;
            let on = match self.several_drives() {
                true => format!("{}: ", self.cur().name),
                false => String::new(),
            };
            let info = StepInfo {
                number: format!("{phase}.{}", i + 1),
                label: format!("{on}{}{suffix}", step.label),
                origin: origin.clone(),
                phase,
                container: false,
            };
            self.perform_best_effort(&info, |s| (step.op)(s));
        }
        done + count
    }
}

/// ` rpm` for an object with a unit, nothing for one without.
fn unit_suffix(object: &ObjectRef) -> String {
    object
        .unit
        .as_deref()
        .map(|u| format!(" {u}"))
        .unwrap_or_default()
}
