//! `wait_until`: poll a state or a value until a condition holds, with a timeout, and
//! record it as a check.

use super::session::show_duration;
use super::session::value_of;
use super::session::{secs, Session};
use super::stop::Stop;
use super::{CheckResult, Condition, ObjectRef, StepOrigin};
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
            return self.wait_until_stable(condition, timeout, every, origin, number);
        }
        let started = self.clock.now();
        let give_up = started.saturating_add(timeout);
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
                let message = format!(
                    "timed out after {} waiting for {condition}; last value seen: {seen}",
                    show_duration(timeout)
                );
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
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.observer.step_progress(number, waited, Some(timeout), &seen);
            self.wait(self.clock.now().saturating_add(every).min(give_up))?;
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
        let started = self.clock.now();
        let give_up = started.saturating_add(timeout);
        loop {
            let name = self.select_object(&object.name)?;
            let v = self.drive().read_number(name)?;
            let seen = value_of(v, object);
            let waited = self.clock.now().saturating_sub(started);
            let ok = holds(v)?;
            if ok || waited >= timeout {
                let message = (!ok).then(|| {
                    format!(
                        "timed out after {} waiting for {what}; last value seen: {seen}",
                        show_duration(timeout)
                    )
                });
                let result = CheckResult {
                    name: format!("wait until {what}"),
                    passed: ok,
                    measured: Some(v),
                    measured_text: Some(seen.clone()),
                    unit: object.unit.clone(),
                    low: None,
                    high: None,
                    object: Some(object.name.clone()),
                    statistic: None,
                    step: self.place().0,
                    stage: self.place().1,
                    window: None,
                    message: message.clone().unwrap_or_else(|| "reached".into()),
                    origin: origin.clone(),
                    at: self.clock.now(),
                    duration: waited,
                    marginal: false,
                    retried: false,
                    inclusive: false,
                    reference: None,
                };
                self.record_check_result(result);
                return match message {
                    None => Ok(format!("{seen} after {}", secs(waited))),
                    Some(m) => Err(Stop::Failed(m)),
                };
            }
            self.watch_fault(false)?;
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.observer.step_progress(number, waited, Some(timeout), &seen);
            self.wait(self.clock.now().saturating_add(every).min(give_up))?;
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
            Condition::Value { object, predicate } => {
                (Some(object.name.clone()), object.unit.clone(), predicate.limits())
            }
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
            name: format!("wait until {name}"),
            passed,
            measured: value,
            measured_text: text,
            unit,
            low,
            high,
            object,
            statistic: None,
            message: message.unwrap_or_else(|| "reached".into()),
            origin: origin.clone(),
            step: self.place().0,
            stage: self.place().1,
            window: None,
            at: self.clock.now(),
            duration: self.clock.now().saturating_sub(started),
            marginal: false,
            retried: false,
            inclusive: false,
            reference: None,
        };
        self.record_check_result(result);
    }
}
