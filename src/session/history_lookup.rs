//! The session's side of comparing with the unit's last passed run: looking it up when
//! the unit's serial becomes known (at the start, or when an operator step sets it),
//! bounded in time and stoppable while the drives are served, and judging a check's
//! comparison against it. Never on the safe stop's path (the safe stop makes no checks).

use super::last_pass::{signed, LastPass, PastRun};
use super::session::round;
use super::session::Session;
use super::stop::Stop;
use super::Limits;
use super::{compared_key, with_unit, CheckReference, CheckResult, StepOrigin, COMPARED};
use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration, Instant};

/// The longest the run waits for the store to say which run is the last pass (real time,
/// as long as the store's own connection limit).
pub const LOOKUP_LIMIT: Duration = Duration::from_secs(10);
/// How often the wait serves the drives and looks for a stop request.
const SLICE: Duration = Duration::from_millis(20);

/// The check a comparison is made for: its name and key, what it measured
/// (`current_actual mean`, `coast-down time`, `answer`) and in which unit.
pub(super) struct Compared<'c> {
    pub name: &'c str,
    pub key: &'c str,
    pub what: String,
    pub unit: Option<&'c str>,
}

/// What the session knows of the unit's last passed run.
#[derive(Debug, Clone, Default)]
pub(super) enum Past {
    /// Not looked up: no serial known yet.
    #[default]
    NotLooked,
    /// The store answered for this serial (`None`: no earlier passed run).
    Known { serial: String, run: Option<PastRun> },
    /// The store could not be read for this serial, or did not answer in time: what to
    /// say. Not asked again for the same serial (each operator step would wait again).
    Unreadable { serial: String, why: String },
}

impl Past {
    /// The serial it was looked up for.
    fn serial(&self) -> Option<&str> {
        match self {
            Past::NotLooked => None,
            Past::Known { serial, .. } | Past::Unreadable { serial, .. } => Some(serial),
        }
    }
}

