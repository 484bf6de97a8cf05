//! An operator step as the session asks it: an instruction to acknowledge, a yes/no
//! question that is a check, a measured value typed in with its unit and limits, or a text
//! answer with an optional pattern that may name a part of the unit's identity; and the
//! rules that judge one typed line (accepted, or asked again saying why). Plain data and
//! pure rules: no terminal, no waiting.

use crate::dictionary::{Quantity, Unit};
use crate::session::{number, with_unit};
use regex::Regex;
use std::fmt;
use std::time::Duration;

/// One question to the operator.
#[derive(Debug, Clone, PartialEq)]
pub struct Prompt {
    /// The answer's name, for `--answer NAME=VALUE` and the answers file.
    pub name: String,
    /// What the operator reads: `Fit the balancing adapter and close the guard`.
    pub text: String,
    pub kind: PromptKind,
    /// Nobody answering within this fails the step (and stops the run).
    pub timeout: Option<Duration>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum PromptKind {
    /// Read and acknowledged with Enter.
    Instruction,
    /// Yes or no; "no" fails the check. Enter alone is no answer.
    Confirm,
    /// A number in `unit` (a bare number is taken in it), checked against the limits
    /// (inclusive; either may be open), and compared with the same answer in the unit's
    /// last passed run when `last_pass` says how far it may move.
    Value {
        unit: Option<Unit>,
        limits: super::Limits,
        last_pass: Option<super::LastPass>,
    },
    /// Any non-empty text, or one matching `pattern` in full; `sets` names the part of
    /// the unit's identity it gives (`serial`).
    Text {
        pattern: Option<Pattern>,
        sets: Option<&'static str>,
    },
}

/// A regular expression as the recipe wrote it; it must match the whole answer.
#[derive(Debug, Clone)]
pub struct Pattern {
    source: String,
    regex: Regex,
}

impl PartialEq for Pattern {
    fn eq(&self, other: &Self) -> bool {
        self.source == other.source
    }
}

impl Pattern {
    /// The pattern `source`, anchored at both ends; the regex crate's error otherwise.
    pub fn new(source: &str) -> Result<Pattern, regex::Error> {
        let regex = Regex::new(&format!("^(?:{source})$"))?;
        Ok(Pattern {
            source: source.to_string(),
            regex,
        })
    }

    pub fn source(&self) -> &str {
        &self.source
    }
}

/// A typed line that is no answer: why, said before asking again.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct NotAnAnswer(pub String);

/// A line the prompt accepted.
#[derive(Debug, Clone, PartialEq)]
pub struct Accepted {
    /// The answer as reports show it: `yes`, `1.2 mm/s`, `SP-104233`, `acknowledged`.
    pub text: String,
    /// A value's number in the prompt's unit.
    pub number: Option<f64>,
    /// False for "no" and for a value outside its limits.
    pub passed: bool,
}

impl Prompt {
    /// What the operator may type, after the question: `[yes/no]`, `[mm/s, at most 2.8]`.
    pub fn hint(&self) -> String {
        match &self.kind {
            PromptKind::Instruction => "[Enter when done]".into(),
            PromptKind::Confirm => "[yes/no]".into(),
            PromptKind::Value { unit, .. } => {
                let unit = unit
                    .map(|u| format!("in {u}"))
                    .unwrap_or_else(|| "a number".into());
                match self.limits_text() {
                    Some(limits) => format!("[{unit}, {limits}]"),
                    None => format!("[{unit}]"),
                }
            }
            PromptKind::Text { pattern: Some(p), .. } => format!("[text matching {}]", p.source()),
            PromptKind::Text { pattern: None, .. } => "[text]".into(),
        }
    }

    /// Whether an answer to it is the unit's `part` (`serial`, `part`, …).
    pub fn sets(&self, part: &str) -> bool {
        matches!(&self.kind, PromptKind::Text { sets: Some(p), .. } if *p == part)
    }

    /// `at most 2.8 mm/s`, `between 1 and 2 mm`; `None` without limits.
    pub fn limits_text(&self) -> Option<String> {
        let PromptKind::Value { unit, limits, .. } = &self.kind else {
            return None;
        };
        let u = unit.map(|u| u.symbol());
        match (&limits.low, &limits.high) {
            (Some(lo), Some(hi)) => Some(format!("between {} and {}", number(*lo), with_unit(*hi, u))),
            (Some(lo), None) => Some(format!("at least {}", with_unit(*lo, u))),
            (None, Some(hi)) => Some(format!("at most {}", with_unit(*hi, u))),
            (None, None) => None,
        }
    }

    /// Whether an answer is a check (pass or fail) rather than a fact.
    pub fn is_check(&self) -> bool {
        matches!(self.kind, PromptKind::Confirm | PromptKind::Value { .. })
    }

