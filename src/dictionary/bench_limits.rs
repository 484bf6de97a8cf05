//! A test bench's limits file: the highest speed and current anything may command on this
//! bench, and where the file was found. Finds and reads the file, checking it with the
//! field reader of every loader (every problem located, unknown keys with did-you-mean, units
//! of the right dimension). Tightening a dictionary's objects is the dictionary's job.
//! Its only I/O is reading the file and looking whether one lies next to the recipe; it
//! must not read the environment (the command line passes `DRIVESCRIPT_LIMITS` in).
//!
//! ```yaml
//! # drivescript bench limits: nothing may command more than this on this bench
//! max_speed: 12000 rpm
//! max_current: 8 A
//! ```

use super::dictionary_error::DictionaryError;
use super::quantity_reader::read_dimensioned;
use super::unit::Dimension;
use super::value::format_number;
use crate::diag::{expected, read_source, Diagnostic, Diagnostics, Reader, Shape, Source, YamlNode};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The file looked for next to a recipe when neither `--limits` nor the environment names one.
pub const LIMITS_FILE_NAME: &str = "drivescript-limits.yaml";
/// The environment variable naming a limits file (a bench's login profile sets it).
pub const LIMITS_ENV: &str = "DRIVESCRIPT_LIMITS";

/// The keys of a limits file and what each caps.
const KEYS: [(&str, Dimension); 2] = [
    ("max_speed", Dimension::Speed),
    ("max_current", Dimension::Current),
];

/// How the limits file in force was found, in the order they are tried.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimitsRoute {
    /// `--limits FILE`.
    Flag,
    /// The `DRIVESCRIPT_LIMITS` environment variable.
    Env,
    /// `drivescript-limits.yaml` in the recipe's folder.
    NextToRecipe,
}

/// The caps of one limits file.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchLimits {
    path: String,
    route: LimitsRoute,
    /// Highest speed in rpm and current in A, in the order of `KEYS`.
    caps: [Option<f64>; 2],
}

impl BenchLimits {
    /// The limits file that applies, if any: `flag` (`--limits`), else `env` (the value of
    /// `DRIVESCRIPT_LIMITS`, ignored when empty), else `drivescript-limits.yaml` next to
    /// `recipe` when that file exists. Only the first found is used.
    pub fn find(
        flag: Option<&Path>,
        env: Option<&OsStr>,
        recipe: Option<&Path>,
    ) -> Option<(PathBuf, LimitsRoute)> {
        if let Some(path) = flag {
            return Some((path.to_path_buf(), LimitsRoute::Flag));
        }
        if let Some(path) = env.filter(|v| !v.is_empty()) {
            return Some((PathBuf::from(path), LimitsRoute::Env));
        }
        let next_to = recipe?.parent()?.join(LIMITS_FILE_NAME);
        // A file that exists but cannot be read is reported when loading, not skipped.
        std::fs::symlink_metadata(&next_to)
            .is_ok()
            .then_some((next_to, LimitsRoute::NextToRecipe))
    }

    /// Reads and checks a limits file; every problem is reported.
    pub fn load(path: &Path, route: LimitsRoute) -> Result<BenchLimits, DictionaryError> {
        let source = read_source(path).map_err(|e| {
            let help = e.help().unwrap_or_else(|| match route {
                LimitsRoute::Flag => "check the path given with --limits".into(),
                LimitsRoute::Env => format!("check the path in {LIMITS_ENV}"),
                LimitsRoute::NextToRecipe => format!("check the file {LIMITS_FILE_NAME} next to the recipe"),
            });
            Diagnostic::unlocated(path.display().to_string(), e.sentence("the limits file")).with_help(help)
        })?;
        Self::from_source(&source, route)
    }

    /// Checks limits file text; `path` is only used in messages.
    pub fn from_yaml(path: &str, text: &str, route: LimitsRoute) -> Result<BenchLimits, DictionaryError> {
        Self::from_source(&Source::new(path, text), route)
    }

