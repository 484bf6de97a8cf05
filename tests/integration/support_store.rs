//! Test support for runs recorded in a results store and compared with a unit's history:
//! a scratch folder with its store, a run recorded in it, the reports a run writes, a
//! stored check and what a failed comparison keeps, `results show`, a script for the
//! simulated drive. It starts no server and holds no fixture of other tests (see `support`).

use crate::support::{assert_has, cli, scratch, sqlite_store, write_file, Ran};
use drivescript::results::{CheckRow, Locator};
use std::path::{Path, PathBuf};

/// A fresh [`scratch`] folder `name` and the SQLite results store in it, as `--results`
/// takes it.
#[track_caller]
pub fn scratch_store(name: &str) -> (PathBuf, String) {
    let dir = scratch(name);
    let store = sqlite_store(&dir);
    (dir, store)
}

/// The JUnit and the HTML report of one run: `NAME.xml` and `NAME.html` in a folder.
pub struct Reports {
    junit: PathBuf,
    html: PathBuf,
}

impl Reports {
    /// The reports `name` in `dir` (not written yet).
    pub fn in_folder(dir: &Path, name: &str) -> Reports {
        Reports {
            junit: dir.join(format!("{name}.xml")),
            html: dir.join(format!("{name}.html")),
        }
    }

    /// `--junit FILE --report FILE` for `run`.
    pub fn args(&self) -> [&str; 4] {
        let utf8 = "a UTF-8 path";
        let (junit, html) = (self.junit.to_str().expect(utf8), self.html.to_str().expect(utf8));
        ["--junit", junit, "--report", html]
    }

    /// Both reports, each of which must hold every one of `parts`.
    #[track_caller]
    pub fn assert_both_have(&self, parts: &[&str]) {
        for report in [&self.junit, &self.html] {
            let text = std::fs::read_to_string(report).expect("the report");
            assert_has(&text, parts);
        }
    }
}

/// The check `name` of run `id` as `store` keeps it.
#[track_caller]
pub fn stored_check(store: &str, id: &str, name: &str) -> CheckRow {
    let mut s = Locator::parse(store).open(false).expect("the store opens");
    let stored = s.run(id).expect("the run");
    let found = stored.checks.into_iter().find(|c| c.name == name);
    found.unwrap_or_else(|| panic!("{name} is not stored in run {id}"))
}

/// `drivescript run RECIPE --fast --results STORE MORE`, which must exit with `code`: what
/// it wrote, standard output and errors apart (`support::run_recording` gives them as one).
#[track_caller]
pub fn run_recorded(recipe: &Path, store: &str, more: &[&str], code: i32) -> Ran {
    let recipe = recipe.to_str().expect("a UTF-8 path");
    cli(
        &[&["run", recipe, "--fast", "--results", store][..], more].concat(),
        code,
    )
}

/// What a failed comparison with the unit's last pass keeps in the store.
pub struct FailedComparison<'a> {
    /// The id of the run compared with.
    pub reference_run: &'a str,
    /// The value in that run.
    pub reference_value: f64,
    /// The change against it, in `unit`.
    pub change: f64,
    pub unit: &'a str,
    /// The limits of the change (low, high).
    pub limits: (Option<f64>, Option<f64>),
    /// How far the stored reference and change may be from these: 0 where the store keeps
    /// a value exactly as measured, the console's 0.001 for a computed one.
    pub within: f64,
}

impl FailedComparison<'_> {
    /// The comparison `name` of run `id` in `store` is kept as failed, as this says (each
    /// value to `within`).
    #[track_caller]
    pub fn assert_kept(&self, store: &str, id: &str, name: &str) {
        let c = stored_check(store, id, name);
        let near = |got: Option<f64>, value: f64| got.is_some_and(|g| (g - value).abs() <= self.within);
        assert!(!c.passed, "{c:?}");
        assert_eq!(c.reference_run.as_deref(), Some(self.reference_run), "{c:?}");
        assert!(near(c.reference_value, self.reference_value), "{c:?}");
        assert!(near(c.measured, self.change), "{c:?}");
        assert_eq!(c.unit.as_deref(), Some(self.unit), "{c:?}");
        assert_eq!((c.limits.low, c.limits.high), self.limits, "{c:?}");
    }
}

/// What `results show ID` of `store` printed; it must succeed.
#[track_caller]
pub fn shown_run(store: &str, id: &str) -> String {
    cli(&["results", "show", id, "--results", store], 0).stdout
}

/// A Rhai script `file` in `dir` for the simulated sd2 drive, named `name` in its header,
/// `body` after the header; its path.
pub fn sd2_script(dir: &Path, file: &str, name: &str, body: &str) -> PathBuf {
    write_file(dir, file, &format!("//! drive: sd2\n//! name: {name}\n{body}"))
}

/// A script as [`sd2_script`] writes it, alone in a fresh [`scratch`] folder `name`; its
/// path.
#[track_caller]
pub fn scratch_sd2_script(name: &str, file: &str, title: &str, body: &str) -> PathBuf {
    sd2_script(&scratch(name), file, title, body)
}
