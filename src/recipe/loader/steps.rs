//! A list of steps and one step: a device command (`- shutdown`) or one keyword with its
//! settings (and an optional `name`), handed to the file of that step kind; the states
//! steps name. Counts steps against the expansion limits. It must not read any step kind's
//! settings itself.

mod expect;
mod go_to;
mod predicate;
mod ramp;
mod read_print;
mod repeat;
mod sample;
mod set;
mod wait_until;

use super::{did_you_mean, show_duration, Loader};
use crate::diag::{Span, Spanned, YamlNode, YamlValue};
use crate::drive::device_control::{DeviceCommand, DeviceState};
use crate::recipe::step::{Step, StepKind, StepOrigin};
use std::time::Duration;

const STEP_KEYS: &[&str] = &[
    "go_to",
    "set",
    "read",
    "print",
    "wait_until",
    "dwell",
    "sample",
    "expect",
    "ramp",
    "repeat",
    "include",
];

impl Loader<'_, '_> {
    /// The steps of a list given as the value of `what` (`steps`, `finally`); nothing is
    /// no steps.
    pub(super) fn steps(&mut self, node: &YamlNode, what: &str) -> Vec<Step> {
        if node.is_null() {
            return Vec::new();
        }
        let Some(items) = self.r.list(node, what, "a list of steps (lines starting `- `)") else {
            return Vec::new();
        };
        let mut steps = Vec::new();
        let mut longest = Duration::ZERO;
        for item in items {
            let Some(step) = self.step(item) else {
                continue;
            };
            longest = longest.saturating_add(step.longest_time());
            if let Err(over) = self.expansion.longest_time(longest) {
                self.over_limit(&item.span, over);
            }
            steps.push(step);
        }
        steps
    }

    fn step(&mut self, node: &YamlNode) -> Option<Step> {
        if self.expansion.is_over() {
            return None;
        }
        if let Err(over) = self.expansion.step() {
            self.over_limit(&node.span, over);
            return None;
        }
        let origin = self.origin(&node.span);
        match &node.value {
            YamlValue::Str(word) => {
                if let Some(cmd) = DeviceCommand::from_id(word) {
                    if !self.has_profile(&node.span, word) {
                        return None;
                    }
                    return Some(Step {
                        kind: StepKind::Command(cmd),
                        origin,
                        label: cmd.id().to_string(),
                    });
                }
                self.unknown_step(&node.span, word);
                None
            }
            YamlValue::Map(entries) => {
                let keys: Vec<&Spanned<String>> = entries
                    .iter()
                    .map(|(k, _)| k)
                    .filter(|k| k.value != "name")
                    .collect();
                let [key] = keys.as_slice() else {
                    self.problem(
                        &node.span,
                        format!(
                            "a step has one keyword (and optionally `name`), this one has {}",
                            keys.len()
                        ),
                        "one step per list item",
                        Some("start each step with its own `- `".into()),
                    );
                    return None;
                };
                let body = node.get(&key.value)?;
                let name = node
                    .get("name")
                    .and_then(|n| self.r.scalar_text(n, "the step's `name`"));
                self.keyed_step(key, body, name, origin)
            }
            _ => {
                let kind = node.kind();
                self.problem(&node.span, format!("a step is a command such as `shutdown` or a mapping such as `set: {{...}}`, this is {kind}"), "not a step", None);
                None
            }
        }
    }

    fn keyed_step(
        &mut self,
        key: &Spanned<String>,
        body: &YamlNode,
        name: Option<String>,
        origin: StepOrigin,
    ) -> Option<Step> {
        let (kind, label) = match key.value.as_str() {
            "go_to" => self.go_to(body)?,
            "set" => self.set(body)?,
            "read" => self.read(body)?,
            "print" => self.print(body)?,
            "wait_until" => self.wait_until(body)?,
            "dwell" => {
                let d = self.duration(body, "dwell")?;
                (StepKind::Dwell(d), format!("dwell {}", show_duration(d)))
            }
            "sample" => self.sample(body)?,
            "expect" => self.expect(body, name.as_deref())?,
            "ramp" => self.ramp(body)?,
            "repeat" => self.repeat(body)?,
            "include" => self.include(body)?,
            word if DeviceCommand::from_id(word).is_some() => {
                self.problem(
                    &key.span,
                    format!("`{word}` takes no settings; write it on its own: `- {word}`"),
                    "a plain command",
                    None,
                );
                return None;
            }
            word => {
                self.unknown_step(&key.span, word);
                return None;
            }
        };
        let label = match (&kind, name) {
            (StepKind::Expect(_), _) | (_, None) => label,
            (_, Some(n)) => n,
        };
        Some(Step { kind, origin, label })
    }

    /// A word (`- frob`) or keyword (`- frob: …`) that is no step, with the closest one.
    fn unknown_step(&mut self, span: &Span, word: &str) {
        let commands: Vec<&str> = DeviceCommand::ALL.iter().map(|c| c.id()).collect();
        let help = did_you_mean(word, commands.iter().copied().chain(STEP_KEYS.iter().copied()))
            .map(|s| format!("did you mean `{s}`?"))
            .unwrap_or_else(|| {
                format!(
                    "a step is a device command ({}) or one of: {}",
                    commands.join(", "),
                    STEP_KEYS.join(", ")
                )
            });
        self.problem(span, format!("unknown step `{word}`"), "unknown step", Some(help));
    }

    /// Device commands and states need the dictionary's device-control profile; without
    /// one the step is refused here rather than failing after the run started.
    fn has_profile(&mut self, span: &Span, what: &str) -> bool {
        if self.dict.profile().is_some() {
            return true;
        }
        self.problem(
            span,
            format!(
                "`{what}` needs device control, and the {} dictionary has no device-control profile",
                self.dict.family()
            ),
            "no device control",
            Some("read, set, wait for and sample objects instead; device commands and states exist only where the dictionary maps them".into()),
        );
        false
    }

    /// A device state named by `node`, the value of `what`.
    fn state(&mut self, node: &YamlNode, what: &str) -> Option<DeviceState> {
        let text = self.text(node, what)?;
        if !self.has_profile(&node.span, text.trim()) {
            return None;
        }
        match DeviceState::from_id(text.trim()) {
            Some(s) => Some(s),
            None => {
                let ids: Vec<&str> = DeviceState::ALL.iter().map(|s| s.id()).collect();
                let help = did_you_mean(&text, ids.iter().copied())
                    .map(|s| format!("did you mean `{s}`?"))
                    .unwrap_or_else(|| format!("states: {}", ids.join(", ")));
                self.problem(
                    &node.span,
                    format!("unknown state `{text}`"),
                    "unknown state",
                    Some(help),
                );
                None
            }
        }
    }
}
