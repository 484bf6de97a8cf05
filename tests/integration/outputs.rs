//! `run` with every output: trace (read back by `decode`), streamed CSV, JUnit and the
//! HTML report, written for a real run of the acceptance recipe; and an unwritable output
//! path refused before anything is sent.

use crate::support::{assert_has, cli, drivescript, scratch, stderr, stdout, words};

#[test]
fn a_run_writes_trace_csv_junit_and_html() {
    let dir = scratch("all");
    let p = |name: &str| dir.join(name).to_str().expect("utf-8").to_string();
    let (trace, csv, junit, html) = (p("trace.txt"), p("samples.csv"), p("junit.xml"), p("report.html"));
    cli(
        &[
            "run",
            "recipes/acceptance-test.yaml",
            "--fast",
            "--trace",
            &trace,
            "--csv",
            &csv,
            "--junit",
            &junit,
            "--report",
            &html,
        ],
        0,
    );

    let trace_text = std::fs::read_to_string(&trace).expect("trace");
    assert!(
        trace_text
            .contains(" TX 00 0b 02 01 0e 44 00 00 00 00 00 02 0f 00 8e  # write object 68 control_word"),
        "enable operation in the trace"
    );
    let telegrams = trace_text
        .lines()
        .filter(|l| !l.starts_with('#') && (l.contains(" TX ") || l.contains(" RX ")))
        .count();
    let decoded = drivescript(&["decode", "--json"], &trace_text);
    assert_eq!(decoded.status.code(), Some(0), "{}", stderr(&decoded));
    assert_eq!(
        stdout(&decoded).lines().count(),
        telegrams,
        "decode reads every telegram of the trace back"
    );

    let csv_text = std::fs::read_to_string(&csv).expect("csv");
    assert!(csv_text.starts_with("time [s],utc,step,object,value,unit\n"));
    // Three stages of 20 s at 100 ms, two objects: 3 × 201 × 2 rows.
    assert_eq!(csv_text.lines().count() - 1, 3 * 201 * 2);

    let junit_text = std::fs::read_to_string(&junit).expect("junit");
    assert!(
        junit_text.contains(r#"<testsuite name="Spindle acceptance test" tests="15""#),
        "{junit_text}"
    );
    assert!(junit_text.contains("failures=\"0\""));
    crate::reports::markup::junit(&junit_text).unwrap_or_else(|e| panic!("{e}\n{junit_text}"));

    let html_text = std::fs::read_to_string(&html).expect("html");
    assert!(html_text.starts_with("<!DOCTYPE html>"));
    crate::reports::markup::html(&html_text).unwrap_or_else(|e| panic!("{e}\n{html_text}"));
    assert!(html_text.contains("Spindle acceptance test"));
    assert!(html_text.contains("<polyline"), "plots of the sampled series");
    assert!(
        !html_text.contains("http://") || html_text.contains("http://www.w3.org/2000/svg"),
        "no external assets"
    );
}

#[test]
fn an_unwritable_output_is_refused_before_anything_is_sent() {
    let out = cli(
        &words("run recipes/commissioning.yaml --fast --csv /proc/no/such/dir/x.csv"),
        2,
    );
    assert_has(&out.stderr, &["/proc/no/such/dir"]);
    assert!(!out.stdout.contains("using the built-in"), "nothing was started");
}

/// A run that cannot start still replaces the JUnit and HTML files it was asked for: a
/// drive that cannot be reached (exit code 3) and an invalid recipe (exit code 2) each give
/// a valid JUnit file with the reason, the recipe's checks as skipped, and an HTML page.
#[test]
fn runs_that_cannot_start_write_junit_and_html() {
    let dir = scratch("not-run");
    let p = |name: &str| dir.join(name).to_str().expect("utf-8").to_string();
    let (junit, html) = (p("junit.xml"), p("report.html"));
    let xml = unreachable_run_writes_not_run_reports("recipes/acceptance-test.yaml", &junit, &html);
    let doc = crate::reports::markup::junit(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"));
    if let Some(valid) = crate::reports::markup::junit_xsd(&xml) {
        valid.unwrap_or_else(|e| panic!("{e}\n{xml}"));
    }
    let error = crate::reports::markup::xml_elements(&doc, "error")[0];
    assert_eq!(error.attribute("type"), Some("communication"));
    assert!(
        error.attribute("message").unwrap().contains("127.0.0.1:1"),
        "{xml}"
    );
    assert!(xml.contains("skipped=\"14\""), "every check of the recipe: {xml}");
    let page = std::fs::read_to_string(&html).expect("html");
    crate::reports::markup::html(&page).unwrap_or_else(|e| panic!("{e}\n{page}"));
    assert_has(&page, &["NOT RUN — ERROR", "127.0.0.1:1"]);

    let bad = dir.join("bad.yaml");
    std::fs::write(
        &bad,
        "name: Bad\ndrive: sd2\nsteps:\n  - set: { speed_setpont: 1 rpm }\n",
    )
    .unwrap();
    invalid_run_writes_not_run_reports(&bad, &junit, &html);
}

/// Runs `file` (a recipe or a script) on a port nobody listens at: exit code 3, and
/// the JUnit and HTML files say why; the JUnit text, for more checks.
pub(crate) fn unreachable_run_writes_not_run_reports(file: &str, junit: &str, html: &str) -> String {
    let no_server = drivescript(
        &[
            "run",
            file,
            "--tcp",
            "127.0.0.1:1",
            "--junit",
            junit,
            "--report",
            html,
        ],
        "",
    );
    assert_eq!(no_server.status.code(), Some(3), "{}", stderr(&no_server));
    let xml = std::fs::read_to_string(junit).expect("junit");
    assert!(xml.contains("type=\"communication\""), "{xml}");
    assert!(xml.contains("127.0.0.1:1"), "{xml}");
    let page = std::fs::read_to_string(html).expect("html");
    assert!(page.contains("NOT RUN — ERROR"), "{page}");
    xml
}

/// Runs `bad` (a recipe or a script that writes `speed_setpont`): exit code 2, and the
/// JUnit and HTML files say it was invalid and why.
pub(crate) fn invalid_run_writes_not_run_reports(bad: &std::path::Path, junit: &str, html: &str) {
    let invalid = drivescript(
        &["run", bad.to_str().unwrap(), "--junit", junit, "--report", html],
        "",
    );
    assert_eq!(invalid.status.code(), Some(2), "{}", stderr(&invalid));
    let xml = std::fs::read_to_string(junit).expect("junit");
    crate::reports::markup::junit(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"));
    assert_has(&xml, &["type=\"invalid\"", "speed_setpont"]);
    let page = std::fs::read_to_string(html).expect("html");
    assert_has(&page, &["NOT RUN — INVALID"]);
}
