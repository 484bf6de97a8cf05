//! `--junit FILE`: the run report as JUnit XML for CI, valid against Jenkins' junit-10.xsd
//! and the Ant/Surefire layout: one test suite named after the recipe, one test case per
//! check named `stage / check` by the check's key (stable when a limit or parameter
//! changes: the measured value and limits go to the message and `system-out`, never into
//! the name), a
//! `<skipped>` case per check the run never reached, a case `run` when the run failed in a
//! way no check shows, and a case `safe stop` with the run's log. Written from the
//! finished report only; never a half-written file.

use super::atomic_write::write_atomically;
use super::case_names::case_names;
use super::junit_xml_writer::XmlWriter;
use crate::session::{at_resolution, CheckResult, PlannedCheck, RunReport, StepRecord, Verdict};
use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;

/// One `<testcase>` before it is written.
#[derive(Clone)]
pub(crate) struct Case {
    pub name: String,
    pub time: f64,
    /// (element, type, message, text): `failure`, `error` or `skipped`.
    pub outcome: Option<(&'static str, String, String, String)>,
    pub out: String,
}

/// One `<testsuite>` before it is written: one file run.
#[derive(Clone)]
pub struct JunitSuite {
    pub(crate) name: String,
    pub(crate) classname: String,
    pub(crate) time: f64,
    pub(crate) properties: Vec<(String, String)>,
    pub(crate) cases: Vec<Case>,
}

/// The JUnit XML of a run; `planned` are the checks the recipe holds, so that the ones
/// the run never reached are shown as skipped.
pub fn junit_xml(report: &RunReport, planned: &[PlannedCheck]) -> String {
    junit_document(&[junit_suite(report, planned)])
}

/// The test suite of a run (see [`junit_xml`]).
pub fn junit_suite(report: &RunReport, planned: &[PlannedCheck]) -> JunitSuite {
    let r = report;
    let (mut cases, mut steps): (Vec<Case>, Vec<String>) =
        r.checks.iter().map(|c| (check_case(c), c.step.clone())).unzip();
    for (case, step) in not_reached(r, planned) {
        cases.push(case);
        steps.push(step);
    }
    name_apart(&mut cases, steps);
    if let Some(case) = run_case(r) {
        cases.push(case);
    }
    cases.push(safe_stop_case(r));
    let started = humantime::format_rfc3339_seconds(r.started_at).to_string();
    JunitSuite {
        name: r.recipe.clone(),
        classname: classname(&r.recipe),
        time: r.duration.as_secs_f64(),
        properties: suite_properties(r, &started),
        cases,
    }
}

/// Counts of `cases`: tests, failures, errors, skipped.
fn counts(cases: &[Case]) -> [usize; 4] {
    let count = |kind: &str| {
        cases
            .iter()
            .filter(|c| c.outcome.as_ref().is_some_and(|o| o.0 == kind))
            .count()
    };
    [cases.len(), count("failure"), count("error"), count("skipped")]
}

/// The whole document: `<testsuites>` with one `<testsuite>` per file run, as CI servers
/// read the reports of pytest, Hurl or Robot.
pub fn junit_document<'s>(suites: impl IntoIterator<Item = &'s JunitSuite>) -> String {
    let suites: Vec<&JunitSuite> = suites.into_iter().collect();
    let mut totals = [0; 4];
    for s in &suites {
        for (t, n) in totals.iter_mut().zip(counts(&s.cases)) {
            *t += n;
        }
    }
    let time = format!("{:.3}", suites.iter().map(|s| s.time).sum::<f64>());
    let mut w = XmlWriter::new();
    w.open(
        "testsuites",
        &[
            ("name", "drivescript"),
            ("tests", &totals[0].to_string()),
            ("failures", &totals[1].to_string()),
            ("errors", &totals[2].to_string()),
            ("time", &time),
        ],
    );
    for s in suites {
        suite_element(&mut w, s);
    }
    w.close("testsuites");
    w.finish()
}

fn suite_element(w: &mut XmlWriter, suite: &JunitSuite) {
    let [tests, failures, errors, skipped] = counts(&suite.cases);
    w.open(
        "testsuite",
        &[
            ("name", &suite.name),
            ("tests", &tests.to_string()),
            ("failures", &failures.to_string()),
            ("errors", &errors.to_string()),
            ("skipped", &skipped.to_string()),
            ("time", &format!("{:.3}", suite.time)),
        ],
    );
    if !suite.properties.is_empty() {
        w.open("properties", &[]);
        for (name, value) in &suite.properties {
            w.empty("property", &[("name", name), ("value", value)]);
        }
        w.close("properties");
    }
    for c in &suite.cases {
        w.open(
            "testcase",
            &[
                ("name", &c.name),
                ("classname", &suite.classname),
                ("time", &format!("{:.3}", c.time)),
            ],
        );
        if let Some((element, kind, message, text)) = &c.outcome {
            // Surefire's schema gives <skipped> a message but no type.
            if *element == "skipped" {
                w.text_element(element, &[("message", message)], text);
            } else {
                w.text_element(element, &[("type", kind), ("message", message)], text);
            }
        }
        if !c.out.is_empty() {
            w.text_element("system-out", &[], &c.out);
        }
        w.close("testcase");
    }
    w.close("testsuite");
}

