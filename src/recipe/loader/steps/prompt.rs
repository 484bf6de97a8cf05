//! The operator steps: `instruct` (read and acknowledge), `confirm` (a yes/no question
//! that is a check), `enter_value` (a measured value with its unit and limits) and
//! `enter_text` (a text with an optional pattern, which may set a part of the unit's
//! identity). Each is the question alone or a mapping with `prompt:` and its settings
//! (a value's `compared_with_last_pass` too); units, limits and patterns are checked here,
//! at their place. It must not ask anyone.

use super::last_pass::{Measured, KEY};
use crate::diag::{Shape, Spanned, YamlNode, YamlValue};
use crate::dictionary::{Quantity, Unit};
use crate::recipe::loader::{did_you_mean, Loader};
use crate::recipe::step::{Step, StepKind};
use crate::session::{default_answer_name, Limits, Pattern, Prompt, PromptKind, UNIT_FIELDS};
use std::time::Duration;

/// The operator step keywords.
pub(in crate::recipe) const PROMPT_KEYS: [&str; 4] = ["instruct", "confirm", "enter_value", "enter_text"];

impl Loader<'_, '_> {
    /// The operator step `word` with its `body`; `name` (the step's) names its answer.
    pub(in crate::recipe::loader) fn prompt(
        &mut self,
        word: &str,
        body: &YamlNode,
        name: Option<&str>,
    ) -> Option<(StepKind, String)> {
        let (keys, example): (&[&str], &str) = match word {
            "enter_value" => (
                &["prompt", "timeout", "unit", "at_least", "at_most", "between", KEY],
                "enter_value: { prompt: Vibration on the hand-held meter, unit: mm/s, at_most: 2.8 mm/s }",
            ),
            "enter_text" => (
                &["prompt", "timeout", "pattern", "sets"],
                "enter_text: { prompt: Scan the spindle's serial number, pattern: 'SP-[0-9]{6}', sets: serial }",
            ),
            _ => (&["prompt", "timeout"], "confirm: { prompt: Is the spindle running quietly?, timeout: 5 min }"),
        };
        let (text, f) = match &body.value {
            YamlValue::Map(_) => {
                let what = format!("this {word}");
                let shape = Shape::new(&what, keys).require(&["prompt"]).example(example);
                let f = self.r.fields(body, &shape)?;
                (self.text(f.get("prompt")?, "`prompt`")?, Some(f))
            }
            _ => (self.text(body, &format!("`{word}`"))?, None),
        };
        if text.trim().is_empty() {
            return self.refuse(
                &body.span,
                format!("{word} needs a question or instruction"),
                "empty",
                None,
            );
        }
        let get = |key: &str| f.as_ref().and_then(|f| f.get(key));
        let timeout = match get("timeout") {
            Some(n) => Some(self.duration(n, "timeout")?),
            None => None,
        };
        let kind = match word {
            "instruct" => PromptKind::Instruction,
            "confirm" => PromptKind::Confirm,
            "enter_value" => {
                let compared = f
                    .as_ref()
                    .and_then(|f| f.entries().iter().find(|(k, _)| k.value == KEY));
                self.value_prompt(
                    get("unit"),
                    [get("at_least"), get("at_most"), get("between")],
                    compared,
                )?
            }
            _ => self.text_prompt(get("pattern"), get("sets"))?,
        };
        let sets = match &kind {
            PromptKind::Text { sets, .. } => *sets,
            _ => None,
        };
        let prompt = Prompt {
            name: name.map_or_else(|| default_answer_name(&text, sets), str::to_string),
            text,
            kind,
            timeout: timeout.filter(|t: &Duration| !t.is_zero()),
        };
        let label = prompt.to_string();
        Some((StepKind::Ask(prompt), label))
    }

    /// `unit`, the limits (`at_least`, `at_most`, `between`) and `compared_with_last_pass`
    /// of an `enter_value`.
    fn value_prompt(
        &mut self,
        unit: Option<&YamlNode>,
        [at_least, at_most, between]: [Option<&YamlNode>; 3],
        compared: Option<&(Spanned<String>, YamlNode)>,
    ) -> Option<PromptKind> {
        let unit = match unit {
            Some(n) => {
                let t = self.text(n, "`unit`")?;
                match Unit::parse_measured(&t) {
                    Ok(u) => Some(u),
                    Err(e) => return self.refuse(&n.span, e.to_string(), "unknown unit", None),
                }
            }
            None => None,
        };
        let mut low = match at_least {
            Some(n) => Some(self.limit_in(n, unit, "at_least")?),
            None => None,
        };
        let mut high = match at_most {
            Some(n) => Some(self.limit_in(n, unit, "at_most")?),
            None => None,
        };
        if let Some(n) = between {
            const EXAMPLE: &str = "[1 mm/s, 2.8 mm/s]";
            let (lo, hi) = self.between_ends(n, EXAMPLE, |_| {
                format!("between takes two values: `between: {EXAMPLE}`")
            })?;
            low = Some(self.limit_in(lo, unit, "between")?);
            high = Some(self.limit_in(hi, unit, "between")?);
        }
        if let (Some(lo), Some(hi)) = (low, high) {
            if lo > hi {
                let span = between.or(at_least).map(|n| n.span.clone())?;
                return self.refuse(
                    &span,
                    format!("the lower limit {lo} is above the upper limit {hi}"),
                    "no value fits",
                    None,
                );
            }
        }
        let last_pass = match compared {
            Some((key, node)) => Some(self.last_pass(&Measured::Typed(unit), key, node)?),
            None => None,
        };
        Some(PromptKind::Value {
            unit,
            limits: Limits::new(low, high),
            last_pass,
        })
    }

