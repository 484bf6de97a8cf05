//! Recipe YAML → a validated [`Recipe`]: walks the spanned YAML tree, resolves objects in
//! the dictionary, converts values to the objects' units, checks limits, durations,
//! states, parameters and included files, and collects EVERY problem with its place
//! instead of stopping at the first. Never talks to a drive.

use super::expansion::{Expansion, OverLimit};
use super::problem::{Problem, RecipeInvalid, RecipeSource};
use super::recipe::{Param, Recipe, SafeStopChoice};
use super::step::{ObjectRef, SetValue, Step, StepKind, StepOrigin};
use crate::diag::read_text_file;
use crate::dictionary::{DataType, Dictionary, Dimension, ObjectDef, Quantity};
use crate::drive::device_control::{DeviceCommand, DeviceState};
use crate::session::{Check, Condition, Predicate, Statistic, Tolerance};
use crate::yaml_tree::{self, Span, Spanned, YamlNode};
use std::collections::{BTreeMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

/// Default `timeout` of `wait_until` and of each `go_to` transition.
pub const DEFAULT_WAIT_TIMEOUT: Duration = Duration::from_secs(10);
pub const DEFAULT_GO_TO_TIMEOUT: Duration = Duration::from_secs(5);
/// Default poll interval of `wait_until`.
pub const DEFAULT_POLL: Duration = Duration::from_millis(100);
/// Default interval of `ramp`.
pub const DEFAULT_RAMP_EVERY: Duration = Duration::from_millis(100);
/// Nested includes beyond this are a mistake (or a cycle the path check missed).
const MAX_INCLUDE_DEPTH: usize = 8;
/// A ramp of more points than this is almost certainly a typo in its step.
const MAX_RAMP_POINTS: usize = 100_000;
/// The longest duration a recipe may give (dwell, timeout, `every`, `for`). Run-ins last
/// hours or days, not years; anything longer is a typo in the number or the unit, and the
/// cap keeps every sum of durations the run makes far from overflowing.
pub const MAX_DURATION: Duration = Duration::from_secs(1000 * 24 * 3600);
/// Most samples one `sample` step may take (`for` / `every` + 1). Each is kept in memory
/// for the statistics and the plots (16 bytes per object), and the runner counts them in
/// a `u32`; a million is 28 h at 100 ms.
pub const MAX_SAMPLES: u64 = 1_000_000;

const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "drive",
    "params",
    "steps",
    "finally",
    "on_fault",
    "leave_enabled",
    "safe_stop",
];
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

/// Loads and validates a recipe file. `overrides` are `--set name=value` pairs.
pub fn load_recipe(
    path: &Path,
    dictionary: &Dictionary,
    overrides: &[(String, String)],
) -> Result<Recipe, RecipeInvalid> {
    let shown = path.display().to_string();
    let text = match read_text_file(path) {
        Ok(t) => t,
        Err(e) => {
            let source = RecipeSource {
                path: shown.clone(),
                text: Arc::from(""),
            };
            let help = e.help().unwrap_or_else(|| {
                "check the path; recipes are YAML files such as recipes/commissioning.yaml".into()
            });
            return Err(RecipeInvalid {
                path: shown.clone(),
                problems: vec![Problem::new(
                    &source,
                    Span::default(),
                    e.sentence(&format!("the recipe {shown}")),
                    "",
                    Some(help),
                )],
            });
        }
    };
    load_recipe_text(
        &shown,
        &text,
        path.parent().unwrap_or(Path::new(".")),
        dictionary,
        overrides,
    )
}

/// Validates recipe text; `base_dir` resolves `include` paths.
pub fn load_recipe_text(
    path: &str,
    text: &str,
    base_dir: &Path,
    dictionary: &Dictionary,
    overrides: &[(String, String)],
) -> Result<Recipe, RecipeInvalid> {
    let mut problems = Vec::new();
    let mut expansion = Expansion::default();
    let source = Arc::new(RecipeSource {
        path: path.to_string(),
        text: Arc::from(text),
    });
    let recipe = {
        let mut loader = Loader {
            dict: dictionary,
            source: source.clone(),
            problems: &mut problems,
            expansion: &mut expansion,
            params: BTreeMap::new(),
            sampled: HashSet::new(),
            base_dir: base_dir.to_path_buf(),
            include_chain: vec![canonical(&base_dir.join(file_name(path)))],
        };
        loader.recipe(text, overrides)
    };
    match recipe {
        Some(r) if problems.is_empty() => Ok(r),
        _ => Err(RecipeInvalid {
            path: path.to_string(),
            problems,
        }),
    }
}

fn file_name(path: &str) -> PathBuf {
    Path::new(path).file_name().map(PathBuf::from).unwrap_or_default()
}

fn canonical(p: &Path) -> PathBuf {
    std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf())
}

struct ParamValue {
    text: String,
    origin: String,
}

struct Loader<'a, 'p> {
    dict: &'a Dictionary,
    source: Arc<RecipeSource>,
    problems: &'p mut Vec<Problem>,
    /// Included files and steps so far, over every level of includes.
    expansion: &'p mut Expansion,
    params: BTreeMap<String, ParamValue>,
    /// Objects sampled so far in file order, for `expect` on statistics.
    sampled: HashSet<String>,
    base_dir: PathBuf,
    include_chain: Vec<PathBuf>,
}

type Entries = Vec<(Spanned<String>, Spanned<YamlNode>)>;

impl Loader<'_, '_> {
    fn problem(
        &mut self,
        span: Span,
        message: impl Into<String>,
        label: impl Into<String>,
        help: Option<String>,
    ) {
        self.problems
            .push(Problem::new(&self.source, span, message, label, help));
    }

    fn over_limit(&mut self, span: Span, over: OverLimit) {
        self.problem(span, over.message, over.label, Some(over.help));
    }

    fn origin(&self, span: Span) -> StepOrigin {
        StepOrigin {
            path: self.source.path.clone(),
            line: span.line,
            column: span.column,
        }
    }

