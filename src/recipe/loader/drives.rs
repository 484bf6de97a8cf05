//! `drives:`: the named drives of a recipe with several, and the references steps make to
//! them (`left.speed_actual`, `- enable_operation: left`, `go_to: { drive: left, … }`),
//! each checked against that drive's own dictionary with did-you-mean on drive names. It
//! must not open anything; the command line does.

use super::{did_you_mean, Loader};
use crate::diag::{read_source, Diagnostic, Fields, Shape, Span, YamlNode, YamlValue};
use crate::dictionary::Dictionary;
use crate::drive::{AddressKey, AddressKeys, KeyUse};
use crate::recipe::drive_decl::DriveDecl;
use std::path::Path;
use std::sync::Arc;

/// The dictionary of every drive a recipe declares, by name, as the command line loaded
/// them (with the bench limits applied).
pub type DriveDictionaries = Vec<(String, Arc<Dictionary>)>;

const DRIVE_KEYS: &[&str] = &["drive", "address", "port", "tcp", "can", "pole_pairs"];

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

/// Each named drive's `pole_pairs:` as written, by drive name: the motor behind that
/// inverter, which its dictionary takes before the recipe is loaded.
pub fn declared_pole_pairs(path: &Path) -> Vec<(String, String)> {
    let is_file = std::fs::metadata(path).is_ok_and(|m| m.is_file());
    let root = match is_file.then(|| read_source(path).ok()).flatten() {
        Some(source) => YamlNode::parse(&source).ok(),
        None => None,
    };
    let Some(entries) = root
        .as_ref()
        .and_then(|r| r.get("drives"))
        .and_then(YamlNode::entries)
    else {
        return Vec::new();
    };
    entries
        .iter()
        .filter_map(|(name, body)| Some((name.value.clone(), body.get("pole_pairs")?.as_text()?)))
        .collect()
}

