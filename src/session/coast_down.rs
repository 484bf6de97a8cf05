//! `coast_down`: the power stage off on purpose and the spindle left to coast, the speed
//! read on, and the time it takes from one speed down past another recorded as a check
//! (bearing drag shows as a coast-down that shrinks from one test to the next). While it
//! coasts the drive is marked so the safe stop says it cannot brake it. Both crossing
//! times are interpolated between polls; the time may also be compared with the unit's
//! last passed run, looked up before the power stage goes off. It must not know recipes or
//! scripts.

use super::history_lookup::Compared;
use super::session::{round, show_duration, Session};
use super::stop::Stop;
use super::Limits;
use super::{BucketSeries, CheckResult, LastPass, Predicate, SetValue, Stats, StepOrigin, SERIES_BUCKETS};
use crate::dictionary::Role;
use crate::drive::DeviceCommand;
use std::time::Duration;

/// What a coast-down measures and how long it may take.
#[derive(Debug, Clone, PartialEq)]
pub struct CoastDown {
    /// The name the recipe gave the step, which names its check (as an `expect`'s does).
    pub name: Option<String>,
    /// The speed the time counts from (the object's unit), crossed on the way down.
    pub from: f64,
    /// The speed the time counts to.
    pub below: f64,
    /// The check on the time in seconds.
    pub predicate: Predicate,
    /// Its warning band: a time that passes outside it is marginal.
    pub warn: Option<Predicate>,
    pub timeout: Duration,
    pub every: Duration,
    /// The actual speed's unit (for the check's name, known before the run).
    pub unit: Option<String>,
    /// How far the time may move from the same check's in the unit's last passed run: a
    /// second check, made right after this one.
    pub last_pass: Option<LastPass>,
}

impl CoastDown {
    /// `coast-down from 6000 rpm below 100 rpm near 19.7 s ± 0.5 s`, or the name the recipe
    /// gave.
    pub fn check_name(&self) -> String {
        match &self.name {
            Some(name) => name.clone(),
            None => format!("{} {}", self.measured(), self.predicate.describe(Some("s"))),
        }
    }

    /// What stays the same when its limits change: what it measures (`coast-down from
    /// 6000 rpm below 100 rpm`), or the name the recipe gave.
    pub fn check_key(&self) -> String {
        self.name.clone().unwrap_or_else(|| self.measured())
    }

    /// `coast-down from 6000 rpm below 100 rpm`.
    fn measured(&self) -> String {
        let unit = self.unit.as_deref().map(|u| format!(" {u}")).unwrap_or_default();
        format!(
            "coast-down from {}{unit} below {}{unit}",
            round(self.from),
            round(self.below)
        )
    }
}

impl Session<'_> {
    pub fn coast_down(&mut self, c: &CoastDown, origin: &StepOrigin, number: &str) -> Result<String, Stop> {
        let (name, key) = (c.check_name(), c.check_key());
        // While the drive still holds its speed: the store is never waited for while the
        // spindle coasts (nor in the safe stop).
        if c.last_pass.is_some() {
            self.will_compare(&name, &key)?;
        }
        let Some(object) = self.role_ref(Role::SpeedActual) else {
            return Err(Stop::Failed(
                "the drive's profile names no actual speed to watch".into(),
            ));
        };
        let unit = object.unit.clone().map(|u| format!(" {u}")).unwrap_or_default();
        let started = self.clock.now();
        let first = self.drive().read_number(&object.name)?.abs();
        if first < c.from {
            return Err(Stop::Failed(format!(
                "the spindle turns at {}{unit}, below the coast-down's start {}{unit}: bring it up to speed first",
                round(first),
                round(c.from)
            )));
        }
        self.cur().coasting_by_design = true;
        self.command(DeviceCommand::DisableOperation)?;
        // The old setpoint must not stand: the next enable would spin the spindle straight
        // back up to it.
        if let Some(setpoint) = self.role_ref(Role::SpeedSetpoint) {
            self.set(&[(setpoint, SetValue::number(0.0))])?;
        }
        let origin_s = started.saturating_sub(self.run_start).as_secs_f64();
        let width = (c.timeout.as_secs_f64() / SERIES_BUCKETS as f64).max(c.every.as_secs_f64());
        let mut series = BucketSeries::new(origin_s, width);
        let mut stats = Stats::default();
        let give_up = started.saturating_add(c.timeout);
        let (mut previous, mut from_at) = (None::<(f64, f64)>, None::<f64>);
        let result = loop {
            let v = self.drive().read_number(&object.name)?;
            let since_start = self.clock.now().saturating_sub(self.run_start);
            let t = since_start.as_secs_f64();
            series.push(t, v);
            stats.push(v);
            // The samples CSV holds the curve the report plots.
            self.observer
                .sample(since_start, std::slice::from_ref(&object), &[v]);
            let speed = v.abs();
            let crossing = |level: f64| match previous {
                Some((t0, v0)) if v0 > level && speed <= level => t0 + (t - t0) * (v0 - level) / (v0 - speed),
                _ => t,
            };
            if from_at.is_none() && speed <= c.from {
                from_at = Some(crossing(c.from));
            }
            if speed < c.below {
                let end = crossing(c.below);
                self.cur().coasting_by_design = false;
                break Ok(end - from_at.unwrap_or(end));
            }
            if self.clock.now() >= give_up {
                break Err(format!(
                    "still at {}{unit} after {}; it coasts on",
                    round(v),
                    show_duration(c.timeout)
                ));
            }
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            let live = format!("{} {}{unit} (coasting)", object.name, round(v));
            let waited = self.clock.now().saturating_sub(started);
            self.observer
                .step_progress(number, waited, Some(c.timeout), &live);
            previous = Some((t, speed));
            self.wait(self.clock.now().saturating_add(c.every).min(give_up))?;
        };
        self.keep_series(&object, &series, stats);
        let (passed, measured, message) = match result {
            Ok(secs) => {
                let passed = c.predicate.holds(secs);
                let said = format!("coast-down took {} s", round(secs));
                let message = match passed {
                    true => said,
                    false => format!("{said}, expected {}", c.predicate.describe(Some("s"))),
                };
                (passed, Some(secs), message)
            }
            Err(why) => (false, None, why),
        };
        let marginal = passed && c.warn.as_ref().zip(measured).is_some_and(|(w, v)| !w.holds(v));
        let message = match (&c.warn, marginal) {
            (Some(w), true) => format!(
                "{message}, MARGINAL: outside the warning band {}",
                w.describe(Some("s"))
            ),
            _ => message,
        };
        let (low, high) = c.predicate.limits();
        self.record_check_result(CheckResult {
            passed,
            measured,
            unit: Some("s".into()),
            limits: Limits::new(low, high),
            object: Some(object.name.clone()),
            statistic: Some("coast_down".into()),
            message: message.clone(),
            window: Some(self.path.id()),
            marginal,
            ..self.check_now(name.clone(), key.clone(), origin, started)
        });
        let mut failed: Vec<String> = Vec::new();
        if !passed {
            self.failed_checks = true;
            failed.push(message.clone());
        }
        if let Some(lp) = &c.last_pass {
            let of = Compared {
                name: &name,
                key: &key,
                what: "coast-down time".into(),
                unit: Some("s"),
            };
            failed.extend(self.record_comparison(&of, lp, measured, origin));
        }
        if failed.is_empty() {
            Ok(format!("power stage off, coasting by design: {message}"))
        } else {
            Ok(format!("FAILED: {}", failed.join("; ")))
        }
    }
}