/// Writes [`junit_xml`] to `path` atomically (via `path.tmp`), creating the directory.
pub fn write_junit(
    report: &RunReport,
    planned: &[PlannedCheck],
    path: &Path,
) -> Result<(), crate::report::ReportWriteError> {
    write_atomically(path, &junit_xml(report, planned))
}

/// Jenkins reads the part of a classname before its last dot as a package; a recipe name
/// is one class, whatever it holds.
pub(crate) fn classname(recipe: &str) -> String {
    recipe.replace('.', "_")
}

fn suite_properties(r: &RunReport, started: &str) -> Vec<(String, String)> {
    let mut p = vec![
        ("recipe".to_string(), r.recipe.clone()),
        ("recipe_path".into(), r.recipe_path.clone()),
        ("drive".into(), r.drive.clone()),
    ];
    if let Some(id) = &r.identity {
        p.push(("drive_identity".into(), id.clone()));
    }
    for (part, value) in r.unit.fields() {
        p.push((format!("unit.{part}"), value.to_string()));
    }
    for (name, value) in &r.params {
        p.push((format!("param.{name}"), value.clone()));
    }
    p.push(("started_at_utc".into(), started.to_string()));
    p.push(("verdict".into(), r.verdict.word().into()));
    p.push(("exit_code".into(), r.exit_code().to_string()));
    if let Some(reason) = r.verdict.reason() {
        p.push(("reason".into(), reason));
    }
    // One state for one drive; with several, `after_safe_stop` names each drive's.
    if let (Some(state), true) = (r.end.final_state, r.drive_ends.len() <= 1) {
        p.push(("final_state".into(), state.to_string()));
    }
    p.push(("after_safe_stop".into(), r.drive_left()));
    p.push((
        "safe_stop_confirmed".into(),
        if r.end.stop_confirmed {
            "true"
        } else {
            "false: CHECK THE DRIVE BY HAND"
        }
        .into(),
    ));
    // What a reader of a CI result must not take for a real unit's, and what ran.
    p.push(("simulated".into(), r.simulated().to_string()));
    if let Some(sha) = &r.recipe_sha256 {
        p.push(("recipe_sha256".into(), sha.clone()));
    }
    p.push(("tool_version".into(), env!("CARGO_PKG_VERSION").into()));
    p
}

/// Tells apart the check cases that share a name by the step that holds each
/// ([`case_names`]); `steps` answer `cases` one for one.
pub(crate) fn name_apart(cases: &mut [Case], steps: Vec<String>) {
    let keys: Vec<(String, String)> = cases.iter().map(|c| c.name.clone()).zip(steps).collect();
    for (case, name) in cases.iter_mut().zip(case_names(&keys)) {
        case.name = name;
    }
}

/// `Stage 2, 12000 rpm / speed_actual mean near`.
pub(crate) fn case_name(stage: &str, check: &str) -> String {
    if stage.is_empty() {
        check.to_string()
    } else {
        format!("{stage} / {check}")
    }
}

fn check_case(c: &CheckResult) -> Case {
    let details = check_details(c);
    let outcome = (!c.passed).then(|| {
        let mut message = c.message.clone();
        if let Some(m) = measured_text(c) {
            if !message.contains(m.as_str()) {
                let _ = write!(message, "; measured {m}");
            }
        }
        if let Some(l) = c.limits_text() {
            let _ = write!(message, "; limits {l}");
        }
        let kind = if c.name.starts_with("wait until") {
            "wait_until"
        } else {
            "expect"
        };
        // A failure of an attempt that was tried again is kept, as skipped: the verdict
        // is the last attempt's.
        match c.retried {
            true => (
                "skipped",
                kind.to_string(),
                format!("RETRIED: failed in an attempt that was tried again: {message}"),
                details.clone(),
            ),
            false => ("failure", kind.to_string(), message, details.clone()),
        }
    });
    Case {
        name: case_name(&c.stage, &c.key),
        time: c.duration.as_secs_f64(),
        outcome,
        out: details,
    }
}