    /// Judges one typed line: accepted (a "no" and a value outside its limits too: they
    /// fail the check), or no answer at all (a typo, Enter alone for a yes/no, a text
    /// not matching its pattern), to be asked again.
    pub fn judge(&self, line: &str) -> Result<Accepted, NotAnAnswer> {
        let t = line.trim();
        match &self.kind {
            PromptKind::Instruction => Ok(Accepted {
                text: "acknowledged".into(),
                number: None,
                passed: true,
            }),
            PromptKind::Confirm => match t.to_ascii_lowercase().as_str() {
                "y" | "yes" => Ok(Accepted {
                    text: "yes".into(),
                    number: None,
                    passed: true,
                }),
                "n" | "no" => Ok(Accepted {
                    text: "no".into(),
                    number: None,
                    passed: false,
                }),
                "" => Err(NotAnAnswer(
                    "answer yes or no: Enter alone does not confirm".into(),
                )),
                _ => Err(NotAnAnswer(format!("`{t}` is neither yes nor no"))),
            },
            PromptKind::Value { unit, limits, .. } => {
                let v = value_in(t, *unit)?;
                let passed = limits.low.is_none_or(|lo| v >= lo) && limits.high.is_none_or(|hi| v <= hi);
                Ok(Accepted {
                    text: with_unit(v, unit.map(|u| u.symbol())),
                    number: Some(v),
                    passed,
                })
            }
            PromptKind::Text { pattern, .. } => {
                if t.is_empty() {
                    return Err(NotAnAnswer("type the answer (Enter alone is none)".into()));
                }
                if let Some(p) = pattern {
                    if !p.regex.is_match(t) {
                        return Err(NotAnAnswer(format!(
                            "`{t}` does not match the pattern {}",
                            p.source()
                        )));
                    }
                }
                Ok(Accepted {
                    text: t.to_string(),
                    number: None,
                    passed: true,
                })
            }
        }
    }
}

/// `t` as a number in `unit` (a bare number is in it already).
fn value_in(t: &str, unit: Option<Unit>) -> Result<f64, NotAnAnswer> {
    if t.is_empty() {
        return Err(NotAnAnswer("type the value (Enter alone is none)".into()));
    }
    let q = Quantity::parse_measured(t).map_err(|e| NotAnAnswer(e.to_string()))?;
    match (q.unit, unit) {
        (None, _) => Ok(q.value),
        (Some(from), Some(to)) => from.convert(q.value, to).ok_or_else(|| {
            NotAnAnswer(format!(
                "{from} is not a unit of {}; type the value in {to}",
                to.dimension().name()
            ))
        }),
        (Some(from), None) => Err(NotAnAnswer(format!(
            "this value has no unit; type a plain number, not {from}"
        ))),
    }
}

impl fmt::Display for Prompt {
    /// `confirm "Is the spindle running quietly?"`: the step's label.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let word = match self.kind {
            PromptKind::Instruction => "instruct",
            PromptKind::Confirm => "confirm",
            PromptKind::Value { .. } => "enter_value",
            PromptKind::Text { .. } => "enter_text",
        };
        write!(f, "{word} \"{}\"", self.text)
    }
}

/// The answer name a prompt gets when none is given: the part it sets, else its text in
/// lower case with `_` between words (`Is the guard closed?` → `is_the_guard_closed`).
pub fn default_answer_name(text: &str, sets: Option<&str>) -> String {
    if let Some(part) = sets {
        return part.to_string();
    }
    let words: Vec<String> = text
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .take(8)
        .map(str::to_lowercase)
        .collect();
    if words.is_empty() {
        "answer".into()
    } else {
        words.join("_")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prompt(kind: PromptKind) -> Prompt {
        Prompt {
            name: "q".into(),
            text: "Q".into(),
            kind,
            timeout: None,
        }
    }

    #[test]
    fn a_yes_no_needs_an_explicit_answer() {
        let p = prompt(PromptKind::Confirm);
        assert!(p.judge("").is_err(), "Enter alone must not confirm");
        assert!(p.judge("  ").is_err());
        assert!(p.judge("maybe").is_err());
        assert!(p.judge("YES").unwrap().passed);
        assert!(!p.judge("n").unwrap().passed);
    }

    #[test]
    fn a_value_is_parsed_with_the_unit_rules_and_judged_against_its_limits() {
        let p = prompt(PromptKind::Value {
            unit: Some(Unit::MillimetrePerSecond),
            limits: crate::session::Limits::new(None, Some(2.8)),
            last_pass: None,
        });
        assert_eq!(p.hint(), "[in mm/s, at most 2.8 mm/s]");
        let ok = p.judge("1.2 mm/s").unwrap();
        assert!(ok.passed);
        assert_eq!(ok.number, Some(1.2));
        assert_eq!(ok.text, "1.2 mm/s");
        assert!(
            p.judge("1.2").unwrap().passed,
            "a bare number is in the prompt's unit"
        );
        assert!(
            !p.judge("3.1 mm/s").unwrap().passed,
            "outside the limits fails, not asked again"
        );
        let typo = p.judge("1,2").unwrap_err().0;
        assert!(typo.contains("`1,2` is not a number"), "{typo}");
        let wrong = p.judge("1.2 rpm").unwrap_err().0;
        assert!(wrong.contains("rpm is not a unit of velocity"), "{wrong}");
    }

    #[test]
    fn a_text_matches_its_pattern_in_full() {
        let p = prompt(PromptKind::Text {
            pattern: Some(Pattern::new(r"SP-\d{6}").unwrap()),
            sets: Some("serial"),
        });
        assert_eq!(p.judge(" SP-104233 ").unwrap().text, "SP-104233");
        assert!(p.judge("SP-1042").is_err());
        assert!(p.judge("xSP-104233").is_err(), "anchored at both ends");
        assert!(p.judge("").is_err());
    }

    #[test]
    fn default_names_come_from_the_part_or_the_text() {
        assert_eq!(default_answer_name("Scan it", Some("serial")), "serial");
        assert_eq!(
            default_answer_name("Is the spindle running quietly?", None),
            "is_the_spindle_running_quietly"
        );
        assert_eq!(default_answer_name("???", None), "answer");
    }
}
