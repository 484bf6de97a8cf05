//! `wait_until`: poll a state or a value until a condition holds, with a timeout, and
//! record it as a check.

use super::session::show_duration;
use super::session::value_of;
use super::session::{secs, Session};
use super::stop::Stop;
use super::Limits;
use super::{CheckResult, Condition, ObjectRef, StepOrigin, WAIT};
use crate::drive::DeviceState;
use std::time::Duration;

impl Session<'_> {
    /// Polls until `condition` holds; a timeout fails (and stops the run), naming the last
    /// value seen.
    pub fn wait_until(
        &mut self,
        condition: &Condition,
        timeout: Duration,
        every: Duration,
        origin: &StepOrigin,
        number: &str,
    ) -> Result<String, Stop> {
        if let Condition::Stable { .. } = condition {
            return self.wait_until_stable(condition, self.polling(timeout, every), origin, number);
        }
        let poll = self.polling(timeout, every);
        let started = poll.started;
        loop {
            let (holds, seen, value) = self.read_condition(condition)?;
            let waited = self.clock.now().saturating_sub(started);
            if holds {
                if matches!(
                    condition,
                    Condition::State(DeviceState::Fault | DeviceState::FaultReactionActive)
                ) {
                    for d in &mut self.drives {
                        d.known_fault = true;
                    }
                }
                self.record_check(
                    origin,
                    &condition.to_string(),
                    true,
                    value,
                    Some(seen.clone()),
                    condition,
                    None,
                    started,
                );
                return Ok(format!("{seen} after {}", secs(waited)));
            }
            if !matches!(condition, Condition::State(DeviceState::Fault)) {
                self.watch_fault(false)?;
            }
            if waited >= timeout {
                let mut message = timed_out(timeout, &condition.to_string(), &seen);
                if let Condition::State(state) = condition {
                    if !matches!(state, DeviceState::Fault | DeviceState::FaultReactionActive) {
                        // The usual cause: a wait written where a command was meant.
                        message.push_str(&format!(
                            " (`wait_until` only waits; `go_to: {}` is what moves the drive there)",
                            state.id()
                        ));
                    }
                }
                self.record_check(
                    origin,
                    &condition.to_string(),
                    false,
                    value,
                    Some(seen),
                    condition,
                    Some(message.clone()),
                    started,
                );
                return Err(Stop::Failed(message));
            }
            let next = poll.next_after(self.clock.now());
            self.between_polls(number, waited, timeout, &seen, next)?;
        }
    }

    /// Polls `object` until `holds` (a front end's own condition, such as a script's
    /// closure) accepts its value; like [`Session::wait_until`] a timeout fails and stops
    /// the run, and the wait is recorded as a check named `wait until {what}`.
    #[allow(clippy::too_many_arguments)]
    pub fn wait_until_value(
        &mut self,
        object: &ObjectRef,
        what: &str,
        holds: &mut dyn FnMut(f64) -> Result<bool, Stop>,
        timeout: Duration,
        every: Duration,
        origin: &StepOrigin,
        number: &str,
    ) -> Result<String, Stop> {
        let poll = self.polling(timeout, every);
        let started = poll.started;
        loop {
            let name = self.select_object(&object.name)?;
            let v = self.drive().read_number(name)?;
            let seen = value_of(v, object);
            let waited = self.clock.now().saturating_sub(started);
            let ok = holds(v)?;
            if ok || waited >= timeout {
                let message = (!ok).then(|| timed_out(timeout, what, &seen));
                // The script's condition has no limits to leave out.
                let name = format!("{WAIT}{what}");
                let result = CheckResult {
                    passed: ok,
                    measured: Some(v),
                    measured_text: Some(seen.clone()),
                    unit: object.unit.clone(),
                    object: Some(object.name.clone()),
                    message: message.clone().unwrap_or_else(|| "reached".into()),
                    ..self.check_now(name.clone(), name, origin, started)
                };
                self.record_check_result(result);
                return wait_ended(message, &seen, waited);
            }
            self.watch_fault(false)?;
            let next = poll.next_after(self.clock.now());
            self.between_polls(number, waited, timeout, &seen, next)?;
        }
    }

    /// A wait that polls every `every` for at most `timeout`, starting now.
    pub(super) fn polling(&self, timeout: Duration, every: Duration) -> Polling {
        Polling {
            started: self.clock.now(),
            timeout,
            every,
        }
    }

    /// Between two polls of a wait, after the fault watch: a stop request ends it, the
    /// progress is shown, and the run waits until `next`.
    pub(super) fn between_polls(
        &mut self,
        number: &str,
        waited: Duration,
        timeout: Duration,
        seen: &str,
        next: Duration,
    ) -> Result<(), Stop> {
        if self.interrupted() {
            return Err(Stop::Interrupted);
        }
        if self.observer.wants_progress() {
            self.observer.step_progress(number, waited, Some(timeout), seen);
        }
        self.wait(next)
    }

    /// A check `name` (keyed `key`, the name without its limits) of the current step begun
    /// at `started`, with what every check a session operation records shares (its step
    /// and stage, when and how long); not passed and with nothing measured until the
    /// caller says otherwise.
    pub(super) fn check_now(
        &self,
        name: String,
        key: String,
        origin: &StepOrigin,
        started: Duration,
    ) -> CheckResult {
        let (step, stage) = self.place();
        let at = self.clock.now();
        CheckResult {
            key,
            origin: origin.clone(),
            step,
            stage,
            at,
            duration: at.saturating_sub(started),
            ..CheckResult::named(name, false)
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn record_check(
        &mut self,
        origin: &StepOrigin,
        name: &str,
        passed: bool,
        value: Option<f64>,
        text: Option<String>,
        condition: &Condition,
        message: Option<String>,
        started: Duration,
    ) {
        let (object, unit, (low, high)) = match condition {
            Condition::State(_) => (None, None, (None, None)),
            Condition::Value { object, predicate } => (
                Some(object.name.clone()),
                object.unit.clone(),
                predicate.reported_limits(),
            ),
            Condition::Stable {
                object,
                predicate,
                rate_unit,
                ..
            } => (
                Some(object.name.clone()),
                Some(rate_unit.clone()),
                predicate.limits(),
            ),
        };
        let result = CheckResult {
            passed,
            measured: value,
            measured_text: text,
            unit,
            limits: Limits::new(low, high),
            object,
            message: message.unwrap_or_else(|| "reached".into()),
            ..self.check_now(
                format!("{WAIT}{name}"),
                format!("{WAIT}{}", condition.key()),
                origin,
                started,
            )
        };
        self.record_check_result(result);
    }
}

/// Why a wait failed: `timed out after 10s waiting for …; last value seen: …`.
pub(super) fn timed_out(timeout: Duration, what: &str, seen: &str) -> String {
    format!(
        "timed out after {} waiting for {what}; last value seen: {seen}",
        show_duration(timeout)
    )
}

/// A wait that polls: when it started (the session's clock), how long it may take, how
/// often it polls.
#[derive(Debug, Clone, Copy)]
pub(super) struct Polling {
    pub started: Duration,
    pub timeout: Duration,
    pub every: Duration,
}

impl Polling {
    /// When the poll after one at `now` is due: a period on, never past the timeout.
    pub fn next_after(&self, now: Duration) -> Duration {
        now.saturating_add(self.every)
            .min(self.started.saturating_add(self.timeout))
    }
}

/// How a wait ended: the value seen and when, or (`message`) why it failed, which stops the
/// run (an `attempts` block tries again).
pub(super) fn wait_ended(message: Option<String>, seen: &str, waited: Duration) -> Result<String, Stop> {
    match message {
        None => Ok(format!("{seen} after {}", secs(waited))),
        Some(m) => Err(Stop::Failed(m)),
    }
}
