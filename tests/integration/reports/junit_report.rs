//! `--junit`: the run report as JUnit XML, read back with a real XML parser and checked
//! against the structure of the common JUnit schema.

use super::markup::{case_property, junit, xml_elements, XML_DECLARATION};
use super::sample_reports::{error_report, passed_report};
use drivescript::report::{junit_xml, write_junit};
use drivescript::session::Verdict;
use drivescript::stop_request::StopSignal;
use roxmltree::Document;

fn parse(xml: &str) -> Document<'_> {
    junit(xml).unwrap_or_else(|e| panic!("{e}\n{xml}"))
}

#[test]
fn a_passed_run_is_one_suite_with_a_case_per_check() {
    let xml = junit_xml(&passed_report());
    let doc = parse(&xml);
    assert!(xml.contains("tests=\"2\""), "{xml}");
    assert!(xml.contains("failures=\"0\""));
    let suites = xml_elements(&doc, "testsuite");
    assert_eq!(suites.len(), 1);
    let suite = suites[0];
    assert_eq!(suite.attribute("name"), Some("Spindle <run-in> & \"test\""));
    assert_eq!(suite.attribute("tests"), Some("2"));
    assert_eq!(suite.attribute("failures"), Some("0"));
    assert_eq!(suite.attribute("time"), Some("66.250"));
    assert_eq!(suite.attribute("timestamp"), Some("2024-06-10T06:13:20"));
    let cases = xml_elements(&doc, "testcase");
    assert_eq!(
        cases[0].attribute("name"),
        Some("speed_actual mean near 6000 rpm ± 0.5 %")
    );
    assert_eq!(cases[0].attribute("classname"), Some("recipes/run-in.yaml"));
    assert_eq!(cases[0].attribute("time"), Some("1.500"));
    assert_eq!(
        cases[1].attribute("name"),
        Some("wait until state operation_enabled")
    );
    let first = "speed_actual mean near 6000 rpm ± 0.5 %";
    assert_eq!(case_property(&doc, first, "measured"), Some("6000.1"));
    assert_eq!(case_property(&doc, first, "unit"), Some("rpm"));
    assert_eq!(case_property(&doc, first, "low"), Some("5970"));
    assert_eq!(case_property(&doc, first, "high"), Some("6030"));
    assert_eq!(
        case_property(&doc, first, "origin"),
        Some("recipes/run-in.yaml:20:5")
    );
    let out = cases[0]
        .children()
        .find(|n| n.has_tag_name("system-out"))
        .and_then(|n| n.text())
        .unwrap();
    assert!(out.contains("measured: 6000.1 rpm"), "{out}");
    assert!(out.contains("limits: 5970 .. 6030 rpm"));
    let props: Vec<(&str, &str)> = suite
        .children()
        .filter(|n| n.has_tag_name("properties"))
        .flat_map(|p| p.children())
        .filter(|p| p.has_tag_name("property"))
        .map(|p| (p.attribute("name").unwrap(), p.attribute("value").unwrap()))
        .collect();
    assert!(props.contains(&("param.speed", "6000 rpm")), "{props:?}");
    assert!(props.contains(&("verdict", "PASSED")));
    assert!(props.contains(&("started_at_utc", "2024-06-10T06:13:20Z")));
    assert!(props.contains(&("final_state", "switched on")));
    let log = suite
        .children()
        .find(|n| n.has_tag_name("system-out"))
        .and_then(|n| n.text())
        .unwrap();
    assert!(log.contains("safe stop: finally: disable_operation ran"), "{log}");
    assert!(!xml.contains("<failure") && !xml.contains("<error"));
    assert!(xml_elements(&doc, "failure").is_empty() && xml_elements(&doc, "error").is_empty());
}

