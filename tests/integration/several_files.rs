//! Several files in one `run` (issue 31 item 4, issue 32 item 7): ONE JUnit file with a
//! `<testsuite>` per file, valid against Jenkins' and Surefire's schemas and complete at
//! every ending (a signal, a panic); each file's own HTML report and an index page that
//! links them with their verdicts; `--set` applied where the parameter exists.

use crate::live_run::LiveRun;
use crate::reports::markup::{self, junit_xsd, select, text, xml_elements};
use crate::support::{
    assert_has, assert_lacks, cli, faults_before_the_run, scratch, scratch_file, words, InProcessRun,
};
use std::path::{Path, PathBuf};
use std::time::Duration;

const PASSING: &str = "tests/cases/ok/identity/recipe.yaml";
const FAILING: &str = "tests/cases/failed/expect_out_of_tolerance/recipe.yaml";
const INVALID: &str = "tests/cases/invalid/many_problems/recipe.yaml";

/// `xml` read back: well-formed, the JUnit structure, and (where xmllint is installed)
/// valid against both vendored schemas, each suite against Surefire's.
#[track_caller]
fn checked_junit(xml: &str) -> roxmltree::Document<'_> {
    let doc = markup::junit(xml).unwrap_or_else(|e| panic!("{e}\n{xml}"));
    match junit_xsd(xml) {
        None => crate::support::tool_missing("xmllint is not installed: only the structural check ran"),
        Some(result) => result.unwrap_or_else(|e| panic!("{e}\n{xml}")),
    }
    doc
}

/// Each suite's name and the `message` of its first failure, error or skipped element.
fn suites(doc: &roxmltree::Document) -> Vec<(String, String)> {
    xml_elements(doc, "testsuite")
        .iter()
        .map(|s| {
            let outcome = s
                .descendants()
                .find(|n| ["failure", "error", "skipped"].iter().any(|k| n.has_tag_name(*k)))
                .map(|n| format!("{} {}", n.tag_name().name(), n.attribute("message").unwrap_or("")))
                .unwrap_or_default();
            (s.attribute("name").unwrap_or("").to_string(), outcome)
        })
        .collect()
}

/// The JUnit file `j.xml` in `dir`, read back and checked as [`checked_junit`] does: each
/// suite's name and outcome, one for each of the run's three files.
#[track_caller]
fn three_suites(dir: &Path) -> Vec<(String, String)> {
    let path = dir.join("j.xml");
    let xml = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let found = suites(&checked_junit(&xml));
    assert_eq!(found.len(), 3, "{xml}");
    found
}