    fn recipe(&mut self, text: &str, overrides: &[(String, String)]) -> Option<Recipe> {
        let root = match yaml_tree::parse(text) {
            Ok(r) => r,
            Err(e) if e.over_limit => {
                self.problem(e.span, e.message, "here", e.help);
                return None;
            }
            Err(e) => {
                self.problem(
                    e.span,
                    format!("not valid YAML: {}", e.message),
                    "here",
                    Some(yaml_help()),
                );
                return None;
            }
        };
        let YamlNode::Map(entries) = &root.value else {
            self.problem(
                root.span,
                format!(
                    "a recipe is a mapping with `name` and `steps`, this is {}",
                    root.value.kind()
                ),
                "expected `name: ...` and `steps: ...`",
                None,
            );
            return None;
        };
        self.check_keys(entries, TOP_KEYS, &["name", "steps"], root.span, "recipe");
        let name = self
            .get(entries, "name")
            .and_then(|n| self.plain_text(n))
            .unwrap_or_default();
        let description = self.get(entries, "description").and_then(|n| self.plain_text(n));
        let drive = match self.get(entries, "drive") {
            Some(n) => self.drive_family(n),
            None => self.dict.family().to_string(),
        };
        let leave_enabled = match self.get(entries, "leave_enabled") {
            Some(n) => match n.value {
                YamlNode::Bool(b) => b,
                _ => {
                    self.problem(n.span, "leave_enabled is true or false", "not true/false", None);
                    false
                }
            },
            None => false,
        };
        let safe_stop = self
            .get(entries, "safe_stop")
            .map(|n| self.safe_stop(n))
            .unwrap_or_default();
        let params = self.params_section(self.get(entries, "params"), overrides);
        let steps = match self.get(entries, "steps") {
            Some(n) => self.steps(n),
            None => Vec::new(),
        };
        let finally = self.get(entries, "finally").map(|n| self.steps(n));
        let on_fault = self
            .get(entries, "on_fault")
            .map(|n| self.steps(n))
            .unwrap_or_default();
        Some(Recipe {
            name,
            description,
            drive,
            path: self.source.path.clone(),
            params,
            steps,
            finally,
            on_fault,
            leave_enabled,
            safe_stop,
        })
    }

    /// `safe_stop: { timeout: 2 min, standstill: 20 rpm }`.
    fn safe_stop(&mut self, node: &Spanned<YamlNode>) -> SafeStopChoice {
        let mut choice = SafeStopChoice::default();
        let Some(entries) = self.map(
            node,
            "safe_stop",
            "safe_stop: { timeout: 2 min, standstill: 20 rpm }",
        ) else {
            return choice;
        };
        self.check_keys(entries, &["timeout", "standstill"], &[], node.span, "safe_stop");
        if let Some(n) = self.get(entries, "timeout") {
            choice.timeout = self.duration(n, "safe_stop timeout");
        }
        if let Some(n) = self.get(entries, "standstill") {
            let text = self.text(n).unwrap_or_default();
            match Quantity::parse(&text) {
                Ok(q) if q.unit.is_some_and(|u| u.dimension() == Dimension::Speed) && q.value >= 0.0 => {
                    choice.standstill = Some(q)
                }
                _ => self.problem(
                    n.span,
                    format!("safe_stop standstill: `{}` is not a speed", text.trim()),
                    "expected a speed",
                    Some("write a speed of 0 or more with its unit, e.g. `10 rpm`".to_string()),
                ),
            }
        }
        choice
    }

