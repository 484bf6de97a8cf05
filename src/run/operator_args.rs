//! The command line's word on the unit under test and the operator's answers: `--unit
//! serial=…` (part, operator, station), `--answers FILE` (a YAML mapping `name: answer`)
//! and `--answer NAME=VALUE`, which wins over the file. Parses and loads; the answers are
//! judged by the prompts that ask them.

use super::{BadValue, RunError};
use crate::diag::{read_source, YamlNode, YamlValue};
use crate::session::{Given, Prompt, PromptKind, StepOrigin, UnitIdentity, UNIT_FIELDS};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Clone, Default, Args)]
#[command(next_help_heading = "Unit under test and operator")]
pub struct OperatorArgs {
    /// A part of the run's identity, PART=VALUE: serial, part, operator or station (e.g.
    /// serial=SP-104233); may be repeated. Shown in the console header, JUnit and HTML,
    /// and usable in output names (`--report "{serial}-{date}.html"`).
    #[arg(long = "unit", value_name = "PART=VALUE", value_parser = parse_unit_part)]
    pub unit: Vec<(String, String)>,
    /// Answers to the operator steps, a YAML file of `name: answer` lines (the name is the
    /// step's `name:`, or what `check` lists), so a run needs nobody at a terminal.
    #[arg(long, value_name = "FILE")]
    pub answers: Option<PathBuf>,
    /// The answer to the operator step called NAME (over --answers); may be repeated.
    #[arg(long = "answer", value_name = "NAME=VALUE", value_parser = parse_answer)]
    pub answer: Vec<(String, String)>,
}

fn parse_unit_part(text: &str) -> Result<(String, String), BadValue> {
    match text.split_once('=') {
        Some((k, v)) if UNIT_FIELDS.contains(&k.trim()) && !v.trim().is_empty() => {
            Ok((k.trim().to_string(), v.trim().to_string()))
        }
        Some((k, _)) if !UNIT_FIELDS.contains(&k.trim()) => Err(BadValue(format!(
            "`{}` is no part of the unit's identity; write one of {} as PART=VALUE, e.g. serial=SP-104233",
            k.trim(),
            UNIT_FIELDS.join(", ")
        ))),
        _ => Err(BadValue(format!(
            "`{text}`: write PART=VALUE, e.g. serial=SP-104233"
        ))),
    }
}

fn parse_answer(text: &str) -> Result<(String, String), BadValue> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(BadValue(format!("`{text}`: write NAME=VALUE, e.g. quiet=yes"))),
    }
}

impl OperatorArgs {
    /// The identity the command line gives.
    pub fn identity(&self) -> UnitIdentity {
        let mut unit = UnitIdentity::default();
        for (part, value) in &self.unit {
            if let Some(slot) = unit.field_mut(part) {
                *slot = Some(value.clone());
            }
        }
        unit
    }

    /// The identity the command line gives, with the parts `given` beforehand to the
    /// operator steps (`prompts`) that set them, where the command line left them open.
    pub fn identity_with_answers(
        &self,
        prompts: &[(Prompt, StepOrigin)],
        given: &[(String, Given)],
    ) -> UnitIdentity {
        let mut unit = self.identity();
        for (prompt, _) in prompts {
            let PromptKind::Text { sets: Some(part), .. } = &prompt.kind else {
                continue;
            };
            let answer = given.iter().find(|(name, _)| *name == prompt.name);
            if let (Some(slot), Some((_, answer))) = (unit.field_mut(part), answer) {
                if slot.is_none() {
                    *slot = prompt.judge(&answer.value).ok().map(|a| a.text);
                }
            }
        }
        unit
    }

    /// Every answer given, by name: `--answer` over the file's. A file that cannot be
    /// read or is no mapping of names to answers is an invalid command line.
    pub fn given(&self) -> Result<Vec<(String, Given)>, RunError> {
        let mut given = Vec::new();
        if let Some(path) = &self.answers {
            let source = read_source(path)
                .map_err(|e| RunError::Invalid(format!("error: {}", e.sentence("the answers file"))))?;
            let root = YamlNode::parse(&source).map_err(|e| {
                RunError::Invalid(crate::diag::render_diagnostic(&e.diagnostic(source.path(), None)))
            })?;
            let shown = path.display().to_string();
            let entries = match &root.value {
                YamlValue::Map(entries) => entries.as_slice(),
                _ if root.is_null() => &[],
                _ => {
                    return Err(RunError::Invalid(format!(
                        "error: {shown}: the answers file is a mapping of names to answers, e.g. `quiet: yes`"
                    )))
                }
            };
            for (name, value) in entries {
                let Some(text) = value.as_text() else {
                    return Err(RunError::Invalid(format!(
                        "error: {shown}:{}:{}: the answer to `{}` is {}, not a single value",
                        value.span.line(),
                        value.span.column(),
                        name.value,
                        value.kind()
                    )));
                };
                given.push((
                    name.value.clone(),
                    Given {
                        value: text,
                        source: shown.clone(),
                    },
                ));
            }
        }
        for (name, value) in &self.answer {
            given.retain(|(n, _)| n != name);
            given.push((
                name.clone(),
                Given {
                    value: value.clone(),
                    source: "--answer".into(),
                },
            ));
        }
        Ok(given)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_parts_are_checked_by_name() {
        assert_eq!(
            parse_unit_part("serial=SP-1").unwrap(),
            ("serial".into(), "SP-1".into())
        );
        let e = parse_unit_part("colour=red").unwrap_err().0;
        assert!(
            e.contains("`colour` is no part") && e.contains("serial, part, operator, station"),
            "{e}"
        );
        assert!(parse_unit_part("serial=").is_err());
    }

    #[test]
    fn command_line_answers_win_over_the_file() {
        let dir = crate::scratch_dir::scratch_dir("answers");
        let file = dir.join("answers.yaml");
        std::fs::write(&file, "quiet: no\nvibration: 1.2 mm/s\n").unwrap();
        let args = OperatorArgs {
            answers: Some(file.clone()),
            answer: vec![("quiet".into(), "yes".into())],
            ..Default::default()
        };
        let given = args.given().unwrap();
        let value = |n: &str| {
            given
                .iter()
                .find(|(k, _)| k == n)
                .map(|(_, g)| g.clone())
                .unwrap()
        };
        assert_eq!(value("quiet").value, "yes");
        assert_eq!(value("quiet").source, "--answer");
        assert_eq!(value("vibration").value, "1.2 mm/s");
        std::fs::write(&file, "- a\n").unwrap();
        assert!(args.given().is_err());
        let _ = std::fs::remove_dir_all(dir);
    }
}