    /// A limit of a typed value, in the prompt's unit (a bare number is in it already).
    pub(in crate::recipe::loader) fn limit_in(
        &mut self,
        node: &YamlNode,
        unit: Option<Unit>,
        what: &str,
    ) -> Option<f64> {
        let text = self.text(node, &format!("`{what}`"))?;
        let q = match Quantity::parse_measured(&text) {
            Ok(q) => q,
            Err(e) => return self.refuse(&node.span, format!("{what}: {e}"), "not a value", None),
        };
        match (q.unit, unit) {
            (None, _) => Some(q.value),
            (Some(from), Some(to)) => match from.convert(q.value, to) {
                Some(v) => Some(v),
                None => self.refuse(
                    &node.span,
                    format!("{what}: {from} is not a unit of {} ({to})", to.dimension().name()),
                    "wrong unit",
                    None,
                ),
            },
            (Some(from), None) => self.refuse(
                &node.span,
                format!("{what}: `{text}` has a unit but the value has none"),
                "which unit?",
                Some(format!("give the value's unit: `unit: {from}`")),
            ),
        }
    }

    fn text_prompt(&mut self, pattern: Option<&YamlNode>, sets: Option<&YamlNode>) -> Option<PromptKind> {
        // Both are checked, so a file with two problems hears of both at once.
        let pattern = self.pattern(pattern);
        let sets = self.sets(sets);
        Some(PromptKind::Text {
            pattern: pattern?,
            sets: sets?,
        })
    }

    /// `pattern:`, compiled; `Some(None)` when there is none.
    fn pattern(&mut self, pattern: Option<&YamlNode>) -> Option<Option<Pattern>> {
        let Some(n) = pattern else { return Some(None) };
        let t = self.r.scalar_text(n, "`pattern`")?;
        match Pattern::new(&t) {
            Ok(p) => Some(Some(p)),
            Err(e) => {
                let text = e.to_string();
                let why = text.lines().last().unwrap_or_default().trim();
                let why = why.strip_prefix("error: ").unwrap_or(why).to_string();
                self.refuse(
                    &n.span,
                    format!("`{t}` is not a pattern (a regular expression): {why}"),
                    "not a pattern",
                    Some("e.g. `SP-[0-9]{6}`: SP- and six digits; the answer must match in full".into()),
                )
            }
        }
    }

    /// `sets:`, a part of the unit's identity; `Some(None)` when there is none.
    fn sets(&mut self, sets: Option<&YamlNode>) -> Option<Option<&'static str>> {
        let Some(n) = sets else { return Some(None) };
        let t = self.text(n, "`sets`")?;
        match UNIT_FIELDS.into_iter().find(|f| *f == t.trim()) {
            Some(f) => Some(Some(f)),
            None => {
                let help = match did_you_mean(t.trim(), UNIT_FIELDS.into_iter()) {
                    Some(s) => format!("did you mean `{s}`?"),
                    None => format!("one of: {}", UNIT_FIELDS.join(", ")),
                };
                self.refuse(
                    &n.span,
                    format!("`sets: {t}` names no part of the unit's identity"),
                    "unknown part",
                    Some(help),
                )
            }
        }
    }

    /// The safe stop (`finally`, `on_fault`) must never wait for a person: an operator
    /// step in it (nested ones too) is refused, at the list and naming the step's place.
    pub(in crate::recipe::loader) fn no_operator_steps(
        &mut self,
        steps: &[Step],
        list: &YamlNode,
        key: &str,
    ) {
        for step in steps {
            match &step.kind {
                StepKind::Ask(p) => self.problem(
                    &list.span,
                    format!(
                        "`{p}` at {} asks the operator in `{key}`, but the safe stop must never wait for a person",
                        step.origin
                    ),
                    "no operator steps here",
                    Some("ask before the end of `steps:`; `finally` and `on_fault` run unattended".into()),
                ),
                _ => self.no_operator_steps(step.nested(), list, key),
            }
        }
    }
}