impl<'a> Loader<'a, '_> {
    /// `drives: { left: { drive: sd2, address: dnc:2 }, … }`.
    pub(super) fn drives_section(&mut self, node: &YamlNode) -> Vec<DriveDecl> {
        let Some(entries) = self.r.mapping(
            node,
            "`drives`",
            "a mapping of named drives (drives: { left: { drive: sd2, address: dnc:2 } })",
        ) else {
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
            let family = self
                .drive_dicts
                .iter()
                .find(|(n, _)| *n == name)
                .map(|(_, d)| d.family().to_string());
            let own_keys = family
                .as_deref()
                .and_then(|f| self.address_keys.of(f))
                .map(|f| f.keys);
            // Keys of other families are said below with what this drive takes instead;
            // did-you-mean offers this drive's own keys.
            let mut allowed: Vec<&str> = DRIVE_KEYS.to_vec();
            allowed.extend(own_keys.iter().flat_map(|k| k.keys.iter().map(|k| k.name)));
            let entry_keys = body.entries().unwrap_or_default();
            let foreign: Vec<&str> = self
                .address_keys
                .all_key_names()
                .into_iter()
                .filter(|k| !allowed.contains(k) && entry_keys.iter().any(|(e, _)| e.value == *k))
                .collect();
            let mut shape_keys = allowed.clone();
            shape_keys.extend(&foreign);
            let shape = Shape::new("this drive", &shape_keys)
                .require(&["drive"])
                .example("left: { drive: sd2, address: dnc:2 }");
            let Some(f) = self.r.fields(body, &shape) else {
                continue;
            };
            // Without the drive's dictionary (said below) its family is unknown.
            if let Some(family) = family.as_deref() {
                for key in &foreign {
                    self.foreign_address_key(&name, family, key, &f.key(key).map(|k| k.span.clone()));
                }
            }
            let mut text = |key: &str| {
                f.get(key)
                    .and_then(|n| self.r.scalar_text(n, &format!("`{key}`")))
            };
            let drive = text("drive").unwrap_or_default();
            // As written: `address: 1.10` is group 1, unit 10, not the number 1.1.
            let address = match f.get("address") {
                Some(n) if matches!(n.value, YamlValue::Float(_)) => Some(n.written().trim().to_string()),
                _ => text("address"),
            };
            let (port, tcp, can) = (text("port"), text("tcp"), text("can"));
            let address = match own_keys {
                Some(keys) => self.address_from_keys(&name, keys, &f, address),
                None => address,
            };
            // Read with the drive's dictionary before the recipe (declared_pole_pairs);
            // only checked here.
            if let Some(n) = f.get("pole_pairs") {
                let given = self.r.scalar_text(n, "`pole_pairs`");
                if let Some(Err(e)) = given.map(|t| crate::dictionary::PolePairs::parse(&t)) {
                    self.r.report(Diagnostic::at(
                        &n.span,
                        e.to_string(),
                        "not a number of pole pairs",
                    ));
                }
            }
            let decl = DriveDecl {
                name: name.clone(),
                drive,
                address,
                port,
                tcp,
                can,
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
                    Some(format!(
                        "give `drive:` a built-in dictionary or family: {}",
                        self.address_keys.drive_names().join(", ")
                    )),
                );
            }
            out.push(decl);
        }
        out
    }

    /// A key another family reads as a drive's address (`dnc_address`) on drive `name` of
    /// `family`: says which families take it and how this drive's address is written.
    fn foreign_address_key(&mut self, name: &str, family: &str, key: &str, span: &Option<Span>) {
        let Some(span) = span else {
            return;
        };
        let takers: Vec<&str> = self
            .address_keys
            .families_with(key)
            .iter()
            .map(|(f, _)| f.family)
            .collect();
        let own = self.address_keys.of(family).map_or(String::new(), |m| {
            let keys: Vec<&str> = m.keys.keys.iter().map(|k| k.name).collect();
            let keys = if keys.is_empty() {
                String::new()
            } else {
                format!(" (or {})", keys.join(", "))
            };
            format!(
                "; drive `{name}` ({family}) takes `address:`{keys}: {}",
                m.address_help
            )
        });
        self.problem(
            span,
            format!("drive `{name}` is a {family} drive, which has no `{key}`"),
            "not a key of this drive's family",
            Some(format!(
                "`{key}` is an address key of {} drives{own}",
                takers.join(", ")
            )),
        );
    }

    /// The address of a `drives:` entry from `address:` and the family's own address keys
    /// (`dnc_address: 2`, `address: 0` with `axis: b`), in the family's notation; problems
    /// at the key they concern.
    fn address_from_keys(
        &mut self,
        name: &str,
        keys: AddressKeys,
        f: &Fields,
        address: Option<String>,
    ) -> Option<String> {
        // (key, value as written, where the key is), in file order.
        let mut given: Vec<(&'static AddressKey, String, Span)> = Vec::new();
        for (k, node) in f.entries() {
            let Some(key) = keys.key(&k.value) else {
                continue;
            };
            if let Some(value) = self.r.scalar_text(node, &format!("`{}`", key.name)) {
                given.push((key, value, k.span.clone()));
            }
        }
        if given.is_empty() {
            return address;
        }
        let address_key = f.key("address");
        let mut ok = true;
        // The one that comes second in the file is the problem: the first was meant.
        let mut instead: Vec<(&str, &Span)> = address_key.iter().map(|k| ("address", &k.span)).collect();
        for (key, value, span) in &given {
            match key.usage {
                KeyUse::InsteadOfAddress => instead.push((key.name, span)),
                KeyUse::WithAddress if address_key.is_none() => {
                    ok = false;
                    self.problem(
                        span,
                        format!("`{}: {value}` of drive `{name}` needs `address:`", key.name),
                        "without address:",
                        Some(format!(
                            "`{}` is {}; give `address:` with it",
                            key.name, key.meaning
                        )),
                    );
                }
                KeyUse::WithAddress => {}
            }
        }
        instead.sort_by_key(|(_, span)| span.offset());
        if let [(first, _), (second, span), ..] = instead.as_slice() {
            ok = false;
            let (first, second, span) = (first.to_string(), second.to_string(), (*span).clone());
            self.problem(
                &span,
                format!("drive `{name}` gives both `{first}` and `{second}`"),
                "a second address",
                Some(format!(
                    "give one of them: `{second}` stands instead of `{first}`"
                )),
            );
        }
        if !ok {
            return address;
        }
        let pairs: Vec<(&str, &str)> = given.iter().map(|(k, v, _)| (k.name, v.as_str())).collect();
        match (keys.to_address)(address.as_deref(), &pairs) {
            Ok(text) => Some(text),
            Err(problem) => {
                let span = f
                    .get(&problem.key)
                    .map_or_else(|| f.span().clone(), |n| n.span.clone());
                self.problem(&span, problem.message, problem.label, problem.help);
                address
            }
        }
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
        let keys = crate::family::Registry::builtin().address_keys();
        super::super::load_source_for(
            Source::new("r.yaml", text),
            Path::new("."),
            &first,
            (&drives, &keys),
            &[],
        )
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

    /// Problems with their place and help, for a recipe whose drives are all SD2 but
    /// `right` (Control Techniques).
    fn problems_with_help(drives: &str) -> Vec<String> {
        let text = format!("name: x\ndrives:\n{drives}steps:\n  - shutdown\n");
        let e = load(&text).expect_err("expected problems");
        e.problems
            .iter()
            .map(|p| format!("{} | {}", p.located(), p.help().unwrap_or_default()))
            .collect()
    }

    /// The first problem of `drives` starts with `start`; all of them, for more checks.
    fn first_starts_with(drives: &str, start: &str) -> Vec<String> {
        let found = problems_with_help(drives);
        assert!(found.first().is_some_and(|p| p.starts_with(start)), "{found:?}");
        found
    }

    /// The names offered for `drive:` are the registry's.
    #[test]
    fn a_drive_without_a_dictionary_is_offered_the_registrys_names() {
        let found = problems_with_help(
            "  left: { drive: sd2 }\n  right: { drive: ct-unidrive-sp }\n  middle: { drive: nothing }\n",
        );
        let problem = found
            .iter()
            .find(|p| p.contains("no dictionary was loaded for drive `middle`"))
            .unwrap_or_else(|| panic!("{found:?}"));
        for name in crate::family::Registry::builtin().address_keys().drive_names() {
            assert!(problem.contains(name), "{name}: {problem}");
        }
    }

    #[test]
    fn the_issue_spelling_of_sd2_addresses_becomes_the_notation() {
        let recipe = load(
            "name: x\ndrives:\n  left: { drive: sd2, dnc_address: 2 }\n  right: { drive: ct-unidrive-sp, address: 1.2 }\nsteps:\n  - shutdown\n",
        )
        .expect("valid");
        assert_eq!(recipe.drives[0].address.as_deref(), Some("dnc:2"));
        assert_eq!(recipe.drives[1].address.as_deref(), Some("1.2"));
        let recipe = load(
            "name: x\ndrives:\n  left: { drive: sd2 }\n  right: { drive: ct-unidrive-sp, address: 1.10 }\nsteps:\n  - shutdown\n",
        )
        .expect("valid");
        assert_eq!(recipe.drives[1].address.as_deref(), Some("1.10"));
        for (axis, address) in [("a", "0A"), ("b", "0B"), ("B", "0B")] {
            let recipe = load(&format!(
                "name: x\ndrives:\n  left: {{ drive: sd2, address: 0, axis: {axis} }}\n  right: {{ drive: ct-unidrive-sp }}\nsteps:\n  - shutdown\n"
            ))
            .expect("valid");
            assert_eq!(recipe.drives[0].address.as_deref(), Some(address));
        }
        // The family's own notation is unchanged.
        let recipe = load(&format!("{HEAD}  - shutdown\n")).expect("valid");
        assert_eq!(recipe.drives[0].address.as_deref(), Some("dnc:2"));
    }

    #[test]
    fn address_keys_given_wrongly_are_problems_at_their_key() {
        let right = "  right: { drive: ct-unidrive-sp }\n";
        assert_eq!(
            problems_with_help(&format!("  left: {{ drive: sd2, address: dnc:2, dnc_address: 2 }}\n{right}")),
            ["r.yaml:3:39: drive `left` gives both `address` and `dnc_address` | give one of them: `dnc_address` stands instead of `address`"]
        );
        assert_eq!(
            problems_with_help(&format!("  left: {{ drive: sd2, dnc_address: 2, address: dnc:2 }}\n{right}")),
            ["r.yaml:3:39: drive `left` gives both `dnc_address` and `address` | give one of them: `address` stands instead of `dnc_address`"]
        );
        for (left, start) in [
            ("{ drive: sd2, axis: b }", "r.yaml:3:23: `axis: b` of drive `left` needs `address:` | `axis` is the axis of a double-axis device"),
            ("{ drive: sd2, dnc_address: 2, axis: b }", "r.yaml:3:39: `axis: b` of drive `left` needs `address:`"),
        ] {
            let found = first_starts_with(&format!("  left: {left}\n{right}"), start);
            assert_eq!(found.len(), 1, "{found:?}");
        }
    }

    #[test]
    fn address_key_values_are_checked_by_the_family_at_their_value() {
        let right = "  right: { drive: ct-unidrive-sp }\n";
        let found = first_starts_with(
            &format!("  left: {{ drive: sd2, dnc_address: 1 }}\n{right}"),
            "r.yaml:3:36: `1` is not a drive's DNC address | a drive's DNC address is 2..=255; 0 and 1 belong to the master",
        );
        assert_eq!(found.len(), 1, "{found:?}");
        for (left, start) in [
            ("{ drive: sd2, address: 0, axis: c }", "r.yaml:3:41: `axis: c` is not an axis of a double-axis SD2 device | write `axis: a` or `axis: b`"),
            ("{ drive: sd2, address: 3B, axis: b }", "r.yaml:3:32: with `axis:`, `address: 3B` must be the address switch position alone"),
        ] {
            first_starts_with(&format!("  left: {left}\n{right}"), start);
        }
    }

    #[test]
    fn address_keys_of_another_family_and_misspelt_keys_say_what_to_write() {
        let found = problems_with_help(
            "  left: { drive: sd2, dnc_adress: 2 }\n  right: { drive: ct-unidrive-sp, dnc_address: 3, axis: b }\n",
        );
        assert_eq!(found.len(), 3, "{found:?}");
        assert_eq!(
            found[0],
            "r.yaml:3:23: unknown key `dnc_adress` in this drive | did you mean `dnc_address` or `address`?"
        );
        let starts = [
            "r.yaml:4:35: drive `right` is a ct-ansi drive, which has no `dnc_address` | `dnc_address` is an address key of sd2 drives; drive `right` (ct-ansi) takes `address:`: ",
            "r.yaml:4:51: drive `right` is a ct-ansi drive, which has no `axis` | `axis` is an address key of sd2 drives",
        ];
        for (problem, start) in found[1..].iter().zip(starts) {
            assert!(problem.starts_with(start), "{found:?}");
        }
    }

    #[test]
    fn one_drive_and_several_drives_do_not_mix() {
        let text = "name: x\ndrive: sd2\ndrives:\n  left: { drive: sd2 }\n  Right: { drive: sd2 }\n  right: { drive: sd2, port: a, tcp: b }\nsteps:\n  - shutdown\n";
        let found = problems(text);
        for part in [
            "`Right` cannot name a drive",
            "names more than one connection",
            "either one `drive:` or several `drives:`",
        ] {
            assert!(found.iter().any(|p| p.contains(part)), "{found:?}");
        }
    }
}
