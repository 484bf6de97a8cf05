//! Before anything is sent: the answers given on the command line against the plan's
//! operator steps (each name must be a step's, each answer one the step accepts), and a
//! run without a terminal refused when some step has no answer, naming every such step
//! at its place, and an answer that would set a part of the unit's identity the command
//! line already names otherwise. Judges only; asks nobody.

use super::RunError;
use crate::diag::did_you_mean;
use crate::session::{Given, Prompt, PromptKind, StepOrigin, UnitIdentity};
use std::fmt::Write as _;

/// The answers `given` for `prompts` (all of them known when `complete`: a recipe's; a
/// script's literal ones only); `terminal`: whether a person can be asked the rest;
/// `unit`: the identity the command line gives (`--unit`).
pub fn answers_checked(
    prompts: &[(Prompt, StepOrigin)],
    complete: bool,
    given: &[(String, Given)],
    terminal: bool,
    unit: &UnitIdentity,
) -> Result<(), RunError> {
    for (name, answer) in given {
        let asked: Vec<&(Prompt, StepOrigin)> = prompts.iter().filter(|(p, _)| &p.name == name).collect();
        if asked.is_empty() && complete {
            let names: Vec<&str> = prompts.iter().map(|(p, _)| p.name.as_str()).collect();
            let help = match did_you_mean(name, names.iter().copied()).first() {
                Some(s) => format!("did you mean `{s}`?"),
                None if names.is_empty() => "this file has no operator steps".to_string(),
                None => format!("its operator steps are: {}", names.join(", ")),
            };
            return Err(RunError::Invalid(format!(
                "error: {}: no operator step is called `{name}`; {help}",
                answer.source
            )));
        }
        for (prompt, origin) in asked {
            let accepted = prompt.judge(&answer.value).map_err(|why| {
                RunError::Invalid(format!(
                    "error: {}: the answer `{}` to `{name}` is no answer to \"{}\" at {origin}: {why}",
                    answer.source, answer.value, prompt.text
                ))
            })?;
            // Two different units named for one run: whichever the run believed, its
            // record would belong to the wrong one.
            if let PromptKind::Text { sets: Some(part), .. } = &prompt.kind {
                if let Some(known) = unit.field(part).filter(|k| *k != accepted.text) {
                    return Err(RunError::Invalid(format!(
                        "error: {}: the answer `{}` to `{name}` sets the unit's {part}, but --unit {part}={known} names another unit; nothing was sent\n  help: give the {part} once, or correct the one that is wrong",
                        answer.source, accepted.text
                    )));
                }
            }
        }
    }
    if terminal {
        return Ok(());
    }
    let mut unanswered = String::new();
    let mut count = 0;
    for (prompt, origin) in prompts {
        if !given.iter().any(|(n, _)| n == &prompt.name) {
            count += 1;
            let _ = writeln!(unanswered, "  {origin}: {}: {prompt}", prompt.name);
        }
    }
    if count == 0 {
        return Ok(());
    }
    Err(RunError::Invalid(format!(
        "error: standard input is not a terminal, so nobody can be asked, and {count} operator step(s) have no answer; nothing was sent:\n{unanswered}  help: give each answer with --answer NAME=VALUE, or in a file of `NAME: answer` lines with --answers FILE"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::PromptKind;

    fn prompt(name: &str, kind: PromptKind, line: usize) -> (Prompt, StepOrigin) {
        (
            Prompt {
                name: name.into(),
                text: format!("{name}?"),
                kind,
                timeout: None,
            },
            StepOrigin {
                path: "r.yaml".into(),
                line,
                column: 5,
            },
        )
    }

    fn given(name: &str, value: &str) -> (String, Given) {
        (
            name.into(),
            Given {
                value: value.into(),
                source: "--answer".into(),
            },
        )
    }

    /// [`answers_checked`] with no `--unit`.
    fn checked(
        prompts: &[(Prompt, StepOrigin)],
        complete: bool,
        given: &[(String, Given)],
        terminal: bool,
    ) -> Result<(), RunError> {
        answers_checked(prompts, complete, given, terminal, &UnitIdentity::default())
    }

    #[test]
    fn every_unanswered_step_is_named_at_its_place_without_a_terminal() {
        let prompts = [
            prompt("guard", PromptKind::Instruction, 4),
            prompt("quiet", PromptKind::Confirm, 6),
        ];
        let e = checked(&prompts, true, &[], false).unwrap_err().to_string();
        assert!(e.contains("2 operator step(s) have no answer"), "{e}");
        assert!(e.contains("r.yaml:4:5: guard: instruct \"guard?\""), "{e}");
        assert!(e.contains("r.yaml:6:5: quiet: confirm \"quiet?\""), "{e}");
        assert!(
            checked(&prompts, true, &[], true).is_ok(),
            "a terminal answers them"
        );
        let all = [given("guard", ""), given("quiet", "yes")];
        assert!(checked(&prompts, true, &all, false).is_ok());
    }

    #[test]
    fn given_answers_are_judged_before_the_run() {
        let prompts = [prompt("quiet", PromptKind::Confirm, 6)];
        let e = checked(&prompts, true, &[given("quiet", "")], true)
            .unwrap_err()
            .to_string();
        assert!(e.contains("Enter alone does not confirm"), "{e}");
        let e = checked(&prompts, true, &[given("quite", "yes")], true)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no operator step is called `quite`; did you mean `quiet`?"),
            "{e}"
        );
        assert!(checked(&prompts, false, &[given("other", "x")], true).is_ok());
    }

    #[test]
    fn an_answer_that_names_another_unit_than_the_command_line_is_refused() {
        let prompts = [prompt(
            "serial",
            PromptKind::Text {
                pattern: None,
                sets: Some("serial"),
            },
            3,
        )];
        let unit = UnitIdentity {
            serial: Some("SP-104233".into()),
            ..UnitIdentity::default()
        };
        let e = answers_checked(&prompts, true, &[given("serial", "SP-000001")], false, &unit)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("the answer `SP-000001` to `serial` sets the unit's serial, but --unit serial=SP-104233 names another unit; nothing was sent"),
            "{e}"
        );
        assert!(answers_checked(&prompts, true, &[given("serial", " SP-104233 ")], false, &unit).is_ok());
        assert!(checked(&prompts, true, &[given("serial", "SP-000001")], false).is_ok());
    }
}