    fn get<'n>(&self, entries: &'n Entries, key: &str) -> Option<&'n Spanned<YamlNode>> {
        entries.iter().find(|(k, _)| k.value == key).map(|(_, v)| v)
    }

    /// Reports unknown keys (with did-you-mean), duplicates, and missing required keys.
    fn check_keys(&mut self, entries: &Entries, allowed: &[&str], required: &[&str], at: Span, what: &str) {
        let mut seen = HashSet::new();
        for (k, _) in entries {
            if !seen.insert(k.value.as_str()) {
                self.problem(
                    k.span,
                    format!("`{}` is given twice in this {what}", k.value),
                    "again here",
                    None,
                );
            }
            if !allowed.contains(&k.value.as_str()) {
                let help = did_you_mean(&k.value, allowed.iter().copied())
                    .map(|s| format!("did you mean `{s}`?"))
                    .or_else(|| Some(format!("a {what} takes: {}", allowed.join(", "))));
                self.problem(
                    k.span,
                    format!("unknown key `{}` in this {what}", k.value),
                    "unknown key",
                    help,
                );
            }
        }
        for r in required {
            if !entries.iter().any(|(k, _)| k.value == *r) {
                self.problem(
                    at,
                    format!("this {what} has no `{r}`"),
                    format!("`{r}` missing"),
                    None,
                );
            }
        }
    }

    fn drive_family(&mut self, node: &Spanned<YamlNode>) -> String {
        let family = self.plain_text(node).unwrap_or_default();
        if family != self.dict.family() {
            self.problem(
                node.span,
                format!(
                    "this recipe is for drive `{family}`, the dictionary in use is `{}`",
                    self.dict.family()
                ),
                "other drive family",
                Some(format!("drive families available: {}", self.dict.family())),
            );
        }
        family
    }

    fn params_section(
        &mut self,
        node: Option<&Spanned<YamlNode>>,
        overrides: &[(String, String)],
    ) -> Vec<Param> {
        let mut out = Vec::new();
        if let Some(node) = node {
            match &node.value {
                YamlNode::Map(entries) => {
                    for (k, v) in entries {
                        if !is_identifier(&k.value) {
                            self.problem(
                                k.span,
                                format!("`{}` is not a parameter name", k.value),
                                "use letters, digits and _",
                                None,
                            );
                            continue;
                        }
                        match v.value.as_text() {
                            Some(text) => {
                                self.params.insert(
                                    k.value.clone(),
                                    ParamValue {
                                        text,
                                        origin: format!("{}:{}", self.source.path, v.span.line),
                                    },
                                );
                            }
                            None => self.problem(
                                v.span,
                                format!("parameter `{}` needs a value such as `6000 rpm`", k.value),
                                format!("this is {}", v.value.kind()),
                                None,
                            ),
                        }
                    }
                }
                YamlNode::Null => {}
                other => self.problem(
                    node.span,
                    format!("params is a mapping of names to values, this is {}", other.kind()),
                    "expected `name: value`",
                    None,
                ),
            }
        }
        for (name, value) in overrides {
            match self.params.get_mut(name) {
                Some(p) => {
                    p.text = value.clone();
                    p.origin = "--set".into();
                }
                None => {
                    let help = did_you_mean(name, self.params.keys().map(String::as_str))
                        .map(|s| format!("did you mean `{s}`?"))
                        .unwrap_or_else(|| format!("this recipe's parameters: {}", self.param_names()));
                    let at = node.map(|n| n.span).unwrap_or_default();
                    self.problem(
                        at,
                        format!("--set {name}: this recipe has no parameter `{name}`"),
                        "parameters are declared here",
                        Some(help),
                    );
                }
            }
        }
        for (name, p) in &self.params {
            out.push(Param {
                name: name.clone(),
                value: p.text.clone(),
                origin: p.origin.clone(),
            });
        }
        out
    }

    fn param_names(&self) -> String {
        if self.params.is_empty() {
            "none".into()
        } else {
            self.params.keys().cloned().collect::<Vec<_>>().join(", ")
        }
    }

    /// The node as text with `{{param}}` substituted; `None` after reporting a problem.
    fn text(&mut self, node: &Spanned<YamlNode>) -> Option<String> {
        let Some(raw) = node.value.as_text() else {
            self.problem(
                node.span,
                format!("expected a value, found {}", node.value.kind()),
                "here",
                None,
            );
            return None;
        };
        self.substitute(&raw, node.span)
    }

    /// Refuses a number that YAML reads as not finite (`.nan`, `.inf`, `1e400`), naming it
    /// as written; true when it was refused.
    fn not_finite(&mut self, node: &Spanned<YamlNode>) -> bool {
        let refused = match &node.value {
            YamlNode::Float(f) => !f.is_finite(),
            // How the parser hands over YAML's non-finite numbers (see `yaml_tree::parse`).
            YamlNode::Str(s) => matches!(s.as_str(), ".nan" | ".inf" | "-.inf" | "+.inf"),
            _ => false,
        };
        if refused {
            let written = self.written(node.span);
            self.problem(
                node.span,
                format!("`{written}` is not a finite number"),
                "not finite",
                Some("write a number such as `6000 rpm`, `1 %` or `0.5 A`".into()),
            );
        }
        refused
    }

    /// The text under `span` as written in the file.
    fn written(&self, span: Span) -> String {
        let text = &self.source.text;
        let start = span.offset.min(text.len());
        let end = (start + span.len).min(text.len());
        text.get(start..end).unwrap_or_default().trim().to_string()
    }

    /// Text that takes no parameters (names, descriptions).
    fn plain_text(&mut self, node: &Spanned<YamlNode>) -> Option<String> {
        match node.value.as_text() {
            Some(t) => Some(t),
            None => {
                self.problem(
                    node.span,
                    format!("expected text, found {}", node.value.kind()),
                    "here",
                    None,
                );
                None
            }
        }
    }

    fn substitute(&mut self, raw: &str, span: Span) -> Option<String> {
        let mut out = String::new();
        let mut rest = raw;
        let mut ok = true;
        while let Some(start) = rest.find("{{") {
            out.push_str(&rest[..start]);
            let after = &rest[start + 2..];
            let Some(end) = after.find("}}") else {
                self.problem(
                    span,
                    format!("`{{{{` without a closing `}}}}` in `{raw}`"),
                    "unclosed parameter",
                    Some("write parameters as {{name}}".into()),
                );
                return None;
            };
            let name = after[..end].trim();
            match self.params.get(name) {
                Some(p) => out.push_str(&p.text),
                None => {
                    ok = false;
                    let help = did_you_mean(name, self.params.keys().map(String::as_str))
                        .map(|s| format!("did you mean `{{{{{s}}}}}`?"))
                        .unwrap_or_else(|| {
                            format!(
                                "declare it under `params:` (this recipe's parameters: {})",
                                self.param_names()
                            )
                        });
                    self.problem(
                        span,
                        format!("unknown parameter `{name}`"),
                        "not declared under params",
                        Some(help),
                    );
                }
            }
            rest = &after[end + 2..];
        }
        out.push_str(rest);
        ok.then_some(out)
    }

    fn duration(&mut self, node: &Spanned<YamlNode>, what: &str) -> Option<Duration> {
        if let YamlNode::Int(_) | YamlNode::Float(_) = node.value {
            let n = node.value.as_text().unwrap_or_default();
            self.problem(
                node.span,
                format!("{what}: `{n}` has no unit"),
                "which unit?",
                Some(format!(
                    "write a duration with its unit, e.g. `{n} s`, `{n} ms` or `{n} min`"
                )),
            );
            return None;
        }
        let text = self.text(node)?;
        match humantime::parse_duration(text.trim()) {
            Ok(d) if d.is_zero() => {
                self.problem(
                    node.span,
                    format!("{what} must be longer than zero"),
                    "zero",
                    None,
                );
                None
            }
            Ok(d) if d > MAX_DURATION => {
                self.problem(
                    node.span,
                    format!(
                        "{what}: `{}` is longer than {} days, the longest duration a recipe may give",
                        text.trim(),
                        MAX_DURATION.as_secs() / (24 * 3600)
                    ),
                    "too long",
                    Some("check the number and the unit; repeat a shorter step for a longer run".into()),
                );
                None
            }
            Ok(d) => Some(d),
            Err(e) => {
                self.problem(
                    node.span,
                    format!("{what}: `{text}` is not a duration ({e})"),
                    "not a duration",
                    Some("write e.g. `500 ms`, `5 s`, `10 min`, `2 h`".into()),
                );
                None
            }
        }
    }

    fn object(&mut self, name: &str, span: Span) -> Option<(ObjectDef, ObjectRef)> {
        match self.dict.lookup(name) {
            Ok(def) => {
                let r = ObjectRef {
                    name: def.name.clone(),
                    unit: def.unit.map(|u| u.symbol().to_string()),
                };
                Some((def.clone(), r))
            }
            Err(e) => {
                let help = if e.suggestions.is_empty() {
                    Some("`drivescript objects` lists the objects of the dictionary".to_string())
                } else {
                    Some(format!(
                        "did you mean {}?",
                        e.suggestions
                            .iter()
                            .map(|s| format!("`{s}`"))
                            .collect::<Vec<_>>()
                            .join(" or ")
                    ))
                };
                self.problem(
                    span,
                    format!("unknown object `{name}` in the {} dictionary", self.dict.family()),
                    "unknown object",
                    help,
                );
                None
            }
        }
    }

    fn readable(&mut self, def: &ObjectDef, span: Span) -> bool {
        if def.readable() {
            return true;
        }
        self.problem(
            span,
            format!("{} is write-only and cannot be read", def.name),
            "write-only",
            None,
        );
        false
    }

    /// A number for `def` in its engineering unit; `check_limits` also refuses values
    /// outside the object's limits and type (for writes).
    fn number_for(&mut self, def: &ObjectDef, node: &Spanned<YamlNode>, check_limits: bool) -> Option<f64> {
        if self.not_finite(node) {
            return None;
        }
        let text = self.text(node)?;
        let q = match Quantity::parse(&text) {
            Ok(q) => q,
            Err(e) => {
                self.problem(node.span, format!("{}: {e}", def.name), "not a value", None);
                return None;
            }
        };
        if check_limits {
            if let Err(e) = def.to_raw(&q) {
                self.problem(
                    node.span,
                    e.to_string(),
                    "refused before anything is sent",
                    limits_help(def),
                );
                return None;
            }
        }
        match (q.unit, def.unit) {
            (None, _) => Some(q.value),
            (Some(u), Some(own)) => match u.convert(q.value, own) {
                Some(v) if !v.is_finite() => {
                    self.problem(
                        node.span,
                        format!("{}: `{text}` is too large to be a number of {own}", def.name),
                        "too large",
                        None,
                    );
                    None
                }
                Some(v) => Some(v),
                None => {
                    self.problem(
                        node.span,
                        format!("{u} is not a unit of {} ({own})", def.name),
                        "wrong unit",
                        None,
                    );
                    None
                }
            },
            (Some(u), None) => {
                self.problem(
                    node.span,
                    format!("{} has no unit; write a plain number, not {u}", def.name),
                    "no unit here",
                    None,
                );
                None
            }
        }
    }

    fn steps(&mut self, node: &Spanned<YamlNode>) -> Vec<Step> {
        match &node.value {
            YamlNode::Seq(items) => {
                let mut steps = Vec::new();
                let mut longest = Duration::ZERO;
                for item in items {
                    let Some(step) = self.step(item) else {
                        continue;
                    };
                    longest = longest.saturating_add(step.longest_time());
                    if let Err(over) = self.expansion.longest_time(longest) {
                        self.over_limit(item.span, over);
                    }
                    steps.push(step);
                }
                steps
            }
            YamlNode::Null => Vec::new(),
            other => {
                self.problem(
                    node.span,
                    format!(
                        "steps are a list (each line starting with `- `), this is {}",
                        other.kind()
                    ),
                    "expected a list",
                    None,
                );
                Vec::new()
            }
        }
    }

    fn step(&mut self, node: &Spanned<YamlNode>) -> Option<Step> {
        if self.expansion.is_over() {
            return None;
        }
        if let Err(over) = self.expansion.step() {
            self.over_limit(node.span, over);
            return None;
        }
        let origin = self.origin(node.span);
        match &node.value {
            YamlNode::Str(word) => {
                if let Some(cmd) = DeviceCommand::from_id(word) {
                    return Some(Step {
                        kind: StepKind::Command(cmd),
                        origin,
                        label: cmd.id().to_string(),
                    });
                }
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
                self.problem(
                    node.span,
                    format!("unknown step `{word}`"),
                    "unknown step",
                    Some(help),
                );
                None
            }
            YamlNode::Map(entries) => {
                let keys: Vec<&Spanned<String>> = entries
                    .iter()
                    .map(|(k, _)| k)
                    .filter(|k| k.value != "name")
                    .collect();
                if keys.len() != 1 {
                    self.problem(
                        node.span,
                        format!(
                            "a step has one keyword (and optionally `name`), this one has {}",
                            keys.len()
                        ),
                        "one step per list item",
                        Some("start each step with its own `- `".into()),
                    );
                    return None;
                }
                let key = keys[0].clone();
                let body = entries
                    .iter()
                    .find(|(k, _)| k.value == key.value)
                    .map(|(_, v)| v.clone())?;
                let name = self.get(entries, "name").and_then(|n| self.plain_text(n));
                self.keyed_step(&key, &body, name, origin)
            }
            other => {
                self.problem(node.span, format!("a step is a command such as `shutdown` or a mapping such as `set: {{...}}`, this is {}", other.kind()), "not a step", None);
                None
            }
        }
    }

    fn keyed_step(
        &mut self,
        key: &Spanned<String>,
        body: &Spanned<YamlNode>,
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
            word => {
                if DeviceCommand::from_id(word).is_some() {
                    self.problem(
                        key.span,
                        format!("`{word}` takes no settings; write it on its own: `- {word}`"),
                        "a plain command",
                        None,
                    );
                    return None;
                }
                let commands: Vec<&str> = DeviceCommand::ALL.iter().map(|c| c.id()).collect();
                let help = did_you_mean(word, STEP_KEYS.iter().copied().chain(commands.iter().copied()))
                    .map(|s| format!("did you mean `{s}`?"))
                    .unwrap_or_else(|| {
                        format!(
                            "steps: {} and the device commands {}",
                            STEP_KEYS.join(", "),
                            commands.join(", ")
                        )
                    });
                self.problem(
                    key.span,
                    format!("unknown step `{word}`"),
                    "unknown step",
                    Some(help),
                );
                return None;
            }
        };
        let label = match (&kind, name) {
            (StepKind::Expect(_), _) | (_, None) => label,
            (_, Some(n)) => n,
        };
        Some(Step { kind, origin, label })
    }

    fn map<'n>(&mut self, node: &'n Spanned<YamlNode>, what: &str, example: &str) -> Option<&'n Entries> {
        match &node.value {
            YamlNode::Map(m) => Some(m),
            other => {
                self.problem(
                    node.span,
                    format!("{what} takes a mapping, this is {}", other.kind()),
                    "expected a mapping",
                    Some(format!("e.g. `{example}`")),
                );
                None
            }
        }
    }

    fn state(&mut self, node: &Spanned<YamlNode>) -> Option<DeviceState> {
        let text = self.text(node)?;
        match DeviceState::from_id(text.trim()) {
            Some(s) => Some(s),
            None => {
                let ids: Vec<&str> = DeviceState::ALL.iter().map(|s| s.id()).collect();
                let help = did_you_mean(&text, ids.iter().copied())
                    .map(|s| format!("did you mean `{s}`?"))
                    .unwrap_or_else(|| format!("states: {}", ids.join(", ")));
                self.problem(
                    node.span,
                    format!("unknown state `{text}`"),
                    "unknown state",
                    Some(help),
                );
                None
            }
        }
    }

    fn go_to(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        let (state_node, timeout) = match &body.value {
            YamlNode::Map(entries) => {
                self.check_keys(entries, &["state", "timeout"], &["state"], body.span, "go_to");
                let timeout = match self.get(entries, "timeout") {
                    Some(t) => self.duration(t, "timeout")?,
                    None => DEFAULT_GO_TO_TIMEOUT,
                };
                (self.get(entries, "state")?.clone(), timeout)
            }
            _ => (body.clone(), DEFAULT_GO_TO_TIMEOUT),
        };
        let state = self.state(&state_node)?;
        if matches!(
            state,
            DeviceState::Fault | DeviceState::FaultReactionActive | DeviceState::NotReadyToSwitchOn
        ) {
            self.problem(
                state_node.span,
                format!(
                    "`{}` is entered by the drive itself, no command leads there",
                    state.id()
                ),
                "cannot be commanded",
                None,
            );
            return None;
        }
        Some((StepKind::GoTo { state, timeout }, format!("go to {}", state.id())))
    }

    fn set(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        let entries = self.map(body, "set", "set: { speed_setpoint: 6000 rpm }")?;
        let mut writes = Vec::new();
        let mut ok = true;
        for (k, v) in entries {
            let Some((def, r)) = self.object(&k.value, k.span) else {
                ok = false;
                continue;
            };
            if !def.writable() {
                self.problem(
                    k.span,
                    format!("{} is read-only and cannot be set", def.name),
                    "read-only",
                    None,
                );
                ok = false;
                continue;
            }
            if let DataType::String { .. } = def.data_type {
                match self.text(v) {
                    Some(t) => match def.text_to_raw(&t) {
                        Ok(_) => writes.push((r, SetValue::Text(t))),
                        Err(e) => {
                            self.problem(v.span, e.to_string(), "refused", None);
                            ok = false;
                        }
                    },
                    None => ok = false,
                }
                continue;
            }
            match self.number_for(&def, v, true) {
                Some(n) => writes.push((r, SetValue::Number(n))),
                None => ok = false,
            }
        }
        if writes.is_empty() && ok {
            self.problem(
                body.span,
                "set names no object",
                "empty",
                Some("e.g. `set: { speed_setpoint: 6000 rpm }`".into()),
            );
            return None;
        }
        let label = format!(
            "set {}",
            writes
                .iter()
                .map(|(o, v)| format!("{} = {}", o.name, show_set_value(v, o)))
                .collect::<Vec<_>>()
                .join(", ")
        );
        ok.then_some((StepKind::Set(writes), label))
    }

    fn object_list(&mut self, node: &Spanned<YamlNode>) -> Option<Vec<ObjectRef>> {
        let items: Vec<Spanned<YamlNode>> = match &node.value {
            YamlNode::Seq(items) => items.clone(),
            YamlNode::Str(_) => vec![node.clone()],
            other => {
                self.problem(
                    node.span,
                    format!(
                        "expected an object name or a list of them, found {}",
                        other.kind()
                    ),
                    "here",
                    None,
                );
                return None;
            }
        };
        let mut out = Vec::new();
        let mut ok = true;
        for item in &items {
            let Some(name) = self.plain_text(item) else {
                ok = false;
                continue;
            };
            match self.object(&name, item.span) {
                Some((def, r)) if self.readable(&def, item.span) => out.push(r),
                _ => ok = false,
            }
        }
        if out.is_empty() && ok {
            self.problem(node.span, "no object named", "empty", None);
            return None;
        }
        ok.then_some(out)
    }

    fn read(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        let objects = self.object_list(body)?;
        let label = format!("read {}", names(&objects));
        Some((StepKind::Read(objects), label))
    }

    fn print(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        if let YamlNode::Seq(_) = body.value {
            let objects = self.object_list(body)?;
            let label = format!("read {}", names(&objects));
            return Some((StepKind::Read(objects), label));
        }
        let text = self.text(body)?;
        Some((StepKind::Print(text.clone()), format!("print \"{text}\"")))
    }

    fn predicate(&mut self, def: &ObjectDef, node: &Spanned<YamlNode>) -> Option<Predicate> {
        let entries = self.map(node, &def.name, "{ near: 6000 rpm, within: 1 % }")?;
        let ops = ["equals", "above", "below", "between", "near"];
        let given: Vec<&Spanned<String>> = entries
            .iter()
            .map(|(k, _)| k)
            .filter(|k| ops.contains(&k.value.as_str()))
            .collect();
        let mut allowed: Vec<&str> = ops.to_vec();
        allowed.push("within");
        self.check_keys(entries, &allowed, &[], node.span, "condition");
        if given.len() != 1 {
            self.problem(
                node.span,
                format!(
                    "a condition on {} has exactly one of equals, above, below, between, near; this has {}",
                    def.name,
                    given.len()
                ),
                "one condition",
                Some("e.g. `{ near: 6000 rpm, within: 1 % }` or `{ above: 100 rpm }`".into()),
            );
            return None;
        }
        let op = given[0].value.clone();
        let value = self.get(entries, &op)?.clone();
        if op != "near" {
            if let Some(w) = self.get(entries, "within") {
                self.problem(w.span, "`within` goes with `near`", "only with near", None);
                return None;
            }
        }
        match op.as_str() {
            "equals" if matches!(def.data_type, DataType::String { .. }) => {
                Some(Predicate::EqualsText(self.text(&value)?))
            }
            "equals" => Some(Predicate::Equals(self.number_for(def, &value, false)?)),
            "above" => Some(Predicate::Above(self.number_for(def, &value, false)?)),
            "below" => Some(Predicate::Below(self.number_for(def, &value, false)?)),
            "between" => {
                let YamlNode::Seq(bounds) = &value.value else {
                    self.problem(
                        value.span,
                        "between takes two values: `between: [5900 rpm, 6100 rpm]`",
                        "expected [low, high]",
                        None,
                    );
                    return None;
                };
                if bounds.len() != 2 {
                    self.problem(
                        value.span,
                        format!("between takes two values, this has {}", bounds.len()),
                        "expected [low, high]",
                        None,
                    );
                    return None;
                }
                let lo = self.number_for(def, &bounds[0], false);
                let hi = self.number_for(def, &bounds[1], false);
                Some(Predicate::Between(lo?, hi?))
            }
            _ => {
                let target = self.number_for(def, &value, false);
                let Some(w) = self.get(entries, "within") else {
                    self.problem(
                        node.span,
                        "`near` needs `within`: how close is near enough",
                        "within missing",
                        Some("e.g. `within: 1 %` or `within: 20 rpm`".into()),
                    );
                    return None;
                };
                let tolerance = self.tolerance(def, w);
                Some(Predicate::Near {
                    target: target?,
                    tolerance: tolerance?,
                })
            }
        }
    }

    fn tolerance(&mut self, def: &ObjectDef, node: &Spanned<YamlNode>) -> Option<Tolerance> {
        if self.not_finite(node) {
            return None;
        }
        let text = self.text(node)?;
        let t = text.trim();
        if let Some(p) = t.strip_suffix('%') {
            return match p.trim().parse::<f64>() {
                Ok(v) if v.is_finite() && v >= 0.0 => Some(Tolerance::Percent(v)),
                _ => {
                    self.problem(
                        node.span,
                        format!("`{t}` is not a percentage"),
                        "expected e.g. 1 %",
                        None,
                    );
                    None
                }
            };
        }
        let v = self.number_for(def, node, false)?;
        if v < 0.0 {
            self.problem(node.span, "a tolerance cannot be negative", "negative", None);
            return None;
        }
        Some(Tolerance::Absolute(v))
    }

    fn wait_until(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        let entries = self.map(
            body,
            "wait_until",
            "wait_until: { state: operation_enabled, timeout: 5 s }",
        )?;
        let mut timeout = DEFAULT_WAIT_TIMEOUT;
        let mut every = DEFAULT_POLL;
        let mut conditions = Vec::new();
        let mut ok = true;
        for (k, v) in entries {
            match k.value.as_str() {
                "timeout" => match self.duration(v, "timeout") {
                    Some(d) => timeout = d,
                    None => ok = false,
                },
                "every" | "poll" => match self.duration(v, "every") {
                    Some(d) => every = d,
                    None => ok = false,
                },
                "state" => match self.state(v) {
                    Some(s) => conditions.push(Condition::State(s)),
                    None => ok = false,
                },
                name => match self.object(name, k.span) {
                    Some((def, r)) if self.readable(&def, k.span) => match self.predicate(&def, v) {
                        Some(p) => conditions.push(Condition::Value {
                            object: r,
                            predicate: p,
                        }),
                        None => ok = false,
                    },
                    _ => ok = false,
                },
            }
        }
        if !ok {
            return None;
        }
        if conditions.len() != 1 {
            self.problem(
                body.span,
                format!(
                    "wait_until waits for exactly one condition, this has {}",
                    conditions.len()
                ),
                "one condition",
                Some("use two wait_until steps to wait for two things".into()),
            );
            return None;
        }
        let condition = conditions.remove(0);
        let label = format!("wait until {condition} (timeout {})", show_duration(timeout));
        Some((
            StepKind::WaitUntil {
                condition,
                timeout,
                every,
            },
            label,
        ))
    }

    fn sample(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        let entries = self.map(
            body,
            "sample",
            "sample: { objects: [speed_actual], every: 100 ms, for: 60 s }",
        )?;
        self.check_keys(
            entries,
            &["objects", "every", "for", "csv"],
            &["objects", "every", "for"],
            body.span,
            "sample",
        );
        let objects = self.get(entries, "objects").and_then(|n| self.object_list(n));
        let every = self.get(entries, "every").and_then(|n| self.duration(n, "every"));
        let duration = self.get(entries, "for").and_then(|n| self.duration(n, "for"));
        let csv = match self.get(entries, "csv") {
            Some(n) => Some(PathBuf::from(self.text(n)?)),
            None => None,
        };
        let (objects, every, duration) = (objects?, every?, duration?);
        if every > duration {
            let at = self.get(entries, "every").map(|n| n.span).unwrap_or(body.span);
            self.problem(
                at,
                format!(
                    "sampling every {} for {} takes no sample after the first",
                    show_duration(every),
                    show_duration(duration)
                ),
                "longer than `for`",
                None,
            );
            return None;
        }
        let samples = duration.as_nanos() / every.as_nanos() + 1;
        if samples > u128::from(MAX_SAMPLES) {
            let at = self.get(entries, "every").map(|n| n.span).unwrap_or(body.span);
            self.problem(
                at,
                format!(
                    "sampling every {} for {} takes {samples} samples, more than {MAX_SAMPLES}",
                    show_duration(every),
                    show_duration(duration)
                ),
                "too often for so long",
                Some(
                    "sample less often (a larger `every`), or split the time into several sample steps"
                        .into(),
                ),
            );
            return None;
        }
        for o in &objects {
            self.sampled.insert(o.name.clone());
        }
        let label = format!(
            "sample {} every {} for {}",
            names(&objects),
            show_duration(every),
            show_duration(duration)
        );
        Some((
            StepKind::Sample {
                objects,
                every,
                duration,
                csv,
            },
            label,
        ))
    }

    fn expect(&mut self, body: &Spanned<YamlNode>, name: Option<&str>) -> Option<(StepKind, String)> {
        let entries = self.map(
            body,
            "expect",
            "expect: { speed_actual: { near: 6000 rpm, within: 1 % } }",
        )?;
        let mut checks = Vec::new();
        let mut ok = true;
        for (k, v) in entries {
            let Some((def, r)) = self.object(&k.value, k.span) else {
                ok = false;
                continue;
            };
            if !self.readable(&def, k.span) {
                ok = false;
                continue;
            }
            // `{ mean: { near: ... } }` checks a statistic; `{ near: ... }` the value now.
            let statistic = match &v.value {
                YamlNode::Map(m) if m.len() == 1 && Statistic::from_id(&m[0].0.value).is_some() => {
                    Some((Statistic::from_id(&m[0].0.value), m[0].1.clone(), m[0].0.span))
                }
                _ => None,
            };
            let (stat, pred_node) = match statistic {
                Some((stat, node, span)) => {
                    if !self.sampled.contains(&def.name) {
                        self.problem(span, format!("no earlier `sample` step samples {}, so there is no {} to check", def.name, m0(stat)), "nothing sampled", Some(format!("add `- sample: {{ objects: [{}], every: 100 ms, for: 10 s }}` before this step", def.name)));
                        ok = false;
                        continue;
                    }
                    (stat, node)
                }
                None => (None, v.clone()),
            };
            match self.predicate(&def, &pred_node) {
                Some(p) => {
                    let stat_text = stat.map(|s| format!("{} ", s.id())).unwrap_or_default();
                    let default_name = format!("{} {stat_text}{}", def.name, p.describe(r.unit.as_deref()));
                    let check_name = match name {
                        Some(n) if entries.len() == 1 => n.to_string(),
                        Some(n) => format!("{n}: {default_name}"),
                        None => default_name,
                    };
                    checks.push(Check {
                        name: check_name,
                        object: r,
                        statistic: stat,
                        predicate: p,
                    });
                }
                None => ok = false,
            }
        }
        if !ok {
            return None;
        }
        if checks.is_empty() {
            self.problem(body.span, "expect names no check", "empty", None);
            return None;
        }
        let label = format!(
            "expect {}",
            checks
                .iter()
                .map(|c| c.name.clone())
                .collect::<Vec<_>>()
                .join("; ")
        );
        Some((StepKind::Expect(checks), label))
    }

    fn ramp(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        let entries = self.map(
            body,
            "ramp",
            "ramp: { object: speed_setpoint, from: 0 rpm, to: 6000 rpm, rate: 1000 rpm/s }",
        )?;
        self.check_keys(
            entries,
            &["object", "from", "to", "step", "rate", "every"],
            &["object", "from", "to"],
            body.span,
            "ramp",
        );
        let obj_node = self.get(entries, "object")?.clone();
        let obj_name = self.plain_text(&obj_node)?;
        let (def, r) = self.object(&obj_name, obj_node.span)?;
        if !def.writable() {
            self.problem(
                obj_node.span,
                format!("{} is read-only and cannot be ramped", def.name),
                "read-only",
                None,
            );
            return None;
        }
        let from = self
            .get(entries, "from")
            .and_then(|n| self.number_for(&def, n, true));
        let to = self
            .get(entries, "to")
            .and_then(|n| self.number_for(&def, n, true));
        let every = match self.get(entries, "every") {
            Some(n) => self.duration(n, "every"),
            None => Some(DEFAULT_RAMP_EVERY),
        };
        let step_size = match (self.get(entries, "step"), self.get(entries, "rate")) {
            (Some(_), Some(rate)) => {
                self.problem(
                    rate.span,
                    "give either `step` or `rate`, not both",
                    "both given",
                    None,
                );
                None
            }
            (Some(s), None) => self.number_for(&def, s, false).map(f64::abs),
            (None, Some(rate)) => self
                .rate(&def, rate)
                .and_then(|per_s| every.map(|e| per_s * e.as_secs_f64())),
            (None, None) => {
                self.problem(
                    body.span,
                    "a ramp needs `step` (how much each write changes) or `rate` (per second)",
                    "step or rate missing",
                    Some("e.g. `rate: 1000 rpm/s` or `step: 500 rpm`".into()),
                );
                None
            }
        };
        let (from, to, every, step_size) = (from?, to?, every?, step_size?);
        if !step_size.is_finite() {
            self.problem(
                body.span,
                "the ramp's step or rate is too large to be a number",
                "not finite",
                None,
            );
            return None;
        }
        if step_size <= 0.0 {
            self.problem(
                body.span,
                "the ramp's step or rate must be more than zero",
                "zero step",
                None,
            );
            return None;
        }
        let n = ((to - from).abs() / step_size).ceil() as usize;
        if n > MAX_RAMP_POINTS {
            self.problem(
                body.span,
                format!("this ramp would write {n} values; make the step larger"),
                "too many steps",
                None,
            );
            return None;
        }
        let dir = if to >= from { 1.0 } else { -1.0 };
        let mut points: Vec<f64> = (0..n).map(|i| from + dir * step_size * i as f64).collect();
        points.push(to);
        let u = r.unit.clone().map(|u| format!(" {u}")).unwrap_or_default();
        let label = format!(
            "ramp {} from {}{u} to {}{u} in {} steps every {}",
            r.name,
            crate::session::number(from),
            crate::session::number(to),
            points.len(),
            show_duration(every)
        );
        Some((
            StepKind::Ramp {
                object: r,
                points,
                every,
            },
            label,
        ))
    }

    /// `1000 rpm/s` → 1000 (object units per second).
    fn rate(&mut self, def: &ObjectDef, node: &Spanned<YamlNode>) -> Option<f64> {
        let text = self.text(node)?;
        let Some((amount, per)) = text.rsplit_once('/') else {
            self.problem(
                node.span,
                format!("`{text}` is not a rate"),
                "expected e.g. 1000 rpm/s",
                None,
            );
            return None;
        };
        let seconds = match per.trim() {
            "s" => 1.0,
            "min" => 60.0,
            "ms" => 0.001,
            "h" => 3600.0,
            other => {
                self.problem(
                    node.span,
                    format!("`/{other}`: a rate is per s, min, ms or h"),
                    "unknown time unit",
                    None,
                );
                return None;
            }
        };
        let amount_node = Spanned::new(YamlNode::Str(amount.trim().to_string()), node.span);
        self.number_for(def, &amount_node, false)
            .map(|v| v.abs() / seconds)
    }

    fn repeat(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        let entries = self.map(body, "repeat", "repeat: { times: 3, steps: [...] }")?;
        self.check_keys(
            entries,
            &["times", "for", "steps"],
            &["steps"],
            body.span,
            "repeat",
        );
        let times = match self.get(entries, "times") {
            Some(n) => match n.value {
                YamlNode::Int(t) if t >= 1 && t <= u32::MAX as i64 => Some(t as u32),
                _ => {
                    self.problem(n.span, "times is a whole number, 1 or more", "not a count", None);
                    return None;
                }
            },
            None => None,
        };
        let duration = match self.get(entries, "for") {
            Some(n) => Some(self.duration(n, "for")?),
            None => None,
        };
        if times.is_none() && duration.is_none() {
            self.problem(
                body.span,
                "repeat needs `times` or `for`",
                "how often?",
                Some("e.g. `times: 3` or `for: 2 h`".into()),
            );
            return None;
        }
        if times.is_some() && duration.is_some() {
            self.problem(
                body.span,
                "give repeat either `times` or `for`, not both",
                "both given",
                None,
            );
            return None;
        }
        let steps = self.steps(self.get(entries, "steps")?);
        if duration.is_some() && !steps.iter().any(Step::takes_time) {
            let at = self.get(entries, "for").map(|n| n.span).unwrap_or(body.span);
            self.problem(
                at,
                "`repeat` with `for` needs a step that takes time (a wait, dwell, sample, ramp or drive access); these steps take none, so it would never end",
                "nothing takes time",
                Some("use `times` to repeat them a number of times".into()),
            );
            return None;
        }
        let label = match (times, duration) {
            (Some(t), _) => format!("repeat {t} times ({} steps)", steps.len()),
            (_, Some(d)) => format!("repeat for {} ({} steps)", show_duration(d), steps.len()),
            _ => "repeat".into(),
        };
        Some((
            StepKind::Repeat {
                times,
                duration,
                steps,
            },
            label,
        ))
    }

    fn include(&mut self, body: &Spanned<YamlNode>) -> Option<(StepKind, String)> {
        if self.expansion.is_over() {
            return None;
        }
        let (file_node, params_node) = match &body.value {
            YamlNode::Map(entries) => {
                self.check_keys(entries, &["file", "params"], &["file"], body.span, "include");
                (
                    self.get(entries, "file")?.clone(),
                    self.get(entries, "params").cloned(),
                )
            }
            _ => (body.clone(), None),
        };
        let file = self.text(&file_node)?;
        let path = self.base_dir.join(&file);
        let canon = canonical(&path);
        if self.include_chain.contains(&canon) {
            self.problem(
                file_node.span,
                format!(
                    "{file} includes itself (through {} file(s))",
                    self.include_chain.len()
                ),
                "include cycle",
                None,
            );
            return None;
        }
        if self.include_chain.len() >= MAX_INCLUDE_DEPTH {
            self.problem(
                file_node.span,
                format!("includes nest deeper than {MAX_INCLUDE_DEPTH} files"),
                "too deep",
                None,
            );
            return None;
        }
        if let Err(over) = self.expansion.load() {
            self.over_limit(file_node.span, over);
            return None;
        }
        let text = match read_text_file(&path) {
            Ok(t) => t,
            Err(e) => {
                let help = e
                    .help()
                    .unwrap_or_else(|| "include paths are relative to the including recipe".into());
                self.problem(
                    file_node.span,
                    e.sentence(&format!("the included file {}", path.display())),
                    "included file",
                    Some(help),
                );
                return None;
            }
        };
        // Parameters given in the include step, resolved in this file's parameters.
        let mut given = Vec::new();
        if let Some(p) = &params_node {
            if let Some(entries) = self.map(p, "params", "params: { speed: 8000 rpm }") {
                for (k, v) in entries {
                    if let Some(t) = self.text(v) {
                        given.push((k.value.clone(), t));
                    }
                }
            }
        }
        let shown = path.display().to_string();
        let source = Arc::new(RecipeSource {
            path: shown.clone(),
            text: Arc::from(text.as_str()),
        });
        let before = self.problems.len();
        let mut chain = self.include_chain.clone();
        chain.push(canon);
        let included = {
            let mut inner = Loader {
                dict: self.dict,
                source,
                problems: self.problems,
                expansion: self.expansion,
                params: BTreeMap::new(),
                sampled: self.sampled.clone(),
                base_dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
                include_chain: chain,
            };
            let r = inner.recipe(&text, &given);
            let sampled = inner.sampled;
            (r, sampled)
        };
        let (recipe, sampled) = included;
        self.sampled = sampled;
        if self.problems.len() > before {
            self.problem(
                file_node.span,
                format!("{file} has problems (listed with their own places)"),
                "included here",
                None,
            );
            return None;
        }
        let recipe = recipe?;
        let label = format!("include {file} ({})", recipe.name);
        Some((
            StepKind::Include {
                path: shown,
                steps: recipe.steps,
            },
            label,
        ))
    }
}