/// Checks of the recipe that no result answers (same place, same pass, same check): the
/// run ended before them; each with the step that holds it.
fn not_reached(r: &RunReport, planned: &[PlannedCheck]) -> Vec<(Case, String)> {
    let reason = match (&r.stopped_on_failure, &r.verdict) {
        (Some(why), _) => format!("not run: {why}"),
        (None, Verdict::Passed) => "not reached".to_string(),
        (None, _) => format!("not reached: the run ended early ({})", r.verdict.word()),
    };
    let answered: HashSet<(String, &str, &str)> = r
        .checks
        .iter()
        .map(|c| (c.origin.to_string(), c.stage.as_str(), c.name.as_str()))
        .collect();
    planned
        .iter()
        .filter(|p| !answered.contains(&(p.origin.to_string(), p.stage.as_str(), p.name.as_str())))
        .map(|p| {
            let text = format!("check: {} at {}\n", p.name, p.origin);
            let case = Case {
                name: case_name(&p.stage, &p.key),
                time: 0.0,
                outcome: Some(("skipped", "not_reached".into(), reason.clone(), text.clone())),
                out: String::new(),
            };
            (case, p.step.clone())
        })
        .collect()
}

/// `measured: 6000.1 rpm`, `limits: 5970 .. 6030 rpm`, the message and where it is written.
fn check_details(c: &CheckResult) -> String {
    let mut s = String::new();
    if let Some(m) = measured_text(c) {
        let _ = writeln!(s, "measured: {m}");
    }
    if let Some(l) = c.limits_text() {
        let _ = writeln!(s, "limits: {l}");
    }
    if c.marginal {
        let _ = writeln!(s, "MARGINAL: passed outside the warning band");
    }
    let _ = writeln!(s, "result: {}", c.message);
    let _ = writeln!(s, "check: {} at {}", c.name, c.origin);
    if !c.step.is_empty() {
        let _ = writeln!(s, "step: {}", c.step);
    }
    s
}

fn measured_text(c: &CheckResult) -> Option<String> {
    match (c.measured, &c.measured_text) {
        (Some(v), _) => Some(at_resolution(v, c.decimals, c.unit.as_deref())),
        (None, Some(t)) => Some(t.clone()),
        (None, None) => None,
    }
}

/// Steps that failed without a failed check of their own (same place in the recipe).
pub(crate) fn unexplained_failures(r: &RunReport) -> Vec<&StepRecord> {
    r.steps
        .iter()
        .filter(|s| !s.ok)
        .filter(|s| !r.checks.iter().any(|c| !c.passed && c.origin == s.origin))
        .collect()
}

/// The test case `run`, failing when the run failed beyond its checks; none otherwise.
fn run_case(r: &RunReport) -> Option<Case> {
    let unexplained = unexplained_failures(r);
    let (kind, message) = match &r.verdict {
        Verdict::Error(m) => ("error", format!("ERROR: {m}")),
        Verdict::Interrupted(s) => (
            "failure",
            format!(
                "INTERRUPTED: the run was interrupted by {} and the safe stop ran",
                s.describe()
            ),
        ),
        Verdict::Panicked(m) => (
            "error",
            format!("PANIC: internal error ({m}); the safe stop ran after it"),
        ),
        Verdict::Failed if !unexplained.is_empty() || r.checks_failed() == 0 => {
            let first = unexplained
                .first()
                .map(|s| format!(": step {} {}: {}", s.id, s.label, s.detail))
                .unwrap_or_default();
            ("failure", format!("FAILED{first}"))
        }
        Verdict::Failed | Verdict::Passed => return None,
    };
    let mut description = String::new();
    for s in &unexplained {
        let _ = writeln!(
            description,
            "step {} ({}) FAIL {}: {} at {}",
            s.id, s.phase, s.label, s.detail, s.origin
        );
    }
    for note in &r.safe_stop {
        let _ = writeln!(description, "safe stop: {note}");
    }
    Some(Case {
        name: "run".into(),
        time: r.duration.as_secs_f64(),
        outcome: Some((kind, r.verdict.word().to_lowercase(), message, description)),
        out: String::new(),
    })
}

/// The test case `safe stop`: passes when the stop was verified and the drive obeyed;
/// its `system-out` is the run's log (JUnit readers show it next to the case).
fn safe_stop_case(r: &RunReport) -> Case {
    let outcome = (!r.end.stop_confirmed || r.disobeyed).then(|| {
        let message = if r.end.stop_confirmed {
            format!("the drive did not obey the stop commands; {}", r.drive_left())
        } else {
            format!(
                "CHECK THE DRIVE BY HAND: the safe stop could not be confirmed; {}",
                r.drive_left()
            )
        };
        let text = r.safe_stop.iter().map(|n| format!("safe stop: {n}\n")).collect();
        ("failure", "safe_stop".to_string(), message, text)
    });
    Case {
        name: "safe stop".into(),
        time: 0.0,
        outcome,
        out: run_log(r),
    }
}

/// Every step as the console showed it, then the safe stop and the verdict.
fn run_log(r: &RunReport) -> String {
    let mut s = String::new();
    for step in &r.steps {
        let _ = writeln!(
            s,
            "{}",
            super::console_reporter::step_line(step, &super::OpenAttempts::NONE)
        );
    }
    for line in super::console_reporter::summary_lines(r, false) {
        let _ = writeln!(s, "{line}");
    }
    s
}