impl Session<'_> {
    /// Looks up the last passed run of the unit whose serial is now known, if the recipe
    /// compares with one and it was not looked up for this serial yet, and says what it
    /// found. `serve`: the drives are served and watched for faults during the wait (a
    /// run under way); at the start nothing moves yet. At most [`LOOKUP_LIMIT`]; a stop
    /// request ends the wait at once.
    pub(super) fn look_up_last_pass(&mut self, serve: bool) -> Result<(), Stop> {
        // The safe stop never waits for a store: a comparison there judges by what was
        // looked up before.
        if self.history_checks.is_empty() || self.in_safe_stop {
            return Ok(());
        }
        let Some(serial) = self.run.unit.serial.clone() else {
            return Ok(());
        };
        if self.past.serial() == Some(serial.as_str()) {
            return Ok(());
        }
        let Some(history) = self.history.clone() else {
            self.past = Past::Unreadable {
                serial,
                why: "no results store to compare with (none is named and there is no data directory)".into(),
            };
            let said = self.past_said("", "");
            self.observer.message(&said);
            return Ok(());
        };
        let answer = history.look_up(&self.run.name, &serial);
        let started = Instant::now();
        self.past = loop {
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            if serve {
                self.watch_fault(false)?;
            }
            // As an operator step paces virtual time: the clock moves as real time does.
            let pace = if self.clock.is_virtual() {
                SLICE
            } else {
                Duration::ZERO
            };
            match answer.recv_timeout(pace) {
                Ok(Ok(run)) => break Past::Known { serial, run },
                Ok(Err(e)) => {
                    break Past::Unreadable {
                        serial,
                        why: e.to_string(),
                    }
                }
                Err(RecvTimeoutError::Disconnected) => {
                    break Past::Unreadable {
                        serial,
                        why: format!(
                            "the results store {} gave no answer (its reader ended)",
                            history.store()
                        ),
                    }
                }
                Err(RecvTimeoutError::Timeout) => {}
            }
            if started.elapsed() >= LOOKUP_LIMIT {
                break Past::Unreadable {
                    serial,
                    why: format!(
                        "the results store {} did not answer within {} s",
                        history.store(),
                        LOOKUP_LIMIT.as_secs()
                    ),
                };
            }
            let until = self.clock.now().saturating_add(SLICE);
            self.wait(until)?;
        };
        let said = self.past_said(history.kind_of_runs(), &history.store());
        self.observer.message(&said);
        Ok(())
    }

    /// The line that says which run the comparisons are made against, with the value of
    /// each check compared.
    fn past_said(&self, kind: &str, store: &str) -> String {
        match &self.past {
            Past::Known {
                serial,
                run: Some(run),
            } => {
                let values: Vec<String> = self
                    .history_checks
                    .iter()
                    .map(|(name, key)| match run.last_check(key, name) {
                        Some(c) => format!("{name} = {}", with_unit(round(c.measured), c.unit.as_deref())),
                        None => format!("{name}: not in that run"),
                    })
                    .collect();
                format!(
                    "history {serial}: compared with its last pass, run {} of {}: {}",
                    run.id,
                    run.started_at,
                    values.join("; ")
                )
            }
            Past::Known { serial, run: None } => format!(
                "history {serial}: no earlier passed run of `{}` in {store} ({kind}); each comparison passes or fails as its `without_history` says",
                self.run.name
            ),
            Past::Unreadable { why, .. } => {
                format!("history: cannot compare with the last pass: {why}; those checks fail")
            }
            Past::NotLooked => String::new(),
        }
    }

    /// The comparison of check `c` (measured `measured`) with the same check in the
    /// unit's last passed run: a check of its own, named after `c`.
    pub(super) fn compared_with_last_pass(
        &self,
        c: &Compared,
        lp: &LastPass,
        measured: Option<f64>,
        origin: &StepOrigin,
    ) -> CheckResult {
        let (step, stage) = self.place();
        let unit = match lp.relative {
            true => Some("%".to_string()),
            // A change is a difference: K for a temperature in °C.
            false => c.unit.map(|u| {
                crate::dictionary::Unit::from_symbol(u)
                    .map_or(u.to_string(), |x| x.difference().symbol().to_string())
            }),
        };
        let allowed = lp.describe(unit.as_deref());
        let mut reference = None;
        let mut change = None;
        let (passed, message) = match (&self.past, measured) {
            (_, None) => (false, format!("nothing measured to compare with the last pass ({allowed})")),
            (Past::NotLooked, _) if self.in_safe_stop && self.run.unit.serial.is_some() => (
                false,
                "not looked up: the safe stop (finally, on_fault) never waits for the results store, so a comparison there is judged by what was looked up before it, and nothing was; compare before the safe stop".to_string(),
            ),
            (Past::NotLooked, _) => (
                false,
                "the unit's serial was not known when this check was made: an operator step with `sets: serial` must come before it, or give --unit serial=…".to_string(),
            ),
            (Past::Unreadable { why, .. }, _) => (false, format!("cannot be judged: {why}")),
            (Past::Known { serial, run }, Some(v)) => {
                let found = run.as_ref().and_then(|r| r.check(c.key, c.name, &step, &stage).map(|p| (r, p)));
                match found {
                    None => {
                        let why = match run {
                            Some(r) => format!(
                                "the last passed run of {serial}, {} of {}, has no check `{}`",
                                r.id, r.started_at, c.name
                            ),
                            None => format!("no earlier passed run of {serial} for this recipe"),
                        };
                        let verdict = if lp.pass_without_history { "passes" } else { "fails" };
                        (
                            lp.pass_without_history,
                            format!(
                                "{why}: {verdict} as `without_history: {}` says",
                                lp.without_history_word()
                            ),
                        )
                    }
                    Some((r, p)) => {
                        reference = Some(CheckReference {
                            run: r.id.clone(),
                            started_at: r.started_at.clone(),
                            value: p.measured,
                        });
                        let now = format!("{} = {}", c.what, with_unit(round(v), c.unit));
                        // Shown to three decimals as every measured value; stored exact.
                        let was = with_unit(round(p.measured), c.unit);
                        match lp.change(p.measured, v) {
                            None => (
                                false,
                                format!(
                                    "{now}: against {was} in run {} of {}, a change relative to 0 is not defined; allow an absolute change (in {}) instead",
                                    r.id,
                                    r.started_at,
                                    c.unit.unwrap_or("the check's unit")
                                ),
                            ),
                            Some(d) => {
                                change = Some(d);
                                (
                                    lp.allows(d),
                                    format!(
                                        "{now}: {} against {was} in run {} of {}",
                                        signed(round(d), unit.as_deref()),
                                        r.id,
                                        r.started_at
                                    ),
                                )
                            }
                        }
                    }
                }
            }
        };
        let message = match (passed, change) {
            (false, Some(_)) => format!("{message}, expected a change {allowed}"),
            _ => message,
        };
        CheckResult {
            name: format!("{}{COMPARED}", c.name),
            key: compared_key(c.key),
            passed,
            measured: change,
            measured_text: None,
            unit,
            limits: Limits::new(lp.at_least, lp.at_most),
            object: None,
            statistic: None,
            message,
            origin: origin.clone(),
            step,
            stage,
            window: None,
            at: self.clock.now(),
            duration: Duration::ZERO,
            marginal: false,
            retried: false,
            inclusive: true,
            // A change in % or in the check's unit: no count of an object.
            decimals: None,
            reference,
        }
    }
}

impl Session<'_> {
    /// Check `name` (keyed `key`) will be compared with the unit's last passed run: it is
    /// named in what the lookup says, and the run is looked up now if it was not for this
    /// serial yet (a script's checks are not known before it runs). Never in the safe stop.
    pub(super) fn will_compare(&mut self, name: &str, key: &str) -> Result<(), Stop> {
        if !self.history_checks.iter().any(|(_, k)| k == key) {
            self.history_checks.push((name.to_string(), key.to_string()));
        }
        self.look_up_last_pass(true)
    }

    /// Records the comparison of check `c` (measured `measured`) with the same check in
    /// the unit's last passed run, right after `c` itself; what to say when it failed.
    pub(super) fn record_comparison(
        &mut self,
        c: &Compared,
        lp: &LastPass,
        measured: Option<f64>,
        origin: &StepOrigin,
    ) -> Option<String> {
        let compared = self.compared_with_last_pass(c, lp, measured, origin);
        let failed = (!compared.passed).then(|| format!("{}: {}", compared.name, compared.message));
        if failed.is_some() {
            self.failed_checks = true;
        }
        self.record_check_result(compared);
        failed
    }

    /// A script's comparison of its check `name` (made with `expect`, measuring
    /// `measured`) with the same check in the unit's last passed run.
    pub fn expect_compared_with_last_pass(
        &mut self,
        name: &str,
        measured: f64,
        lp: &LastPass,
        origin: &StepOrigin,
    ) -> Result<String, Stop> {
        // A script names its checks itself: the name is the key.
        self.will_compare(name, name)?;
        let check = Compared {
            name,
            key: name,
            what: name.to_string(),
            unit: None,
        };
        let result = self.compared_with_last_pass(&check, lp, Some(measured), origin);
        self.expect_result(result)
    }
}
