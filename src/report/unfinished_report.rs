//! The reports written at the start of a run, before anything is sent: a valid JUnit file
//! with one failing test case and an HTML page, both saying that the run has not finished.
//! The final reports replace them; a run killed beyond any safe stop (SIGKILL, power loss)
//! leaves them, so CI reads a failure instead of an earlier run's PASS. Knows nothing of
//! drives; only the recipe's name and path.

use super::atomic_write::write_atomically;
use super::html_report::esc;
use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
use std::path::Path;

/// Completes "The run …" in both reports.
const NOT_FINISHED: &str = "has not finished: it is still running, or it was killed \
before it could write its report (SIGKILL, power loss, a crash of the machine); the drive's \
state is unknown to this report, check it";

/// The JUnit XML that stands in for a run still under way.
pub fn junit_unfinished(recipe: &str, recipe_path: &str) -> String {
    let mut status = TestCaseStatus::non_success(NonSuccessKind::Failure);
    status.set_message(format!("NOT FINISHED: the run {NOT_FINISHED}"));
    status.set_type("not_finished");
    let mut case = TestCase::new("run", status);
    case.set_classname(recipe_path);
    let mut suite = TestSuite::new(recipe);
    suite.add_test_case(case);
    let mut junit = Report::new("drivescript");
    junit.add_test_suite(suite);
    junit.to_string().unwrap_or_else(|e| {
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"drivescript\" tests=\"1\" \
             failures=\"1\" errors=\"0\"><testsuite name=\"not finished\" tests=\"1\" failures=\"1\" \
             errors=\"0\"><testcase name=\"run\"><failure message=\"NOT FINISHED\"/></testcase>\
             </testsuite><!-- {} --></testsuites>\n",
            e.to_string().replace("--", "- -")
        )
    })
}

/// Writes [`junit_unfinished`] to `path` atomically.
pub fn write_junit_unfinished(recipe: &str, recipe_path: &str, path: &Path) -> Result<(), String> {
    write_atomically(path, &junit_unfinished(recipe, recipe_path))
}

/// The HTML page that stands in for a run still under way.
pub fn html_unfinished(recipe: &str, recipe_path: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"generator\" content=\"drivescript {version}\">\n\
         <title>{name} — NOT FINISHED</title>\n<style>\n\
         body {{ font-family: system-ui, sans-serif; margin: 2em auto; max-width: 60em; }}\n\
         .verdict {{ display: inline-block; font-size: 2.2em; font-weight: bold; color: #8b0000; \
         background: #fbe0e0; padding: 0.1em 0.5em; border: 2px dashed #8b0000; }}\n\
         </style>\n</head>\n<body>\n<header>\n<h1>{name}</h1>\n\
         <p class=\"verdict not-finished\" id=\"verdict\">✘ NOT FINISHED</p>\n\
         <p class=\"why\">{why}.</p>\n</header>\n<p>Recipe file: {path}</p>\n\
         <footer>Written by drivescript {version} when the run started; the run replaces it \
         with its report when it ends.</footer>\n</body>\n</html>\n",
        version = env!("CARGO_PKG_VERSION"),
        name = esc(recipe),
        path = esc(recipe_path),
        why = esc(&format!("The run {NOT_FINISHED}")),
    )
}

/// Writes [`html_unfinished`] to `path` atomically.
pub fn write_html_unfinished(recipe: &str, recipe_path: &str, path: &Path) -> Result<(), String> {
    write_atomically(path, &html_unfinished(recipe, recipe_path))
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