    fn from_source(file: &Arc<Source>, route: LimitsRoute) -> Result<BenchLimits, DictionaryError> {
        let path = file.path();
        if file.text().trim().is_empty() {
            return Err(Diagnostic::unlocated(path, "the limits file is empty")
                .with_help("write the caps of this bench, e.g. `max_speed: 12000 rpm` and `max_current: 8 A`")
                .into());
        }
        let root = YamlNode::parse(file).map_err(|e| e.diagnostic(path, None))?;
        let mut errors = Diagnostics::new();
        let mut caps = [None; 2];
        let mut r = Reader::new(&mut errors);
        let keys: Vec<&str> = KEYS.iter().map(|(k, _)| *k).collect();
        if let Some(fields) = r.fields(&root, &Shape::new("the limits file", &keys).nothing_is_absent()) {
            for (i, (key, dimension)) in KEYS.into_iter().enumerate() {
                if let Some(node) = fields.get(key) {
                    caps[i] = cap(&mut r, node, key, dimension);
                }
            }
        }
        let named_any = root.entries().is_some_and(|entries| !entries.is_empty());
        if errors.is_empty() && !named_any {
            errors.push(
                Diagnostic::at(&root.span, "the limits file names no limit", "no limit")
                    .with_help("write `max_speed: 12000 rpm`, `max_current: 8 A` or both"),
            );
        }
        if let Some(e) = DictionaryError::collect(errors) {
            return Err(e);
        }
        Ok(BenchLimits {
            path: path.to_string(),
            route,
            caps,
        })
    }

    /// The cap on objects of `dimension` in its base unit (rpm, A), if this file has one.
    pub fn cap(&self, dimension: Dimension) -> Option<f64> {
        KEYS.iter()
            .position(|(_, d)| *d == dimension)
            .and_then(|i| self.caps[i])
    }

    /// The file as given.
    pub fn path(&self) -> &str {
        &self.path
    }

    pub fn route(&self) -> LimitsRoute {
        self.route
    }

    /// `limits file /x/drivescript-limits.yaml`: where the caps come from, for messages.
    pub fn source(&self) -> String {
        match self.route {
            LimitsRoute::Env => format!("limits file {} from {LIMITS_ENV}", self.path),
            LimitsRoute::Flag | LimitsRoute::NextToRecipe => format!("limits file {}", self.path),
        }
    }

