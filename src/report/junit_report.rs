//! `--junit FILE`: the run report as JUnit XML for CI. One test suite named after the
//! recipe, one test case per check (measured value, unit and limits as properties and in
//! the failure), and a test case `run` when the run failed in a way no check shows
//! (communication error, drive fault, interruption, a step that failed on its own).
//! Written from the finished report only; never a half-written file.

use super::atomic_write::write_atomically;
use crate::session::{number, with_unit, CheckResult, RunReport, StepRecord, Verdict};
use quick_junit::{NonSuccessKind, Property, Report, TestCase, TestCaseStatus, TestSuite, XmlString};
use std::fmt::Write as _;
use std::path::Path;

/// The JUnit XML of a run.
pub fn junit_xml(report: &RunReport) -> String {
    let mut suite = TestSuite::new(report.recipe.as_str());
    suite.set_time(report.duration);
    // Common JUnit schema: local time without zone; ours is UTC (the property says so).
    let started = humantime::format_rfc3339_seconds(report.started_at).to_string();
    suite.extra.insert(
        XmlString::new("timestamp"),
        XmlString::new(started.trim_end_matches('Z')),
    );
    suite.add_properties(suite_properties(report, &started));
    for c in &report.checks {
        suite.add_test_case(check_case(c, &report.recipe_path));
    }
    if let Some(case) = run_case(report) {
        suite.add_test_case(case);
    }
    suite.set_system_out(run_log(report));

    let mut junit = Report::new("drivescript");
    junit.set_time(report.duration);
    junit.add_test_suite(suite);
    match junit.to_string() {
        Ok(xml) => xml,
        // Serializing into memory only fails on a bug in quick-junit; say so in valid XML.
        Err(e) => format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"drivescript\" tests=\"0\" \
             failures=\"0\" errors=\"0\"><!-- cannot serialize: {} --></testsuites>\n",
            e.to_string().replace("--", "- -")
        ),
    }
}

/// Writes [`junit_xml`] to `path` atomically (via `path.tmp`), creating the directory.
pub fn write_junit(report: &RunReport, path: &Path) -> Result<(), String> {
    write_atomically(path, &junit_xml(report))
}

fn suite_properties(r: &RunReport, started: &str) -> Vec<Property> {
    let mut p = vec![
        Property::new("recipe", r.recipe.as_str()),
        Property::new("recipe_path", r.recipe_path.as_str()),
        Property::new("drive", r.drive.as_str()),
    ];
    if let Some(id) = &r.identity {
        p.push(Property::new("drive_identity", id.as_str()));
    }
    for (name, value) in &r.params {
        p.push(Property::new(format!("param.{name}"), value.as_str()));
    }
    p.push(Property::new("started_at_utc", started));
    p.push(Property::new("verdict", r.verdict.word()));
    p.push(Property::new("exit_code", r.exit_code().to_string()));
    if let Some(reason) = r.verdict.reason() {
        p.push(Property::new("reason", reason));
    }
    if let Verdict::Error(m) = &r.verdict {
        p.push(Property::new("error", m.as_str()));
    }
    if let Some(state) = r.final_state {
        p.push(Property::new("final_state", state.to_string()));
    }
    p.push(Property::new("after_safe_stop", r.drive_left()));
    p.push(Property::new(
        "safe_stop_confirmed",
        if r.stop_confirmed {
            "true"
        } else {
            "false: CHECK THE DRIVE BY HAND"
        },
    ));
    p
}

fn check_case(c: &CheckResult, classname: &str) -> TestCase {
    let details = check_details(c);
    let status = if c.passed {
        TestCaseStatus::success()
    } else {
        let mut s = TestCaseStatus::non_success(NonSuccessKind::Failure);
        let mut message = c.message.clone();
        let (measured, limits) = (measured_text(c), limits_text(c));
        if let Some(m) = &measured {
            if !message.contains(m.as_str()) {
                let _ = write!(message, "; measured {m}");
            }
        }
        if let Some(l) = &limits {
            let _ = write!(message, "; limits {l}");
        }
        s.set_message(message);
        s.set_type(if c.name.starts_with("wait until") {
            "wait_until"
        } else {
            "expect"
        });
        s.set_description(details.as_str());
        s
    };
    let mut case = TestCase::new(c.name.as_str(), status);
    case.set_classname(classname);
    case.set_time(c.duration);
    if let Some(v) = c.measured {
        case.add_property(Property::new("measured", number(v)));
    }
    if let Some(t) = &c.measured_text {
        case.add_property(Property::new("measured_text", t.as_str()));
    }
    if let Some(u) = &c.unit {
        case.add_property(Property::new("unit", u.as_str()));
    }
    if let Some(v) = c.low {
        case.add_property(Property::new("low", number(v)));
    }
    if let Some(v) = c.high {
        case.add_property(Property::new("high", number(v)));
    }
    if let Some(o) = &c.object {
        case.add_property(Property::new("object", o.as_str()));
    }
    if let Some(s) = &c.statistic {
        case.add_property(Property::new("statistic", s.as_str()));
    }
    case.add_property(Property::new("origin", c.origin.to_string()));
    case.set_system_out(details);
    case
}

