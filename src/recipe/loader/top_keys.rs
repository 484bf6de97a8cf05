//! The recipe document itself: its top-level keys (`name`, `drive`, `params`, `steps`,
//! `finally`, `on_fault`, `leave_enabled`, `on_failure`, `watch`, `safe_stop`, `link`, `drives`), each handed to the part that reads
//! it. It must not read steps or values itself.

use super::Loader;
use crate::diag::{Shape, YamlNode};
use crate::dictionary::{read_dimensioned, Dimension};
use crate::recipe::recipe::{Recipe, SafeStopChoice};

const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "drive",
    "params",
    "steps",
    "finally",
    "on_fault",
    "leave_enabled",
    "on_failure",
    "watch",
    "safe_stop",
    "link",
    "drives",
];

impl Loader<'_, '_> {
    /// The whole file; `None` when it is not a recipe at all (not YAML, not a mapping).
    pub(super) fn recipe(&mut self, overrides: &[(String, String)]) -> Option<Recipe> {
        let root = match YamlNode::parse(&self.source) {
            Ok(root) => root,
            Err(e) => {
                // The parser stops a line or more after a list that lacks its `steps:` line;
                // the list's first line is where the fix goes.
                if let Some(span) = list_without_its_key(&self.source) {
                    self.problem(
                        &span,
                        "a list of steps with no `steps:` line above it",
                        "a list item after `key: value`",
                        Some(format!("add a line `steps:` above line {}", span.line())),
                    );
                    return None;
                }
                let help =
                    "check indentation (spaces, not tabs) and that every `key:` is followed by a space";
                self.r.report(e.diagnostic(self.source.path(), Some(help.into())));
                return None;
            }
        };
        let shape = Shape::new("this recipe", TOP_KEYS)
            .require(&["name", "steps"])
            .help("a recipe starts with `name:` and lists its `steps:`");
        let f = self.r.fields(&root, &shape)?;
        let name = f
            .get("name")
            .and_then(|n| self.r.scalar_text(n, "`name`"))
            .unwrap_or_default();
        let description = f
            .get("description")
            .and_then(|n| self.r.scalar_text(n, "`description`"));
        let drives = f
            .get("drives")
            .map(|n| self.drives_section(n))
            .unwrap_or_default();
        if let (Some(one), Some(_)) = (f.get("drive"), f.get("drives")) {
            self.problem(
                &one.span,
                "a recipe names either one `drive:` or several `drives:`, not both",
                "drive and drives",
                Some("move this drive into `drives:` with a name".into()),
            );
        }
        let drive_named = f.get("drive").is_some() || !drives.is_empty();
        let drive = match (f.get("drive"), drives.first()) {
            (Some(n), _) => self.drive_family(n),
            (None, Some(first)) => first.drive.clone(),
            (None, None) => self.dict.family().to_string(),
        };
        let leave_enabled = f
            .get("leave_enabled")
            .and_then(|n| self.r.bool(n, "`leave_enabled`"))
            .unwrap_or(false);
        let on_failure = f
            .get("on_failure")
            .and_then(|n| self.on_failure(n))
            .unwrap_or_default();
        let watches = f.get("watch").map(|n| self.watch_section(n)).unwrap_or_default();
        let safe_stop = f.get("safe_stop").map(|n| self.safe_stop(n)).unwrap_or_default();
        let link = f.get("link").map(|n| self.link(n)).unwrap_or_default();
        let params = self.params_section(f.get("params"), overrides);
        let steps = match f.get("steps") {
            Some(n) => self.steps(n, "`steps`"),
            None => Vec::new(),
        };
        let finally = f.get("finally").map(|n| self.steps(n, "`finally`"));
        let on_fault = f
            .get("on_fault")
            .map(|n| self.steps(n, "`on_fault`"))
            .unwrap_or_default();
        for (key, list) in [
            ("finally", finally.as_deref()),
            ("on_fault", Some(on_fault.as_slice())),
        ] {
            if let (Some(list), Some(node)) = (list, f.get(key)) {
                self.no_operator_steps(list, node, key);
            }
        }
        Some(Recipe {
            name,
            description,
            drive,
            drive_named,
            path: self.source.path().to_string(),
            params,
            steps,
            finally,
            on_fault,
            leave_enabled,
            on_failure,
            watches,
            safe_stop,
            link,
            drives,
            text_sha256: String::new(),
        })
    }

