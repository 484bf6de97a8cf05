//! `drives:`: the named drives of a recipe with several, and the references steps make to
//! them (`left.speed_actual`, `- enable_operation: left`, `go_to: { drive: left, … }`),
//! each checked against that drive's own dictionary with did-you-mean on drive names. It
//! must not open anything; the command line does.

use super::{did_you_mean, Loader};
use crate::diag::{expected, read_source, Shape, Span, YamlNode, YamlValue};
use crate::dictionary::Dictionary;
use crate::recipe::drive_decl::DriveDecl;
use std::path::Path;
use std::sync::Arc;

/// The dictionary of every drive a recipe declares, by name, as the command line loaded
/// them (with the bench limits applied).
pub type DriveDictionaries = Vec<(String, Arc<Dictionary>)>;

const DRIVE_KEYS: &[&str] = &["drive", "address", "port", "tcp", "can"];

/// The drives a recipe file declares under `drives:` and the dictionary each names, read
/// before the recipe is loaded so that each drive's dictionary can be loaded first.
/// Anything that cannot be read is left to the loader to report.
pub fn declared_drives(path: &Path) -> Vec<(String, String)> {
    let is_file = std::fs::metadata(path).is_ok_and(|m| m.is_file());
    if !is_file {
        return Vec::new();
    }
    let Ok(source) = read_source(path) else {
        return Vec::new();
    };
    let Ok(root) = YamlNode::parse(&source) else {
        return Vec::new();
    };
    let Some(entries) = root.get("drives").and_then(YamlNode::entries) else {
        return Vec::new();
    };
    entries
        .iter()
        .filter_map(|(name, body)| match &body.get("drive")?.value {
            YamlValue::Str(drive) => Some((name.value.clone(), drive.clone())),
            _ => None,
        })
        .collect()
}

impl<'a> Loader<'a, '_> {
    /// `drives: { left: { drive: sd2, address: dnc:2 }, … }`.
    pub(super) fn drives_section(&mut self, node: &YamlNode) -> Vec<DriveDecl> {
        let Some(entries) = node.entries() else {
            self.r.report(expected(
                node,
                "`drives`",
                "a mapping of named drives (drives: { left: { drive: sd2, address: dnc:2 } })",
            ));
            return Vec::new();
        };
        if entries.is_empty() {
            self.problem(&node.span, "`drives` names no drive", "empty", None);
        }
        let mut out = Vec::new();
        for (key, body) in entries {
            let name = key.value.clone();
            let valid = name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
                && name
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
            if !valid {
                self.problem(
                    &key.span,
                    format!("`{name}` cannot name a drive"),
                    "drive name",
                    Some("a drive's name is lowercase letters, digits and `_`, starting with a letter (left, spindle_2)".into()),
                );
                continue;
            }
            let shape = Shape::new("this drive", DRIVE_KEYS)
                .require(&["drive"])
                .example("left: { drive: sd2, address: dnc:2 }");
            let Some(f) = self.r.fields(body, &shape) else {
                continue;
            };
            let mut text = |key: &str| {
                f.get(key)
                    .and_then(|n| self.r.scalar_text(n, &format!("`{key}`")))
            };
            let drive = text("drive").unwrap_or_default();
            let decl = DriveDecl {
                name: name.clone(),
                drive,
                address: text("address"),
                port: text("port"),
                tcp: text("tcp"),
                can: text("can"),
            };
            let own = [&decl.port, &decl.tcp, &decl.can]
                .iter()
                .filter(|c| c.is_some())
                .count();
            if own > 1 {
                self.problem(
                    &body.span,
                    format!("drive `{name}` names more than one connection"),
                    "one of port, tcp, can",
                    None,
                );
            }
            if !self.drive_dicts.iter().any(|(n, _)| *n == name) {
                self.problem(
                    &key.span,
                    format!("no dictionary was loaded for drive `{name}`"),
                    "drive",
                    Some("give `drive:` a built-in dictionary or family: sd2, ct-unidrive-sp, lenze-931, lenze-9400".into()),
                );
            }
            out.push(decl);
        }
        out
    }

    /// Whether the recipe declares named drives (then every object and command names one).
    pub(super) fn several_drives(&self) -> bool {
        !self.drive_dicts.is_empty()
    }

    /// The dictionary of the drive called `name` (written at `span`), or a problem with
    /// did-you-mean on the drive names.
    pub(super) fn drive_dictionary(&mut self, name: &str, span: &Span) -> Option<&'a Dictionary> {
        let drives: &'a [(String, Arc<Dictionary>)] = self.drive_dicts;
        if let Some((_, d)) = drives.iter().find(|(n, _)| n == name) {
            return Some(d);
        }
        let names: Vec<&str> = drives.iter().map(|(n, _)| n.as_str()).collect();
        let help = match did_you_mean(name, names.iter().copied()) {
            Some(s) => format!("did you mean `{s}`?"),
            None => format!("the recipe's drives are: {}", names.join(", ")),
        };
        self.problem(
            span,
            format!("unknown drive `{name}`"),
            "unknown drive",
            Some(help),
        );
        None
    }

    /// Runs `f` with the dictionary of the drive called `name` in place of the current one.
    pub(super) fn on_drive<T>(
        &mut self,
        name: &str,
        span: &Span,
        f: impl FnOnce(&mut Self) -> T,
    ) -> Option<T> {
        let dict = self.drive_dictionary(name, span)?;
        let before = std::mem::replace(&mut self.dict, dict);
        let out = f(self);
        self.dict = before;
        Some(out)
    }

    /// Runs `f` with each drive's dictionary in place in turn (once with the recipe's one
    /// dictionary without `drives:`) until one returns false (its problem is then said
    /// once, not once per drive); true when every run returned true.
    pub(super) fn on_every_drive(&mut self, mut f: impl FnMut(&mut Self) -> bool) -> bool {
        if !self.several_drives() {
            return f(self);
        }
        let drives: &'a [(String, Arc<Dictionary>)] = self.drive_dicts;
        let before = self.dict;
        let mut all = true;
        for (_, dict) in drives {
            self.dict = dict;
            if !f(self) {
                all = false;
                break;
            }
        }
        self.dict = before;
        all
    }
}

