//! The reports of runs that have no run report: the ones written at the start, before
//! anything is sent, saying that the run has not finished (the final reports replace
//! them; a run killed beyond any safe stop — SIGKILL, power loss — leaves them, so CI
//! reads a failure instead of an earlier run's PASS), and the ones of a run that never
//! started (an invalid recipe or command line, exit code 2; a drive that cannot be
//! reached, exit code 3), with the recipe's checks as not run. Knows nothing of drives.

use super::atomic_write::write_atomically;
use super::html::esc;
use super::junit_report::{case_name, classname, junit_document, name_apart, Case, JunitSuite};
use crate::session::PlannedCheck;
use std::path::Path;

/// Completes "The run …" in both reports.
const NOT_FINISHED: &str = "has not finished: it is still running, or it was killed \
before it could write its report (SIGKILL, power loss, a crash of the machine); the drive's \
state is unknown to this report, check it";

/// The JUnit XML that stands in for a run still under way.
pub fn junit_unfinished(recipe: &str, recipe_path: &str) -> String {
    junit_document(&[junit_unfinished_suite(recipe, recipe_path)])
}

/// The test suite of [`junit_unfinished`].
pub fn junit_unfinished_suite(recipe: &str, recipe_path: &str) -> JunitSuite {
    not_run_junit(
        recipe,
        recipe_path,
        ("failure", "not_finished"),
        &format!("NOT FINISHED: the run {NOT_FINISHED}"),
        &[],
    )
}

/// The JUnit XML of a run that never started: a case `run` with the error (`kind`
/// `invalid` or `communication`), and every check of the recipe as skipped.
pub fn junit_not_run(
    recipe: &str,
    recipe_path: &str,
    kind: &str,
    message: &str,
    planned: &[PlannedCheck],
) -> String {
    junit_document(&[junit_not_run_suite(recipe, recipe_path, kind, message, planned)])
}

/// The test suite of [`junit_not_run`].
pub fn junit_not_run_suite(
    recipe: &str,
    recipe_path: &str,
    kind: &str,
    message: &str,
    planned: &[PlannedCheck],
) -> JunitSuite {
    not_run_junit(recipe, recipe_path, ("error", kind), message, planned)
}

/// The test suite of a file that a command of several never started, because it ended
/// before (`why`): its case `run` skipped, so that CI counts it and does not fail on it
/// twice (the file that ended the command says why).
pub fn junit_skipped_suite(recipe_path: &str, why: &str) -> JunitSuite {
    not_run_junit(recipe_path, recipe_path, ("skipped", "not_run"), why, &[])
}

fn not_run_junit(
    recipe: &str,
    recipe_path: &str,
    (element, kind): (&'static str, &str),
    message: &str,
    planned: &[PlannedCheck],
) -> JunitSuite {
    let mut cases = vec![Case {
        name: "run".into(),
        time: 0.0,
        outcome: Some((
            element,
            kind.to_string(),
            first_line(message),
            message.to_string(),
        )),
        out: format!("recipe file: {recipe_path}\n"),
    }];
    let mut steps = vec![String::new()];
    for p in planned {
        steps.push(p.step.clone());
        cases.push(Case {
            name: case_name(&p.stage, &p.key),
            time: 0.0,
            outcome: Some((
                "skipped",
                "not_run".into(),
                "not run: the run did not start".into(),
                format!("check: {} at {}\n", p.name, p.origin),
            )),
            out: String::new(),
        });
    }
    name_apart(&mut cases, steps);
    JunitSuite {
        name: recipe.to_string(),
        classname: classname(recipe),
        time: 0.0,
        properties: vec![
            ("recipe".to_string(), recipe.to_string()),
            ("recipe_path".to_string(), recipe_path.to_string()),
        ],
        cases,
    }
}

/// A message's first line (a diagnostic's headline), for the JUnit `message`.
fn first_line(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("")
        .to_string()
}

/// Writes the stand-in report `page` makes ([`junit_unfinished`], [`html_unfinished`]) to
/// `path` atomically.
pub fn write_unfinished(
    page: fn(&str, &str) -> String,
    recipe: &str,
    recipe_path: &str,
    path: &Path,
) -> Result<(), crate::report::ReportWriteError> {
    write_atomically(path, &page(recipe, recipe_path))
}

/// The HTML page that stands in for a run still under way.
pub fn html_unfinished(recipe: &str, recipe_path: &str) -> String {
    page(
        recipe,
        recipe_path,
        "not-finished",
        "NOT FINISHED",
        &format!("The run {NOT_FINISHED}."),
        "when the run started; the run replaces it with its report when it ends",
    )
}

/// The HTML page of a run that never started: `word` (`INVALID`, `ERROR`) and why.
pub fn html_not_run(recipe: &str, recipe_path: &str, word: &str, why: &str) -> String {
    page(
        recipe,
        recipe_path,
        "not-run",
        &format!("NOT RUN — {word}"),
        why,
        "when the run could not start; nothing was sent to the drive by this run",
    )
}

fn page(recipe: &str, recipe_path: &str, class: &str, word: &str, why: &str, when: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"generator\" content=\"drivescript {version}\">\n\
         <title>{name} — {word_text}</title>\n<style>\n\
         body {{ font-family: system-ui, sans-serif; margin: 2em auto; max-width: 60em; }}\n\
         .verdict {{ display: inline-block; font-size: 2.2em; font-weight: bold; color: #8b0000; \
         background: #fbe0e0; padding: 0.1em 0.5em; border: 2px dashed #8b0000; }}\n\
         pre {{ white-space: pre-wrap; }}\n\
         </style>\n</head>\n<body>\n<header>\n<h1>{name}</h1>\n\
         <p class=\"verdict {class}\" id=\"verdict\">✘ {word_text}</p>\n\
         <pre class=\"why\">{why}</pre>\n</header>\n<p>Recipe file: {path}</p>\n\
         <footer>Written by drivescript {version} {when}.</footer>\n</body>\n</html>\n",
        version = env!("CARGO_PKG_VERSION"),
        name = esc(recipe),
        path = esc(recipe_path),
        word_text = esc(word),
        why = esc(why.trim_end()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_placeholders_say_not_finished_and_fail() {
        let xml = junit_unfinished("Run <in>", "recipes/x.yaml");
        assert!(xml.contains("failures=\"1\""), "{xml}");
        assert!(xml.contains("NOT FINISHED: the run has not finished"), "{xml}");
        assert!(xml.contains("Run &lt;in&gt;"), "{xml}");
        let html = html_unfinished("Run <in>", "recipes/x.yaml");
        assert!(html.contains("NOT FINISHED"), "{html}");
        assert!(html.contains("The run has not finished"), "{html}");
        assert!(html.contains("Run &lt;in&gt;"), "{html}");
    }
}
