//! A list of steps and one step: a device command (`- shutdown`) or one keyword with its
//! settings (and an optional `name`), handed to the file of that step kind; the states
//! steps name. Counts steps against the expansion limits. It must not read any step kind's
//! settings itself.

mod attempts;
mod coast_down;
mod expect;
mod expect_parameters;
mod go_to;
pub(in crate::recipe) mod last_pass;
mod predicate;
mod prompt;
mod ramp;
mod read_print;
mod repeat;
mod sample;
mod set;
mod statistic;
mod wait_until;
mod warn_band;

use super::{did_you_mean, show_duration, Loader};
use crate::diag::{Span, Spanned, YamlNode, YamlValue};
use crate::dictionary::Profile;
use crate::drive::device_control::{DeviceCommand, DeviceState};
use crate::recipe::step::{Step, StepKind};
use crate::session::StepOrigin;
pub(in crate::recipe) use coast_down::{
    DEFAULT_EVERY as COAST_DOWN_EVERY, DEFAULT_TIMEOUT as COAST_DOWN_TIMEOUT,
};
use std::time::Duration;

/// Every step keyword, for the loader's suggestions and the JSON Schema's list alike.
pub(in crate::recipe) const STEP_KEYS: &[&str] = &[
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
    "expect_parameters",
    "instruct",
    "confirm",
    "enter_value",
    "enter_text",
    "coast_down",
    "attempts",
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
                    // A bare command goes to every drive: each must have it.
                    let ok = self.on_every_drive(|l| {
                        if !l.has_profile(&node.span, &format!("`{word}`")) {
                            return false;
                        }
                        l.check_command(&node.span, cmd);
                        true
                    });
                    if !ok {
                        return None;
                    }
                    return Some(Step {
                        kind: StepKind::Command(cmd, None),
                        origin,
                        label: cmd.id().to_string(),
                        on_failure: None,
                        watches: Vec::new(),
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
                let is_step = |k: &str| STEP_KEYS.contains(&k) || DeviceCommand::from_id(k).is_some();
                let (step_keys, others): (Vec<&Spanned<String>>, Vec<&Spanned<String>>) =
                    keys.iter().partition(|k| is_step(&k.value));
                if let ([step_key], [other, ..]) = (step_keys.as_slice(), others.as_slice()) {
                    // `timeout:` under `wait_until:`, or an object under `set:`, written level
                    // with it: a second `- ` would break the step; indenting is the fix.
                    return self.refuse(
                        &other.span,
                        format!(
                            "`{}` is level with `{}:`, so it reads as a second keyword of this step",
                            other.value, step_key.value
                        ),
                        format!("belongs under `{}:`", step_key.value),
                        Some(format!(
                            "indent `{}:` two spaces further than `{}:`, so that it is part of it",
                            other.value, step_key.value
                        )),
                    );
                }
                let [key] = keys.as_slice() else {
                    return self.refuse(
                        &node.span,
                        format!(
                            "a step has one keyword (and optionally `name`), this one has {}",
                            keys.len()
                        ),
                        "one step per list item",
                        Some("start each step with its own `- `".into()),
                    );
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
        if let Some(cmd) = DeviceCommand::from_id(&key.value) {
            return self.command_on_drive(cmd, body, origin);
        }
        let on_failure = match key.value.as_str() {
            "repeat" | "attempts" | "include" => self.block_on_failure(body),
            _ => None,
        };
        let watches = match (key.value.as_str(), body.get("watch")) {
            ("repeat" | "attempts", Some(node)) => self.watch_section(node),
            _ => Vec::new(),
        };
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
            "expect_parameters" => self.expect_parameters(body)?,
            "coast_down" => self.coast_down(body, name.as_deref())?,
            "attempts" => self.attempts(body)?,
            "ramp" => self.ramp(body)?,
            "repeat" => self.repeat(body)?,
            "include" => self.include(body)?,
            word if prompt::PROMPT_KEYS.contains(&word) => self.prompt(word, body, name.as_deref())?,
            word if DeviceCommand::from_id(word).is_some() => {
                return self.refuse(
                    &key.span,
                    format!("`{word}` takes no settings; write it on its own: `- {word}`"),
                    "a plain command",
                    None,
                );
            }
            word => {
                self.unknown_step(&key.span, word);
                return None;
            }
        };
        let label = match (&kind, name) {
            (StepKind::Expect(_) | StepKind::ExpectParameters { .. } | StepKind::Ask(_), _) | (_, None) => {
                label
            }
            (_, Some(n)) => n,
        };
        Some(Step {
            kind,
            origin,
            label,
            on_failure,
            watches,
        })
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

    /// `- enable_operation: left`: a command to one named drive.
    fn command_on_drive(&mut self, cmd: DeviceCommand, body: &YamlNode, origin: StepOrigin) -> Option<Step> {
        let drive = self.r.scalar_text(body, "the drive to command")?;
        if !self.several_drives() {
            return self.refuse(
                &body.span,
                format!(
                    "`{}: {drive}` names a drive, but this recipe has no `drives:`",
                    cmd.id()
                ),
                "no such drive",
                Some(format!("write `- {}` for the recipe's one drive", cmd.id())),
            );
        }
        let ok = self.on_drive(&drive, &body.span, |l| {
            if !l.has_profile(&body.span, &format!("`{}`", cmd.id())) {
                return false;
            }
            l.check_command(&body.span, cmd);
            true
        })?;
        ok.then(|| Step {
            kind: StepKind::Command(cmd, Some(drive.clone())),
            origin,
            label: format!("{} {drive}", cmd.id()),
            on_failure: None,
            watches: Vec::new(),
        })
    }

    /// Device control (commands, states) needs the dictionary's profile; without one the
    /// step is refused here, before anything is sent, saying what to add.
    fn has_profile(&mut self, span: &Span, what: &str) -> bool {
        if self.dict.profile().is_some() {
            return true;
        }
        let dictionary = self.dict.name().to_string();
        self.problem(
            span,
            format!("{what} needs device control, but the {dictionary} dictionary has no `profile:`"),
            "no device-control profile",
            Some(
                "add a `profile:` to a dictionary file given with --dictionary FILE: which objects are the control_word and status_word, the control-word value of each command and the status-word mask and value of each state (the built-in dictionary's comments show a template)"
                    .into(),
            ),
        );
        false
    }

    /// A command the dictionary's profile leaves out (the drive has no such command) is
    /// refused before anything is sent.
    fn check_command(&mut self, span: &Span, command: DeviceCommand) {
        let lacks = format!("has no `{}` command", command.id());
        self.check_profile(span, &lacks, |p| {
            (!p.has_command(command)).then(|| format!("its commands are: {}", p.command_ids().join(", ")))
        });
    }

    /// A state the dictionary's profile leaves out can be neither reached nor waited for.
    fn check_state(&mut self, span: &Span, state: DeviceState) {
        let lacks = format!("does not show the state `{}`", state.id());
        self.check_profile(span, &lacks, |p| {
            (!p.has_state(state)).then(|| format!("its states are: {}", p.state_ids().join(", ")))
        });
    }

    /// Refuses what the dictionary's profile leaves out: `missing` gives the help (what the
    /// profile has instead) when the profile lacks it.
    fn check_profile(&mut self, span: &Span, lacks: &str, missing: impl Fn(&Profile) -> Option<String>) {
        let Some(help) = self.dict.profile().and_then(missing) else {
            return;
        };
        let dictionary = self.dict.name().to_string();
        self.problem(
            span,
            format!("the {dictionary} drive {lacks} (its profile leaves it out)"),
            "not on this drive",
            Some(help),
        );
    }

    /// A device state named by `node`, the value of `what`.
    fn state(&mut self, node: &YamlNode, what: &str) -> Option<DeviceState> {
        let text = self.text(node, what)?;
        match DeviceState::from_id(text.trim()) {
            Some(_) if !self.has_profile(&node.span, &format!("the state `{}`", text.trim())) => None,
            Some(s) => {
                self.check_state(&node.span, s);
                Some(s)
            }
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