    /// `max_speed 12000 rpm, max_current 8 A`
    pub fn summary(&self) -> String {
        KEYS.iter()
            .zip(self.caps)
            .filter_map(|((key, dimension), cap)| {
                cap.map(|c| format!("{key} {} {}", format_number(c, 6), dimension.base()))
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// One cap in the base unit of `dimension`; `None` after reporting a problem.
fn cap(r: &mut Reader, node: &YamlNode, key: &str, dimension: Dimension) -> Option<f64> {
    let what = format!("`{key}`");
    let example = format!("{key}: {}", example_value(dimension));
    if r.refuse_non_finite(node, &what, &format!("write e.g. `{example}`")) {
        return None;
    }
    let Some(text) = node.as_text() else {
        let wanted = format!("a {} with its unit", dimension.name());
        r.report(expected(node, &what, &wanted).with_help(format!("write e.g. `{example}`")));
        return None;
    };
    read_dimensioned(r, &node.span, key, &text, dimension, &example).map(|(_, value)| value)
}

fn example_value(dimension: Dimension) -> &'static str {
    match dimension {
        Dimension::Current => "8 A",
        _ => "12000 rpm",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits(text: &str) -> Result<BenchLimits, DictionaryError> {
        BenchLimits::from_yaml("bench.yaml", text, LimitsRoute::Flag)
    }

    /// (line, column, message) of every problem.
    fn problems(text: &str) -> Vec<(usize, usize, String)> {
        limits(text)
            .expect_err("expected problems")
            .problems()
            .map(|p| (p.line(), p.column(), p.message().to_string()))
            .collect()
    }

    #[test]
    fn caps_in_base_units() {
        let l = limits("# bench 2\nmax_speed: 12 krpm\nmax_current: 8000 mA\n").unwrap();
        assert_eq!(l.cap(Dimension::Speed), Some(12000.0));
        assert_eq!(l.cap(Dimension::Current), Some(8.0));
        assert_eq!(l.cap(Dimension::Voltage), None);
        assert_eq!(l.summary(), "max_speed 12000 rpm, max_current 8 A");
        assert_eq!(l.source(), "limits file bench.yaml");
        let l = BenchLimits::from_yaml("b.yaml", "max_speed: 6000 rpm\n", LimitsRoute::Env).unwrap();
        assert_eq!(l.cap(Dimension::Current), None);
        assert_eq!(l.source(), "limits file b.yaml from DRIVESCRIPT_LIMITS");
    }

    #[test]
    fn every_problem_is_located_and_says_what_to_write() {
        let all = problems("max_sped: 6000 rpm\nmax_current: 8 rpm\n");
        assert_eq!(all[0], (1, 1, "unknown key `max_sped` in the limits file".into()));
        assert_eq!(
            all[1],
            (2, 14, "`max_current` is a current, but rpm measures speed".into())
        );
        let e = limits("max_sped: 6000 rpm\n").unwrap_err();
        assert!(e.first().help().unwrap_or("").contains("max_speed"), "{e:?}");

        let all = problems("max_speed: 6000\nmax_current: .inf\n");
        assert_eq!(all[0], (1, 12, "`max_speed` 6000 has no unit".into()));
        assert_eq!(
            all[1],
            (2, 14, "`max_current` must be a finite number, not `.inf`".into())
        );
        let all = problems("max_speed: -5 rpm\n");
        assert_eq!(all[0].2, "`max_speed` -5 rpm must be a finite number, 0 or more");
        let all = problems("max_speed: 6000 rpn\n");
        assert!(all[0].2.contains("did you mean `rpm`"), "{all:?}");
        let all = problems("max_speed: [6000 rpm]\n");
        assert_eq!(
            all[0].2,
            "`max_speed` must be a speed with its unit, found a list"
        );
        assert_eq!(problems("{}\n")[0].2, "the limits file names no limit");
        assert_eq!(
            problems("- 6000 rpm\n")[0].2,
            "the limits file must be a mapping (`key: value` lines), found a list"
        );
        assert_eq!(
            limits("  \n").unwrap_err().first().message(),
            "the limits file is empty"
        );
    }

    #[test]
    fn found_by_flag_then_environment_then_next_to_the_recipe() {
        let dir = std::env::temp_dir().join(format!("drivescript-bench-find-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let recipe = dir.join("r.yaml");
        let flag = Path::new("flag.yaml");
        let env = OsStr::new("env.yaml");
        assert_eq!(BenchLimits::find(None, None, Some(&recipe)), None);
        std::fs::write(dir.join(LIMITS_FILE_NAME), "max_speed: 1 rpm\n").unwrap();
        let next_to = (dir.join(LIMITS_FILE_NAME), LimitsRoute::NextToRecipe);
        assert_eq!(
            BenchLimits::find(None, None, Some(&recipe)),
            Some(next_to.clone())
        );
        assert_eq!(
            BenchLimits::find(None, Some(OsStr::new("")), Some(&recipe)),
            Some(next_to)
        );
        assert_eq!(
            BenchLimits::find(None, Some(env), Some(&recipe)),
            Some((PathBuf::from("env.yaml"), LimitsRoute::Env))
        );
        assert_eq!(
            BenchLimits::find(Some(flag), Some(env), Some(&recipe)),
            Some((PathBuf::from("flag.yaml"), LimitsRoute::Flag))
        );
        assert_eq!(BenchLimits::find(None, None, None), None);
        let e = BenchLimits::load(&dir.join("missing.yaml"), LimitsRoute::Env).unwrap_err();
        assert!(
            e.first().message().starts_with("cannot read the limits file"),
            "{e}"
        );
        assert_eq!(e.first().help(), Some("check the path in DRIVESCRIPT_LIMITS"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