    /// `link: { channel: cyclic, velocity_scaling: 24000 rpm }`: settings of the family's
    /// link, as `--link-option NAME=VALUE` gives them; the family checks them before the
    /// port opens, and the command line's win.
    fn link(&mut self, node: &YamlNode) -> Vec<(String, String)> {
        let entries = self.r.mapping(
            node,
            "`link`",
            "a mapping of link settings (link: { channel: cyclic, velocity_scaling: 24000 rpm })",
        );
        entries
            .unwrap_or_default()
            .iter()
            .filter_map(|(key, value)| {
                let text = self.r.scalar_text(value, "a link setting")?;
                Some((key.value.clone(), text))
            })
            .collect()
    }

    /// `safe_stop: { timeout: 2 min, standstill: 20 rpm, brake_to_standstill: false }`.
    fn safe_stop(&mut self, node: &YamlNode) -> SafeStopChoice {
        let mut choice = SafeStopChoice::default();
        let shape = Shape::new(
            "this safe_stop",
            &["timeout", "standstill", "brake_to_standstill"],
        )
        .example("safe_stop: { timeout: 2 min, standstill: 20 rpm }");
        let Some(f) = self.r.fields(node, &shape) else {
            return choice;
        };
        if let Some(n) = f.get("timeout") {
            choice.timeout = self.duration(n, "safe_stop timeout");
        }
        if let Some(n) = f.get("brake_to_standstill") {
            if self.r.bool(n, "`brake_to_standstill`") == Some(false) {
                choice.no_brake_at = Some((n.span.line(), n.span.column()));
            }
        }
        if let Some(n) = f.get("standstill") {
            if let Some(text) = self.text(n, "`standstill`") {
                let example = "standstill: 20 rpm";
                choice.standstill = read_dimensioned(
                    &mut self.r,
                    &n.span,
                    "standstill",
                    text.trim(),
                    Dimension::Speed,
                    example,
                )
                .map(|(q, _)| q);
            }
        }
        choice
    }

    fn drive_family(&mut self, node: &YamlNode) -> String {
        let drive = self.r.scalar_text(node, "`drive`").unwrap_or_default();
        if !self.dict.is_for_drive(&drive) {
            let dictionary = self.dict.name();
            self.problem(
                &node.span,
                format!("this recipe is for drive `{drive}`, the dictionary in use is `{dictionary}`"),
                "other drive family",
                Some(format!(
                    "leave out --drive (a recipe's `drive:` picks its dictionary), or write `drive: {dictionary}`"
                )),
            );
        }
        drive
    }
}

/// The first list item (`- …`) that follows a top-level `key: value` line directly: the
/// steps of a recipe whose `steps:` line is missing, which YAML reads as more of the value
/// and then refuses a line or more later.
fn list_without_its_key(source: &std::sync::Arc<crate::diag::Source>) -> Option<crate::diag::Span> {
    let mut offset = 0;
    let mut previous: Option<&str> = None;
    for (index, line) in source.text().split_inclusive('\n').enumerate() {
        let content = line.trim_end();
        let trimmed = content.trim_start();
        let start = offset;
        offset += line.len();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let is_item = trimmed == "-" || trimmed.starts_with("- ");
        if is_item {
            let after_value = previous.is_some_and(|p| {
                !p.starts_with([' ', '\t', '-'])
                    && p.split_once(':').is_some_and(|(_, v)| {
                        let v = v.split(" #").next().unwrap_or("").trim();
                        !v.is_empty() && !v.starts_with(['|', '>', '&'])
                    })
            });
            if after_value {
                let column = content.len() - trimmed.len();
                return Some(crate::diag::Span::new(
                    source,
                    start + column,
                    trimmed.len(),
                    index + 1,
                    column + 1,
                ));
            }
        }
        previous = Some(content);
    }
    None
}