#[test]
fn failed_checks_and_errors_are_failures_ci_sees() {
    let xml = junit_xml(&error_report());
    let doc = parse(&xml);
    assert!(
        xml.contains("tests=\"2\" skipped=\"0\" failures=\"1\" errors=\"1\""),
        "{xml}"
    );
    let failure = xml_elements(&doc, "failure")[0];
    assert_eq!(
        failure.attribute("message"),
        Some("mean 5800 rpm; limits 5970 .. 6030 rpm")
    );
    assert_eq!(failure.attribute("type"), Some("expect"));
    let failure_text = failure.text().unwrap_or("");
    assert!(failure_text.contains("measured: 5800 rpm"), "{failure_text}");
    let run = xml_elements(&doc, "testcase")
        .into_iter()
        .find(|c| c.attribute("name") == Some("run"))
        .unwrap();
    assert_eq!(run.attribute("classname"), Some("recipes/accept.yaml"));
    let error = xml_elements(&doc, "error")[0];
    assert_eq!(error.parent_element(), Some(run));
    assert_eq!(
        error.attribute("message"),
        Some("ERROR: no reply within 100 ms from drive 2 <port>")
    );
    // The step explained by its failed check is not repeated; the other one is.
    let error_text = error.text().unwrap_or("");
    assert!(
        error_text.contains("step 2 (steps) FAIL dwell 10 s"),
        "{error_text}"
    );
    assert!(!error_text.contains("step 1 "), "{error_text}");
    assert!(error_text.contains("safe stop: the safety net"));
    // The check name with markup characters is escaped.
    assert!(xml.contains("name=\"speed &amp; &lt;mean&gt;\""), "{xml}");
    assert_eq!(
        xml_elements(&doc, "testcase")[0].attribute("name"),
        Some("speed & <mean>")
    );
}

#[test]
fn interrupted_and_checkless_runs() {
    let mut r = passed_report();
    r.checks.clear();
    let xml = junit_xml(&r);
    let doc = parse(&xml);
    assert!(xml.contains("<testcase name=\"run\""), "{xml}");
    assert!(xml.contains("tests=\"1\" skipped=\"0\" failures=\"0\""), "{xml}");
    assert_eq!(xml_elements(&doc, "testcase")[0].attribute("name"), Some("run"));

    r.verdict = Verdict::Interrupted(StopSignal::INT);
    r.steps[2].ok = false;
    r.steps[2].detail = "interrupted".into();
    let xml = junit_xml(&r);
    let doc = parse(&xml);
    let failure = xml_elements(&doc, "failure")[0];
    assert!(failure.attribute("message").unwrap().starts_with("INTERRUPTED"));
    let failure_text = failure.text().unwrap_or("");
    assert!(failure_text.contains("sample speed_actual"), "{failure_text}");

    // Failed without a failed check (e.g. a step refused by the drive).
    r.verdict = Verdict::Failed;
    let xml = junit_xml(&r);
    let doc = parse(&xml);
    let failure = xml_elements(&doc, "failure")[0];
    assert_eq!(
        failure.attribute("message"),
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

/// The checks above would notice a broken file: each of these edits of a good one is
/// refused, saying why.
#[test]
fn a_broken_junit_file_is_refused() {
    let xml = junit_xml(&error_report());
    parse(&xml);
    for (broken, why) in [
        (xml.replacen("&lt;mean&gt;", "<mean>", 1), "not well-formed"),
        (xml.replacen("speed &amp;", "speed &", 1), "not well-formed"),
        (xml.replacen("</testcase>", "", 1), "not well-formed"),
        (
            xml.replacen(" classname=\"recipes/accept.yaml\"", "", 1),
            "<testcase> lacks classname",
        ),
        (
            xml.replacen(" message=\"mean 5800 rpm", " note=\"mean 5800 rpm", 1),
            "<failure> lacks message",
        ),
        (
            xml.replacen(
                "name=\"Acceptance\" tests=\"2\"",
                "name=\"Acceptance\" tests=\"3\"",
                1,
            ),
            "testsuite tests=Some(\"3\"), but it holds 2",
        ),
        (
            xml.replacen("errors=\"1\"", "errors=\"0\"", 1),
            "errors=Some(\"0\")",
        ),
        (
            xml.replacen("time=\"9.000\"", "time=\"9 s\"", 1),
            "is not a number",
        ),
        (
            xml.replacen("<properties>", "<props/><properties>", 1),
            "element <props> is not in the JUnit schema",
        ),
        (xml.replacen(XML_DECLARATION, "", 1), "XML declaration"),
    ] {
        assert_ne!(broken, xml, "the edit for {why:?} changed nothing");
        let refused = junit(&broken).map(|_| ()).unwrap_err();
        assert!(refused.contains(why), "{why:?}: {refused}");
    }
}
