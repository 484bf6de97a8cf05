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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::markup_check::{check_markup, unescape, Element};
    use crate::report::sample_report::{error_report, passed_report};

    fn parse(xml: &str) -> Vec<Element> {
        assert!(
            xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>"),
            "{xml}"
        );
        check_markup(xml, &[]).unwrap_or_else(|e| panic!("{e}\n{xml}"))
    }

    /// The structure of the common JUnit schema: testsuites > testsuite[name, tests,
    /// failures, errors, time] > testcase[name, classname, time] > failure|error[message].
    fn check_schema(elements: &[Element]) {
        assert_eq!(elements[0].name, "testsuites");
        for e in elements {
            let (parent, required): (&[&str], &[&str]) = match e.name.as_str() {
                "testsuites" => (&[], &["tests", "failures", "errors"]),
                "testsuite" => (&["testsuites"], &["name", "tests", "failures", "errors", "time"]),
                "properties" => (&["testsuite", "testcase"], &[]),
                "property" => (&["properties"], &["name", "value"]),
                "testcase" => (&["testsuite"], &["name", "classname", "time"]),
                "failure" | "error" => (&["testcase"], &["message", "type"]),
                "system-out" | "system-err" => (&["testsuite", "testcase"], &[]),
                other => panic!("element <{other}> is not in the JUnit schema"),
            };
            if parent.is_empty() {
                assert!(e.ancestors.is_empty());
            } else {
                assert!(
                    parent.iter().any(|p| e.parent_is(p)),
                    "<{}> inside {:?}",
                    e.name,
                    e.ancestors
                );
            }
            for a in required {
                assert!(e.attr(a).is_some(), "<{}> lacks {a}", e.name);
            }
            if let Some(t) = e.attr("time") {
                assert!(t.parse::<f64>().is_ok(), "time {t}");
            }
        }
        // Counts agree with the test cases.
        let suite = elements.iter().find(|e| e.name == "testsuite").unwrap();
        let cases = elements.iter().filter(|e| e.name == "testcase").count();
        let failures = elements.iter().filter(|e| e.name == "failure").count();
        let errors = elements.iter().filter(|e| e.name == "error").count();
        assert_eq!(suite.attr("tests"), Some(cases.to_string().as_str()));
        assert_eq!(suite.attr("failures"), Some(failures.to_string().as_str()));
        assert_eq!(suite.attr("errors"), Some(errors.to_string().as_str()));
    }

    fn property<'a>(elements: &'a [Element], case: &str, name: &str) -> Option<&'a str> {
        let start = elements
            .iter()
            .position(|e| e.name == "testcase" && e.attr("name").map(unescape).as_deref() == Some(case))?;
        elements[start + 1..]
            .iter()
            .take_while(|e| e.name != "testcase")
            .find(|e| e.name == "property" && e.attr("name") == Some(name))
            .and_then(|e| e.attr("value"))
    }

    #[test]
    fn a_passed_run_is_one_suite_with_a_case_per_check() {
        let xml = junit_xml(&passed_report());
        let e = parse(&xml);
        check_schema(&e);
        assert!(xml.contains("tests=\"2\""), "{xml}");
        assert!(xml.contains("failures=\"0\""));
        let suite = e.iter().find(|e| e.name == "testsuite").unwrap();
        assert_eq!(
            unescape(suite.attr("name").unwrap()),
            "Spindle <run-in> & \"test\""
        );
        assert_eq!(suite.attr("time"), Some("66.250"));
        assert_eq!(suite.attr("timestamp"), Some("2024-06-10T06:13:20"));
        let cases: Vec<&Element> = e.iter().filter(|e| e.name == "testcase").collect();
        assert_eq!(
            unescape(cases[0].attr("name").unwrap()),
            "speed_actual mean near 6000 rpm ± 0.5 %"
        );
        assert_eq!(cases[0].attr("classname"), Some("recipes/run-in.yaml"));
        assert_eq!(cases[0].attr("time"), Some("1.500"));
        assert_eq!(cases[1].attr("name"), Some("wait until state operation_enabled"));
        let first = "speed_actual mean near 6000 rpm ± 0.5 %";
        assert_eq!(property(&e, first, "measured"), Some("6000.1"));
        assert_eq!(property(&e, first, "unit"), Some("rpm"));
        assert_eq!(property(&e, first, "low"), Some("5970"));
        assert_eq!(property(&e, first, "high"), Some("6030"));
        assert_eq!(property(&e, first, "origin"), Some("recipes/run-in.yaml:20:5"));
        let out = e
            .iter()
            .find(|e| e.name == "system-out" && e.parent_is("testcase"))
            .unwrap();
        assert!(out.text.contains("measured: 6000.1 rpm"), "{}", out.text);
        assert!(out.text.contains("limits: 5970 .. 6030 rpm"));
        let props: Vec<(&str, &str)> = e
            .iter()
            .filter(|p| p.name == "property" && p.ancestors.len() == 3)
            .map(|p| (p.attr("name").unwrap(), p.attr("value").unwrap()))
            .collect();
        assert!(props.contains(&("param.speed", "6000 rpm")), "{props:?}");
        assert!(props.contains(&("verdict", "PASSED")));
        assert!(props.contains(&("started_at_utc", "2024-06-10T06:13:20Z")));
        assert!(props.contains(&("final_state", "switched on")));
        let log = e
            .iter()
            .find(|e| e.name == "system-out" && e.parent_is("testsuite"))
            .unwrap();
        assert!(
            log.text.contains("safe stop: finally: disable_operation ran"),
            "{}",
            log.text
        );
        assert!(!xml.contains("<failure") && !xml.contains("<error"));
    }

    #[test]
    fn failed_checks_and_errors_are_failures_ci_sees() {
        let xml = junit_xml(&error_report());
        let e = parse(&xml);
        check_schema(&e);
        assert!(
            xml.contains("tests=\"2\" skipped=\"0\" failures=\"1\" errors=\"1\""),
            "{xml}"
        );
        let failure = e.iter().find(|e| e.name == "failure").unwrap();
        assert_eq!(
            unescape(failure.attr("message").unwrap()),
            "mean 5800 rpm; limits 5970 .. 6030 rpm"
        );
        assert_eq!(failure.attr("type"), Some("expect"));
        assert!(failure.text.contains("measured: 5800 rpm"), "{}", failure.text);
        let run = e
            .iter()
            .find(|e| e.name == "testcase" && e.attr("name") == Some("run"))
            .unwrap();
        assert_eq!(run.attr("classname"), Some("recipes/accept.yaml"));
        let error = e.iter().find(|e| e.name == "error").unwrap();
        assert_eq!(
            unescape(error.attr("message").unwrap()),
            "ERROR: no reply within 100 ms from drive 2 <port>"
        );
        // The step explained by its failed check is not repeated; the other one is.
        assert!(
            error.text.contains("step 2 (steps) FAIL dwell 10 s"),
            "{}",
            error.text
        );
        assert!(!error.text.contains("step 1 "), "{}", error.text);
        assert!(error.text.contains("safe stop: the safety net"));
        // The check name with markup characters is escaped.
        assert!(xml.contains("name=\"speed &amp; &lt;mean&gt;\""), "{xml}");
    }

    #[test]
    fn interrupted_and_checkless_runs() {
        let mut r = passed_report();
        r.checks.clear();
        let xml = junit_xml(&r);
        check_schema(&parse(&xml));
        assert!(xml.contains("<testcase name=\"run\""), "{xml}");
        assert!(xml.contains("tests=\"1\" skipped=\"0\" failures=\"0\""), "{xml}");

        r.verdict = Verdict::Interrupted(crate::stop_request::StopSignal::INT);
        r.steps[2].ok = false;
        r.steps[2].detail = "interrupted".into();
        let xml = junit_xml(&r);
        let e = parse(&xml);
        check_schema(&e);
        let failure = e.iter().find(|e| e.name == "failure").unwrap();
        assert!(failure.attr("message").unwrap().starts_with("INTERRUPTED"));
        assert!(failure.text.contains("sample speed_actual"), "{}", failure.text);

        // Failed without a failed check (e.g. a step refused by the drive).
        r.verdict = Verdict::Failed;
        let xml = junit_xml(&r);
        let e = parse(&xml);
        check_schema(&e);
        let failure = e.iter().find(|e| e.name == "failure").unwrap();
        assert_eq!(
            failure.attr("message"),
            Some("FAILED: step 3 sample speed_actual every 100 ms for 60 s: interrupted")
        );
    }

    #[test]
    fn written_atomically() {
        let dir = std::env::temp_dir().join(format!("drivescript-junit-{}", std::process::id()));
        let path = dir.join("ci/junit.xml");
        write_junit(&error_report(), &path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, junit_xml(&error_report()));
        assert!(!dir.join("ci/junit.xml.tmp").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