fn m0(stat: Option<Statistic>) -> &'static str {
    stat.map(Statistic::id).unwrap_or("value")
}

fn names(objects: &[ObjectRef]) -> String {
    objects
        .iter()
        .map(|o| o.name.clone())
        .collect::<Vec<_>>()
        .join(", ")
}

fn show_set_value(v: &SetValue, o: &ObjectRef) -> String {
    match v {
        SetValue::Text(t) => format!("\"{t}\""),
        SetValue::Number(n) => match &o.unit {
            Some(u) => format!("{} {u}", crate::session::number(*n)),
            None => crate::session::number(*n),
        },
    }
}

/// `10 min`, `500 ms`, `1h 30m`.
pub fn show_duration(d: Duration) -> String {
    humantime::format_duration(d).to_string()
}

fn limits_help(def: &ObjectDef) -> Option<String> {
    let unit = def.unit.map(|u| format!(" {}", u.symbol())).unwrap_or_default();
    let bench = match def.bench {
        Some(_) => " on this bench; only the limits file can raise a bench limit (not the recipe, --set or a dictionary)",
        None => "",
    };
    match (def.min, def.max) {
        (Some(lo), Some(hi)) => Some(format!(
            "{} accepts {}{unit} to {}{unit}{bench}",
            def.name,
            crate::session::number(lo),
            crate::session::number(hi)
        )),
        _ => None,
    }
}

fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The closest candidate, if any is close (the dictionary's similarity rule).
fn did_you_mean<'a>(input: &str, candidates: impl Iterator<Item = &'a str>) -> Option<String> {
    crate::diag::did_you_mean(input, candidates).into_iter().next()
}

fn yaml_help() -> String {
    "check indentation (spaces, not tabs) and that every `key:` is followed by a space".into()
}