#[cfg(test)]
mod tests {
    use crate::diag::Source;
    use crate::dictionary::Dictionary;
    use crate::recipe::{Recipe, RecipeInvalid, StepKind};
    use std::path::Path;
    use std::sync::Arc;

    fn dictionary(name: &str) -> Arc<Dictionary> {
        Arc::new(
            crate::family::Registry::builtin()
                .load_dictionary(name)
                .expect("built-in dictionary"),
        )
    }

    fn load(text: &str) -> Result<Recipe, RecipeInvalid> {
        let drives = vec![
            ("left".to_string(), dictionary("sd2")),
            ("right".to_string(), dictionary("ct-unidrive-sp")),
        ];
        let first = drives[0].1.clone();
        super::super::load_source_for(Source::new("r.yaml", text), Path::new("."), &first, &drives, &[])
    }

    fn problems(text: &str) -> Vec<String> {
        let e = load(text).expect_err("expected problems");
        e.problems.iter().map(|p| p.located()).collect()
    }

    const HEAD: &str = "name: x\ndrives:\n  left: { drive: sd2, address: dnc:2 }\n  right: { drive: ct-unidrive-sp, port: /dev/ttyUSB1 }\nsteps:\n";

    #[test]
    fn drives_steps_name_their_drive_and_are_checked_against_its_dictionary() {
        let recipe = load(&format!(
            "{HEAD}  - shutdown\n  - enable_operation: right\n  - go_to: {{ drive: left, state: operation_enabled }}\n  - set: {{ left.speed_setpoint: 1000 rpm }}\n"
        ))
        .expect("valid");
        assert_eq!(recipe.drives.len(), 2);
        assert_eq!(recipe.drives[0].address.as_deref(), Some("dnc:2"));
        assert!(recipe.drives[0].on_command_line_connection());
        assert_eq!(recipe.drives[1].port.as_deref(), Some("/dev/ttyUSB1"));
        assert!(matches!(recipe.steps[0].kind, StepKind::Command(_, None)));
        assert!(matches!(&recipe.steps[1].kind, StepKind::Command(_, Some(d)) if d == "right"));
        assert!(matches!(&recipe.steps[2].kind, StepKind::GoTo { drive: Some(d), .. } if d == "left"));
        match &recipe.steps[3].kind {
            StepKind::Set(writes) => assert_eq!(writes[0].0.name, "left.speed_setpoint"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn wrong_drive_references_are_problems_at_their_place() {
        assert_eq!(
            problems(&format!(
                "{HEAD}  - read: [lfet.speed_actual, speed_actual]\n  - disable_operation: rihgt\n  - go_to: {{ drive: nobody, state: switched_on }}\n"
            )),
            [
                "r.yaml:6:12: unknown drive `lfet`",
                "r.yaml:6:31: `speed_actual` does not say which drive it is on",
                "r.yaml:7:24: unknown drive `rihgt`",
                "r.yaml:8:21: unknown drive `nobody`",
            ]
        );
    }

    #[test]
    fn one_drive_and_several_drives_do_not_mix() {
        let text = "name: x\ndrive: sd2\ndrives:\n  left: { drive: sd2 }\n  Right: { drive: sd2 }\n  right: { drive: sd2, port: a, tcp: b }\nsteps:\n  - shutdown\n";
        let found = problems(text);
        assert!(
            found.iter().any(|p| p.contains("`Right` cannot name a drive")),
            "{found:?}"
        );
        assert!(
            found.iter().any(|p| p.contains("names more than one connection")),
            "{found:?}"
        );
        assert!(
            found
                .iter()
                .any(|p| p.contains("either one `drive:` or several `drives:`")),
            "{found:?}"
        );
    }
}
