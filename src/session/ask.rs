//! The operator steps as session operations: a prompt answered beforehand, or asked at the
//! terminal while the session keeps serving the drives (the fault watch, the cyclic
//! channel's telegrams) and stays stoppable; each answer recorded as a check with who
//! answered and when, a typed value compared with the unit's last passed run, and an
//! answer for a part of the unit's identity passed on.

use super::history_lookup::Compared;
use super::operator::{Given, Reply};
use super::prompt::{Accepted, Prompt, PromptKind};
use super::session::Session;
use super::stop::Stop;
use super::Limits;
use super::{CheckResult, StepOrigin};
use std::time::Duration;

/// How long the session waits for a keystroke before it serves the drives again, and so
/// the longest a stop request or a typed answer waits for the session (in real time).
const SLICE: Duration = Duration::from_millis(20);

impl Session<'_> {
    /// Asks `prompt` and records the answer as a check; the text of the step line and
    /// what was answered. A "no" or a value outside its limits fails the check and the run
    /// goes on; no answer within the prompt's timeout fails and stops the run
    /// ([`Stop::Unanswered`], never retried); a closed terminal ends the run (an error); a
    /// stop request or a drive fault ends the wait at once.
    /// A value compared with the unit's last passed run is a second check right after
    /// the answer's (the run looked up before the question, not after the operator typed).
    /// An answer that sets the unit's serial looks up its last passed run at once (bounded,
    /// the drives served meanwhile) for the checks that compare with it.
    pub fn ask(
        &mut self,
        prompt: &Prompt,
        origin: &StepOrigin,
        number: &str,
    ) -> Result<(String, Accepted), Stop> {
        let compared = match &prompt.kind {
            PromptKind::Value {
                unit,
                last_pass: Some(lp),
                ..
            } => Some((unit.map(|u| u.symbol()), lp)),
            _ => None,
        };
        if compared.is_some() {
            self.will_compare(&prompt.text, &prompt.text)?;
        }
        let (mut detail, accepted) = self.ask_once(prompt, origin, number)?;
        if let Some((unit, lp)) = compared {
            let of = Compared {
                name: &prompt.text,
                key: &prompt.text,
                what: "answer".into(),
                unit,
            };
            if let Some(failed) = self.record_comparison(&of, lp, accepted.number, origin) {
                detail = match accepted.passed {
                    true => format!("FAILED: {detail}; {failed}"),
                    false => format!("{detail}; {failed}"),
                };
            }
        }
        self.look_up_last_pass(true)?;
        Ok((detail, accepted))
    }

    fn ask_once(
        &mut self,
        prompt: &Prompt,
        origin: &StepOrigin,
        number: &str,
    ) -> Result<(String, Accepted), Stop> {
        let started = self.clock.now();
        if self.in_safe_stop {
            // A script's `finally` can get here; a recipe's is refused when loaded.
            return Err(Stop::Error(format!(
                "`{prompt}` ({origin}) asks the operator during the safe stop, which must never wait for a person; it was skipped"
            )));
        }
        if let Some(given) = self.operator.given(&prompt.name) {
            return self.given_answer(prompt, &given, origin, started);
        }
        if !self.operator.has_terminal() {
            return Err(Stop::Error(format!(
                "nobody can answer `{}` ({origin}): standard input is not a terminal and no answer was given; give one with --answer {}=VALUE or --answers FILE",
                prompt.text, prompt.name
            )));
        }
        self.operator.discard_typed_ahead();
        self.observer
            .asked(number, &format!("{} {}", prompt.text, prompt.hint()));
        self.observer.idle();
        self.operator.start_asking();
        loop {
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.watch_fault(false)?;
            let waited = self.clock.now().saturating_sub(started);
            if let Some(limit) = prompt.timeout.filter(|t| waited >= *t) {
                return Err(self.unanswered(prompt, origin, limit, started));
            }
            // In virtual time the clock does not wait for a person: the wait for a
            // keystroke paces it, so a prompt takes as long on the run's clock as it does
            // for the person (and the cyclic channel sends as many telegrams).
            let pace = if self.clock.is_virtual() {
                SLICE
            } else {
                Duration::ZERO
            };
            match self.operator.next_line(pace) {
                Reply::Line(line) => match prompt.judge(&line) {
                    Ok(accepted) => {
                        let who = format!(
                            "by {}",
                            self.run
                                .unit
                                .operator
                                .clone()
                                .unwrap_or_else(|| self.operator.person())
                        );
                        let detail = self.record_answer(prompt, &accepted, &who, origin, started)?;
                        return Ok((detail, accepted));
                    }
                    Err(why) => {
                        self.observer.message(&format!("{why}; answer again"));
                        self.observer.idle();
                        self.operator.start_asking();
                    }
                },
                Reply::Closed => {
                    return Err(Stop::Error(format!(
                        "the terminal closed (end of input) while asking `{}` ({origin}): nobody can answer, so the run ends here with the safe stop",
                        prompt.text
                    )))
                }
                Reply::Nothing => {}
            }
            let mut until = self.clock.now().saturating_add(SLICE);
            if let Some(t) = prompt.timeout {
                until = until.min(started.saturating_add(t));
            }
            self.wait(until)?;
        }
    }

    fn given_answer(
        &mut self,
        prompt: &Prompt,
        given: &Given,
        origin: &StepOrigin,
        started: Duration,
    ) -> Result<(String, Accepted), Stop> {
        let accepted = prompt.judge(&given.value).map_err(|why| {
            Stop::Error(format!(
                "the answer `{}` given for `{}` ({}) is no answer to `{}` ({origin}): {why}",
                given.value, prompt.name, given.source, prompt.text
            ))
        })?;
        let who = format!("(given with {})", given.source);
        let detail = self.record_answer(prompt, &accepted, &who, origin, started)?;
        Ok((detail, accepted))
    }

    /// Records the answer as a check (`who`, `by J. Smith`, and when in its message) and
    /// passes on a part of the unit's identity; the step line's text. An answer naming
    /// another unit than the run already knows (`--unit`, an earlier answer) fails its
    /// check and stops the run: what it measured next would be recorded for the wrong
    /// unit.
    fn record_answer(
        &mut self,
        prompt: &Prompt,
        accepted: &Accepted,
        who: &str,
        origin: &StepOrigin,
        started: Duration,
    ) -> Result<String, Stop> {
        let when = humantime::format_rfc3339_seconds(self.clock.wall_time());
        let mut message = format!("answered `{}` {who} at {when}", accepted.text);
        let sets = match &prompt.kind {
            PromptKind::Text { sets: Some(part), .. } => Some(*part),
            _ => None,
        };
        let other_unit = sets.and_then(|part| {
            let known = self.run.unit.field(part).filter(|k| *k != accepted.text)?;
            Some(format!(
                "this run is for {part} {known}, not {}: the unit on the bench is not the one the run was started for",
                accepted.text
            ))
        });
        if let Some(why) = &other_unit {
            message.push_str(&format!(", but {why}"));
            let refused = Accepted {
                passed: false,
                ..accepted.clone()
            };
            // No attempt follows (its line must not say `retrying`).
            self.observer.attempts_given_up();
            self.record_prompt_check(prompt, Some(&refused), message, origin, started);
            return Err(Stop::OtherUnit(format!("`{}` ({origin}): {why}", prompt.text)));
        }
        if let (false, Some(limits)) = (accepted.passed, prompt.limits_text()) {
            message.push_str(&format!(", expected {limits}"));
        }
        self.record_prompt_check(prompt, Some(accepted), message, origin, started);
        if let Some(part) = sets {
            self.identify(part, &accepted.text);
        }
        Ok(if accepted.passed {
            format!("`{}`", accepted.text)
        } else {
            format!("FAILED: `{}`", accepted.text)
        })
    }

    /// A part of the unit's identity learnt during the run: the report and every observer
    /// get the whole identity as it now stands.
    fn identify(&mut self, part: &str, value: &str) {
        if let Some(slot) = self.run.unit.field_mut(part) {
            *slot = Some(value.to_string());
            self.report.unit = self.run.unit.clone();
            let unit = self.run.unit.clone();
            self.observer.unit_identified(&unit);
        }
    }

    /// Nobody answered within the prompt's timeout: a failed check, and the run stops (an
    /// `attempts` block does not try again: an absent person is no failed measurement, and
    /// another attempt would move the drive again with nobody watching).
    fn unanswered(
        &mut self,
        prompt: &Prompt,
        origin: &StepOrigin,
        limit: Duration,
        started: Duration,
    ) -> Stop {
        let message = format!("nobody answered within {}", super::session::show_duration(limit));
        self.observer.attempts_given_up();
        self.record_prompt_check(prompt, None, message.clone(), origin, started);
        Stop::Unanswered(message)
    }

    /// The check of `prompt`: named after its question, with the answer (`None`: none
    /// came, which fails it) and a value's unit and limits.
    fn record_prompt_check(
        &mut self,
        prompt: &Prompt,
        accepted: Option<&Accepted>,
        message: String,
        origin: &StepOrigin,
        started: Duration,
    ) {
        let (unit, limits) = match &prompt.kind {
            PromptKind::Value { unit, limits, .. } => (unit.map(|u| u.symbol().to_string()), *limits),
            _ => (None, Limits::default()),
        };
        let passed = accepted.is_some_and(|a| a.passed);
        let result = CheckResult {
            passed,
            measured: accepted.and_then(|a| a.number),
            measured_text: accepted.map(|a| a.text.clone()),
            unit,
            limits,
            message,
            inclusive: true,
            // A question holds no limits: it is its own key.
            ..self.check_now(prompt.text.clone(), prompt.text.clone(), origin, started)
        };
        if !passed {
            self.failed_checks = true;
        }
        self.record_check_result(result);
    }
}
