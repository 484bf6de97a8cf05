//! `expect`: named pass/fail checks on a value now, or on a statistic of the last sample
//! window; each becomes a check in the report. Also where an attempt's checks are marked
//! retried when it is tried again.

use super::session::Session;
use super::stop::Stop;
use super::Limits;
use super::{Check, CheckResult, Condition, Measured, StepOrigin};

impl Session<'_> {
    /// Named checks, instant or on the last sample window; a failed check is recorded and
    /// the run goes on (the result text starts with `FAILED`).
    pub fn expect(&mut self, checks: &[Check], origin: &StepOrigin) -> Result<String, Stop> {
        let mut failed = Vec::new();
        for c in checks {
            let started = self.clock.now();
            let (passed, measured, text, message) = match c.statistic {
                Some(stat) => match self.windows.get(&c.object.name).map(|w| w.measure(stat)) {
                    Some(Measured::Value(v)) => (
                        c.predicate.holds(v),
                        Some(v),
                        None,
                        format!(
                            "{} {} = {}",
                            c.object.name,
                            stat.id(),
                            self.shown_value(v, &c.object)
                        ),
                    ),
                    Some(Measured::Missing(why)) => (
                        false,
                        None,
                        None,
                        format!("no {} of {} to check: {why}", stat.id(), c.object.name),
                    ),
                    None => (
                        false,
                        None,
                        None,
                        format!("no samples of {} to check", c.object.name),
                    ),
                },
                None => {
                    let cond = Condition::Value {
                        object: c.object.clone(),
                        predicate: c.predicate.clone(),
                    };
                    let (ok, seen, v) = self.read_condition(&cond)?;
                    (ok, v, Some(seen.clone()), format!("{} = {seen}", c.object.name))
                }
            };
            let (low, high) = c.predicate.reported_limits();
            let marginal = passed && c.warn.as_ref().zip(measured).is_some_and(|(w, v)| !w.holds(v));
            let message = match (&c.warn, marginal) {
                (Some(w), true) => format!(
                    "{message}, MARGINAL: outside the warning band {}",
                    w.describe(c.object.unit.as_deref())
                ),
                _ => message,
            };
            let result = CheckResult {
                passed,
                measured,
                measured_text: text,
                unit: c.object.unit.clone(),
                limits: Limits::new(low, high),
                object: Some(c.object.name.clone()),
                statistic: c.statistic.map(|s| s.id().to_string()),
                message: if passed {
                    message
                } else {
                    format!(
                        "{message}, expected {}",
                        c.predicate.describe(c.object.unit.as_deref())
                    )
                },
                window: c
                    .statistic
                    .and_then(|_| self.window_steps.get(&c.object.name).cloned()),
                marginal,
                ..self.check_now(c.name.clone(), c.key.clone(), origin, started)
            };
            if !passed {
                self.failed_checks = true;
                failed.push(result.message.clone());
            }
            self.record_check_result(result);
            if let Some(lp) = &c.last_pass {
                let of = super::history_lookup::Compared {
                    name: &c.name,
                    key: &c.key,
                    what: match c.statistic {
                        Some(s) => format!("{} {}", c.object.name, s.id()),
                        None => c.object.name.clone(),
                    },
                    unit: c.object.unit.as_deref(),
                };
                failed.extend(self.record_comparison(&of, lp, measured, origin));
            }
        }
        if failed.is_empty() {
            let count = checks.len() + checks.iter().filter(|c| c.last_pass.is_some()).count();
            Ok(format!("{count} check(s) passed"))
        } else {
            Ok(format!("FAILED: {}", failed.join("; ")))
        }
    }

    /// A check a front end evaluated itself (a script's `expect`), recorded like the checks
    /// above: same report, JUnit and HTML; a failure lets the run go on.
    pub fn expect_result(&mut self, mut result: CheckResult) -> Result<String, Stop> {
        result.at = self.clock.now();
        (result.step, result.stage) = self.place();
        let passed = result.passed;
        let message = result.message.clone();
        if !passed {
            self.failed_checks = true;
        }
        self.record_check_result(result);
        if passed {
            Ok("1 check(s) passed".into())
        } else {
            Ok(format!("FAILED: {message}"))
        }
    }
}

/// Where the checks stood when an attempt began: how many were recorded and whether one had
/// failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AttemptMark {
    checks: usize,
    failed: bool,
}

impl Session<'_> {
    /// The current step (an `attempts` block, `number`) begins its attempt `attempt` of
    /// `of`: the ids of the steps inside carry `[attempt]`, the observers are told (so a
    /// console can say that a failure may yet be retried), and where the checks stand.
    pub fn begin_attempt(&mut self, number: &str, attempt: u32, of: u32) -> AttemptMark {
        self.iteration(attempt);
        self.observer.attempt_started(number, attempt, of);
        AttemptMark {
            checks: self.report.checks.len(),
            failed: self.failed_checks,
        }
    }

    /// Whether a check recorded since `mark` failed.
    pub fn failed_since(&self, mark: AttemptMark) -> bool {
        self.report.checks.iter().skip(mark.checks).any(|c| !c.passed)
    }

    /// The attempt since `mark` is tried again: its checks stay in the report, marked
    /// retried, and no longer decide the verdict.
    pub fn retry_attempt(&mut self, mark: AttemptMark) {
        for c in self.report.checks.iter_mut().skip(mark.checks) {
            c.retried = true;
        }
        self.failed_checks = mark.failed;
    }

    /// Where the checks stand now, for [`Session::failed_check_since`].
    pub fn check_mark(&self) -> AttemptMark {
        AttemptMark {
            checks: self.report.checks.len(),
            failed: self.failed_checks,
        }
    }

    /// The first check recorded since `mark` that failed and still counts (a failure an
    /// `attempts` block tried again does not): its name and where it is written.
    pub fn failed_check_since(&self, mark: AttemptMark) -> Option<String> {
        self.report
            .checks
            .iter()
            .skip(mark.checks)
            .find(|c| !c.passed && !c.retried)
            .map(|c| format!("{} ({})", c.name, c.origin))
    }

    /// The run ends at a failed check because `why` (`on_failure: stop`, `-x`) says so:
    /// said at once, kept among the run's notes (every report and the store show them) and
    /// as the reason the checks after it were not reached. Returns the stop that ends it.
    pub fn stop_on_failure(&mut self, check: &str, step: &str, why: &str) -> Stop {
        let text = format!(
            "stopped at the first failed check, {check} in step {step} ({why}); the steps after it were not run"
        );
        self.observer.message(&text);
        self.report.safe_stop.push(text.clone());
        self.report.stopped_on_failure = Some(text.clone());
        Stop::StoppedOnFailure(text)
    }
}