/// The index page's rows: file, verdict cell, link target.
fn index_rows(path: &Path) -> Vec<(String, String, Option<String>)> {
    let page = std::fs::read_to_string(path).expect("the index page");
    let doc = markup::html_index(&page).unwrap_or_else(|e| panic!("{e}\n{page}"));
    select(&doc, "section#files tbody > tr")
        .iter()
        .map(|row| {
            let cells: Vec<_> = row.child_elements().collect();
            let link = cells[3]
                .child_elements()
                .find(|a| a.value().name() == "a")
                .and_then(|a| a.value().attr("href").map(str::to_string));
            (text(&cells[1]), text(&cells[2]), link)
        })
        .collect()
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("the output dir")
        .map(|e| e.expect("an entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn one_junit_file_holds_a_suite_per_recipe_and_the_index_links_each_report() {
    let dir = scratch("one-junit");
    let out = cli(
        &[
            "run",
            PASSING,
            FAILING,
            INVALID,
            "--fast",
            "--output-dir",
            dir.to_str().unwrap(),
            "--junit",
            "j.xml",
            "--report",
            "report.html",
        ],
        2,
    )
    .stdout;
    assert_eq!(
        files_in(&dir),
        [
            "j.xml",
            "report-1-recipe.html",
            "report-2-recipe.html",
            "report-3-recipe.html",
            "report.html"
        ],
        "one JUnit file, a report per recipe and the index"
    );
    let xml = std::fs::read_to_string(dir.join("j.xml")).unwrap();
    let doc = checked_junit(&xml);
    let found = suites(&doc);
    assert_eq!(found.len(), 3, "{xml}");
    assert_eq!(
        found[0],
        ("Identity and state read-out".to_string(), String::new())
    );
    assert!(found[1].1.starts_with("failure "), "{found:?}");
    assert!(found[2].1.starts_with("error "), "the invalid recipe: {found:?}");
    let root = doc.root_element();
    assert_eq!(root.attribute("errors"), Some("1"), "{xml}");

    let rows = index_rows(&dir.join("report.html"));
    let verdicts: Vec<&str> = rows.iter().map(|r| r.1.split(' ').next().unwrap()).collect();
    assert_eq!(verdicts, ["PASSED", "FAILED", "NOT"], "{rows:?}");
    assert!(rows[2].1.contains("NOT RUN — INVALID"), "{rows:?}");
    assert_eq!(rows[0].0, PASSING);
    for (n, (_, _, link)) in rows.iter().enumerate() {
        let link = link
            .as_deref()
            .unwrap_or_else(|| panic!("row {n} links its report"));
        assert_eq!(link, format!("report-{}-recipe.html", n + 1));
        assert!(dir.join(link).is_file(), "{link}");
    }
    let page = std::fs::read_to_string(dir.join("report.html")).unwrap();
    assert!(page.contains("id=\"verdict\">✘ INVALID"), "the worst: {page}");
    assert!(!page.contains("src=") && !page.contains("<link") && !page.contains("<script"));

    let last = out.lines().last().unwrap_or("");
    for name in [
        "j.xml",
        "report.html",
        "report-1-recipe.html",
        "report-3-recipe.html",
    ] {
        assert!(last.contains(&dir.join(name).display().to_string()), "{last}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A signal in the first of three recipes: the JUnit file said while it ran that it had
/// not finished; at the end it holds that recipe as interrupted and the other two as
/// skipped, never run; the index says the same.
#[test]
fn a_signal_leaves_one_complete_junit_file_with_the_rest_not_run() {
    let (dir, slow) = scratch_file(
        "signal",
        "slow.yaml",
        "name: Slow\nsteps:\n  - read: [ident]\n  - dwell: 30 s\n  - expect: { bus_voltage: { between: [300 V, 340 V] } }\n",
    );
    let mut run = LiveRun::start([
        "run",
        slow.to_str().unwrap(),
        PASSING,
        FAILING,
        "--junit",
        dir.join("j.xml").to_str().unwrap(),
        "--report",
        dir.join("index.html").to_str().unwrap(),
    ]);
    run.wait_for("read ident");
    // Written before the first recipe ran.
    let found = three_suites(&dir);
    assert!(found[0].1.starts_with("failure NOT FINISHED"), "{found:?}");
    assert!(found[1].1.starts_with("skipped not run yet"), "{found:?}");
    run.signal("INT");
    let (code, out) = run.finish();
    assert_eq!(code, Some(130), "{out}");
    assert_has(&out, &["exit code 130 (the worst of them)"]);
    let found = three_suites(&dir);
    assert_eq!(found[0].0, "Slow");
    assert!(found[0].1.contains("INTERRUPTED"), "{found:?}");
    for later in &found[1..] {
        assert!(
            later
                .1
                .starts_with("skipped not run: the command was stopped by a signal"),
            "{found:?}"
        );
    }
    let rows = index_rows(&dir.join("index.html"));
    assert!(rows[0].1.starts_with("INTERRUPTED"), "{rows:?}");
    assert!(
        rows[1].1.starts_with("NOT RUN") && rows[1].2.is_none(),
        "{rows:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A panic in the second of three recipes: the file holds the first as passed, the
/// second as the panic it was, the third as not run.
#[test]
fn a_panic_leaves_one_complete_junit_file_with_the_rest_not_run() {
    let (dir, slow) = scratch_file(
        "panic",
        "turning.yaml",
        "name: Turning\nsteps:\n  - set: { speed_setpoint: 1000 rpm }\n  - go_to: operation_enabled\n  - dwell: 10 s\n",
    );
    let panic_after_the_first = faults_before_the_run(|f| f.panic_at(Duration::from_secs(2)));
    let mut run = InProcessRun::new(PASSING);
    run.output_dir = dir.clone();
    run.outputs.junit = Some("j.xml".into());
    run.prepare = Some(&panic_after_the_first);
    let files: Vec<PathBuf> = vec![PASSING.into(), slow, FAILING.into()];
    let (code, out) = run.run_many(&files);
    assert_eq!(code, 101, "{out}");
    let found = three_suites(&dir);
    assert_eq!(found[1].0, "Turning");
    assert!(found[1].1.starts_with("error PANIC"), "{found:?}");
    assert!(
        found[2]
            .1
            .starts_with("skipped not run: the command ended with an internal error"),
        "{found:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A run of a recipe and a script names each as what it is, and the summary counts files.
#[test]
fn a_recipe_and_a_script_are_each_named_as_what_they_are() {
    let out = cli(&["run", PASSING, "recipes/speed-sweep.rhai", "--fast"], 0);
    assert_has(
        &out.stdout,
        &[
            "== recipe 1 of 2: tests/cases/ok/identity/recipe.yaml",
            "== script 2 of 2: recipes/speed-sweep.rhai",
            "== 2 files:",
        ],
    );
    assert_lacks(&out.stdout, &["recipe(s)"]);
}

/// `--set speed=…` that only the first recipe has: applied there, and the second runs
/// without it (it used to refuse the second with exit code 2).
#[test]
fn a_set_applies_where_the_parameter_exists() {
    let out = cli(
        &words("run recipes/commissioning.yaml recipes/identity.yaml --fast --set speed=4000rpm"),
        0,
    );
    assert_has(
        &out.stdout,
        &[
            "params  speed = 4000rpm",
            "set speed_setpoint = 4000 rpm",
            "exit code 0 (the worst of them)",
        ],
    );
    assert_eq!(out.stdout.matches("PASSED —").count(), 2, "{}", out.stdout);
}

/// A `--set` name that no file of the run has is refused before anything runs, with the
/// name meant from any of the files.
#[test]
fn a_set_no_file_has_is_refused_before_anything_runs() {
    let dir = scratch("set-unknown");
    let junit = dir.join("j.xml");
    let out = cli(
        &[
            "run",
            "recipes/identity.yaml",
            "recipes/commissioning.yaml",
            "recipes/speed-sweep.rhai",
            "--fast",
            "--set",
            "spedd=4000rpm",
            "--set",
            "top=20000rpm",
            "--junit",
            junit.to_str().unwrap(),
        ],
        2,
    );
    assert_has(
        &out.stderr,
        &[
            "--set spedd=4000rpm: no file of this run has a parameter `spedd`",
            "did you mean `speed`?",
            "recipes/speed-sweep.rhai: from, top, step",
            "nothing was sent",
        ],
    );
    assert!(
        !out.stderr.contains("--set top"),
        "top is the script's: {}",
        out.stderr
    );
    assert!(!out.stdout.contains(" 1 of 3"), "nothing ran: {}", out.stdout);
    // CI reads this run's refusal.
    let found = three_suites(&dir);
    assert!(
        found.iter().all(|s| s.1.starts_with("error error: --set spedd")),
        "{found:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `--set` value in the wrong unit is said once, at the `--set`, not at each of the
/// three includes that use it and again at each include step.
#[test]
fn a_set_with_a_wrong_unit_is_said_once_at_the_set() {
    let out = cli(
        &words("run recipes/acceptance-test.yaml --fast --set max_current=5rpm"),
        2,
    );
    let text = out.stderr;
    assert_has(
        &text,
        &[
            "--set max_current=5rpm: rpm is not a unit of current_actual (A)",
            // With the platform's separator throughout: `recipes\includes\…` on Windows.
            &format!(
                "{}:20:39",
                Path::new("recipes")
                    .join("includes")
                    .join("speed-stage.yaml")
                    .display()
            ),
            "1 problem found; nothing was sent",
        ],
    );
    assert_eq!(text.matches("rpm is not a unit").count(), 1, "{text}");
    assert!(!text.contains("has problems"), "{text}");
}