/// `measured: 6000.1 rpm`, `limits: 5970 .. 6030 rpm`, the message and where it is written.
fn check_details(c: &CheckResult) -> String {
    let mut s = String::new();
    if let Some(m) = measured_text(c) {
        let _ = writeln!(s, "measured: {m}");
    }
    if let Some(l) = limits_text(c) {
        let _ = writeln!(s, "limits: {l}");
    }
    let _ = writeln!(s, "result: {}", c.message);
    let _ = writeln!(s, "check: {} at {}", c.name, c.origin);
    s
}

fn measured_text(c: &CheckResult) -> Option<String> {
    match (c.measured, &c.measured_text) {
        (Some(v), _) => Some(with_unit(v, c.unit.as_deref())),
        (None, Some(t)) => Some(t.clone()),
        (None, None) => None,
    }
}

/// `5970 .. 6030 rpm`, `= 1`, `> 5 A`, `< 60 °C`.
pub(crate) fn limits_text(c: &CheckResult) -> Option<String> {
    let u = c.unit.as_deref();
    Some(match (c.low, c.high) {
        (Some(lo), Some(hi)) if lo == hi => format!("= {}", with_unit(lo, u)),
        (Some(lo), Some(hi)) => format!("{} .. {}", number(lo), with_unit(hi, u)),
        (Some(lo), None) => format!("> {}", with_unit(lo, u)),
        (None, Some(hi)) => format!("< {}", with_unit(hi, u)),
        (None, None) => return None,
    })
}

/// Steps that failed without a failed check of their own (same place in the recipe).
pub(crate) fn unexplained_failures(r: &RunReport) -> Vec<&StepRecord> {
    r.steps
        .iter()
        .filter(|s| !s.ok)
        .filter(|s| !r.checks.iter().any(|c| !c.passed && c.origin == s.origin))
        .collect()
}

/// The test case `run`: failing when the run failed beyond its checks; passing when the
/// run has no checks at all (so CI does not see an empty suite); otherwise none.
fn run_case(r: &RunReport) -> Option<TestCase> {
    let unexplained = unexplained_failures(r);
    let (kind, message) = match &r.verdict {
        Verdict::Error(m) => (NonSuccessKind::Error, format!("ERROR: {m}")),
        Verdict::Interrupted(s) => (
            NonSuccessKind::Failure,
            format!(
                "INTERRUPTED: the run was interrupted by {} and the safe stop ran",
                s.describe()
            ),
        ),
        Verdict::Panicked(m) => (
            NonSuccessKind::Error,
            format!("PANIC: internal error ({m}); the safe stop ran after it"),
        ),
        Verdict::Failed if !unexplained.is_empty() || r.checks_failed() == 0 => {
            let first = unexplained
                .first()
                .map(|s| format!(": step {} {}: {}", s.number, s.label, s.detail))
                .unwrap_or_default();
            (NonSuccessKind::Failure, format!("FAILED{first}"))
        }
        Verdict::Failed | Verdict::Passed => {
            if !r.checks.is_empty() {
                return None;
            }
            let mut case = TestCase::new("run", TestCaseStatus::success());
            case.set_classname(r.recipe_path.as_str());
            case.set_time(r.duration);
            case.set_system_out(run_log(r));
            return Some(case);
        }
    };
    let mut description = String::new();
    for s in &unexplained {
        let _ = writeln!(
            description,
            "step {} ({}) FAIL {}: {} at {}",
            s.number, s.phase, s.label, s.detail, s.origin
        );
    }
    for note in &r.safe_stop {
        let _ = writeln!(description, "safe stop: {note}");
    }
    let mut status = TestCaseStatus::non_success(kind);
    status.set_message(message);
    status.set_type(r.verdict.word().to_lowercase());
    status.set_description(description);
    let mut case = TestCase::new("run", status);
    case.set_classname(r.recipe_path.as_str());
    case.set_time(r.duration);
    Some(case)
}

/// Every step as the console showed it, then the safe stop and the verdict.
fn run_log(r: &RunReport) -> String {
    let mut s = String::new();
    for step in &r.steps {
        let _ = writeln!(s, "{}", super::console_reporter::step_line(step));
    }
    for line in super::console_reporter::summary_lines(r, false) {
        let _ = writeln!(s, "{line}");
    }
    s
}
