//! `--junit`: the run report as JUnit XML, read back with a real XML parser, held to the
//! structure Jenkins' junit-10.xsd and Surefire accept, and validated with `xmllint`
//! against the vendored `tests/junit-10.xsd` and `tests/surefire-test-report-3.0.xsd`
//! where xmllint is installed.

use super::markup::{case_out, junit, junit_xsd, xml_elements, XML_DECLARATION};
use super::sample_reports::{check, error_report, key_of, origin, passed_report, speed_check};
use crate::support::{assert_has, assert_lacks};
use drivescript::report::{junit_not_run, junit_unfinished, junit_xml, write_junit};
use drivescript::session::{CheckResult, PlannedCheck, Verdict};
use drivescript::stop_request::StopSignal;
use roxmltree::Document;

fn parse(xml: &str) -> Document<'_> {
    junit(xml).unwrap_or_else(|e| panic!("{e}\n{xml}"))
}

fn names<'a>(doc: &'a Document) -> Vec<&'a str> {
    xml_elements(doc, "testcase")
        .iter()
        .filter_map(|c| c.attribute("name"))
        .collect()
}

fn planned(
    name: &str,
    object: Option<&str>,
    statistic: Option<&str>,
    stage: &str,
    line: usize,
) -> PlannedCheck {
    PlannedCheck {
        name: name.into(),
        key: key_of(name),
        object: object.map(Into::into),
        statistic: statistic.map(Into::into),
        stage: stage.into(),
        step: line.to_string(),
        origin: origin(line),
    }
}

#[test]
fn a_passed_run_is_one_suite_with_a_case_per_check_and_the_safe_stop() {
    let xml = junit_xml(&passed_report(), &[]);
    let doc = parse(&xml);
    let suites = xml_elements(&doc, "testsuite");
    assert_eq!(suites.len(), 1);
    let suite = suites[0];
    assert_eq!(suite.attribute("name"), Some("Spindle <run-in> & \"test\""));
    assert_eq!(suite.attribute("tests"), Some("3"));
    assert_eq!(suite.attribute("failures"), Some("0"));
    assert_eq!(suite.attribute("skipped"), Some("0"));
    assert_eq!(suite.attribute("time"), Some("66.250"));
    // Names without limit values, so CI history survives a changed parameter.
    assert_eq!(
        names(&doc),
        vec![
            "speed_actual mean near",
            "wait until state operation_enabled",
            "safe stop"
        ]
    );
    let case = xml_elements(&doc, "testcase")[0];
    // Jenkins splits a classname at its last dot; the recipe name has none to split.
    assert_eq!(case.attribute("classname"), Some("Spindle <run-in> & \"test\""));
    assert_eq!(case.attribute("time"), Some("1.500"));
    let out = case_out(&doc, "speed_actual mean near").unwrap();
    assert_has(
        out,
        &[
            "measured: 6000.1 rpm",
            "limits: 5970 .. 6030 rpm",
            "check: speed_actual mean near 6000 rpm ± 0.5 % at recipes/run-in.yaml:20:5",
            "step: 4",
        ],
    );
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
    let log = case_out(&doc, "safe stop").unwrap();
    assert_has(log, &["safe stop: finally: disable_operation ran"]);
    assert!(xml_elements(&doc, "failure").is_empty() && xml_elements(&doc, "error").is_empty());
}

#[test]
fn names_are_unique_and_carry_the_stage() {
    let mut r = passed_report();
    let stage = |n: u32| CheckResult {
        stage: format!("repeat 2 times #{n} / Stage 2"),
        ..speed_check("speed_actual mean near 12000 rpm ± 0.5 %", 12000.0, true)
    };
    r.checks = vec![
        stage(1),
        stage(2),
        check("Spindle is quiet", true, ""),
        check("Spindle is quiet", true, ""),
    ];
    let xml = junit_xml(&r, &[]);
    let doc = parse(&xml);
    assert_eq!(
        names(&doc),
        vec![
            "repeat 2 times #1 / Stage 2 / speed_actual mean near",
            "repeat 2 times #2 / Stage 2 / speed_actual mean near",
            "Spindle is quiet",
            "Spindle is quiet (2)",
            "safe stop",
        ]
    );
}

/// The case names of `tests/cases/ok/run_in` run to its end, or interrupted by Ctrl-C at
/// `interrupt_at` (virtual time), sorted.
fn run_in_case_names(interrupt_at: Option<std::time::Duration>) -> Vec<String> {
    let dir = std::env::temp_dir().join(format!(
        "drivescript-junit-names-{}-{}",
        std::process::id(),
        interrupt_at.map_or(0, |d| d.as_secs())
    ));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let junit = dir.join("junit.xml");
    let recipe = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/cases/ok/run_in/recipe.yaml");
    let mut run = crate::support::InProcessRun::new(recipe);
    run.output_dir = dir.clone();
    run.outputs.junit = Some(junit.clone());
    if let Some(at) = interrupt_at {
        run.stop.schedule(at, StopSignal::INT);
    }
    let (result, output) = run.run();
    let want = if interrupt_at.is_some() { 130 } else { 0 };
    assert_eq!(result.exit_code, want, "{output}");
    let xml = std::fs::read_to_string(&junit).expect("junit written");
    let doc = parse(&xml);
    let mut names: Vec<String> = names(&doc).into_iter().map(str::to_string).collect();
    names.retain(|n| n != "run");
    names.sort();
    let _ = std::fs::remove_dir_all(&dir);
    names
}

/// A CI server follows each check by its name: an interrupted run names every check as
/// the complete run does, the passes it never reached included, and the two checks that
/// share a name in each pass are told apart by their step, whichever the run reached.
#[test]
fn an_interrupted_run_names_its_cases_as_a_complete_run_does() {
    let complete = run_in_case_names(None);
    let stage = "repeat 2 times (7 steps)";
    for want in [
        format!("{stage} #1 / wait until speed_actual near"),
        format!("{stage} #1 / wait until speed_actual near (step 2.5)"),
        format!("{stage} #2 / speed_actual mean near"),
        "wait until speed_actual below".to_string(),
    ] {
        assert!(complete.contains(&want), "{want} not in {complete:#?}");
    }
    // In the first pass's dwell, and in the second pass's dwell.
    for minutes in [5, 40] {
        let at = std::time::Duration::from_secs(minutes * 60);
        assert_eq!(
            run_in_case_names(Some(at)),
            complete,
            "interrupted at {minutes} min"
        );
    }
}

#[test]
fn failed_checks_and_errors_are_failures_ci_sees() {
    let xml = junit_xml(&error_report(), &[]);
    let doc = parse(&xml);
    assert_has(&xml, &["tests=\"3\" failures=\"2\" errors=\"1\" skipped=\"0\""]);
    let failure = xml_elements(&doc, "failure")[0];
    assert_eq!(
        failure.attribute("message"),
        Some("mean 5800 rpm; limits 5970 .. 6030 rpm")
    );
    assert_eq!(failure.attribute("type"), Some("expect"));
    assert!(failure.text().unwrap_or("").contains("measured: 5800 rpm"));
    let run = xml_elements(&doc, "testcase")
        .into_iter()
        .find(|c| c.attribute("name") == Some("run"))
        .unwrap();
    let error = xml_elements(&doc, "error")[0];
    assert_eq!(error.parent_element(), Some(run));
    assert_eq!(
        error.attribute("message"),
        Some("ERROR: no reply within 100 ms from drive 2 <port>")
    );
    // The step explained by its failed check is not repeated; the other one is.
    let error_text = error.text().unwrap_or("");
    assert_has(error_text, &["step 2 (steps) FAIL dwell 10 s"]);
    assert_lacks(error_text, &["step 1 "]);
    assert!(error_text.contains("safe stop: the safety net"));
    // The unconfirmed safe stop is a failure of its own.
    let stop = xml_elements(&doc, "failure")[1];
    assert!(stop
        .attribute("message")
        .unwrap()
        .starts_with("CHECK THE DRIVE BY HAND"));
    // The check name with markup characters is escaped.
    assert_has(&xml, &["name=\"speed &amp; &lt;mean&gt;\""]);
}

#[test]
fn checks_not_reached_are_skipped() {
    let r = error_report();
    let planned = [
        // Answered by the failed check (same place, same name).
        planned("speed & <mean>", Some("speed_actual"), Some("mean"), "", 11),
        planned(
            "current_actual max below 5 A",
            Some("current_actual"),
            Some("max"),
            "Stage 3",
            30,
        ),
    ];
    let xml = junit_xml(&r, &planned);
    let doc = parse(&xml);
    assert_has(&xml, &["tests=\"4\" failures=\"2\" errors=\"1\" skipped=\"1\""]);
    let skipped = xml_elements(&doc, "skipped");
    assert_eq!(skipped.len(), 1);
    assert_eq!(
        skipped[0].parent_element().and_then(|c| c.attribute("name")),
        Some("Stage 3 / current_actual max below")
    );
    assert_eq!(
        skipped[0].attribute("message"),
        Some("not reached: the run ended early (ERROR)")
    );
}

#[test]
fn interrupted_and_checkless_runs() {
    let mut r = passed_report();
    r.checks.clear();
    let xml = junit_xml(&r, &[]);
    let doc = parse(&xml);
    assert_eq!(names(&doc), vec!["safe stop"]);

    r.verdict = Verdict::Interrupted(StopSignal::INT);
    r.steps[2].ok = false;
    r.steps[2].detail = "interrupted".into();
    let xml = junit_xml(&r, &[]);
    let doc = parse(&xml);
    let failure = xml_elements(&doc, "failure")[0];
    assert!(failure.attribute("message").unwrap().starts_with("INTERRUPTED"));
    assert!(failure.text().unwrap_or("").contains("sample speed_actual"));

    // Failed without a failed check (e.g. a step refused by the drive).
    r.verdict = Verdict::Failed;
    let xml = junit_xml(&r, &[]);
    let doc = parse(&xml);
    let failure = xml_elements(&doc, "failure")[0];
    assert_eq!(
        failure.attribute("message"),
        Some("FAILED: step 3 sample speed_actual every 100 ms for 60 s: interrupted")
    );
}

/// Every kind of JUnit file the tool writes passes `xmllint --schema` with Jenkins'
/// junit-10.xsd, and its suite with Surefire's schema.
#[test]
fn every_junit_file_is_valid_against_jenkins_and_surefire_schemas() {
    let mut interrupted = passed_report();
    interrupted.verdict = Verdict::Interrupted(StopSignal::TERM);
    let planned = [planned(
        "wait until state operation_enabled",
        None,
        None,
        "Stage <1>",
        40,
    )];
    let files = [
        junit_xml(&passed_report(), &[]),
        junit_xml(&error_report(), &planned),
        junit_xml(&interrupted, &planned),
        junit_unfinished("Run <in>", "recipes/x.yaml"),
        junit_not_run(
            "Run",
            "recipes/x.yaml",
            "communication",
            "error: no reply\nfrom drive 4",
            &planned,
        ),
    ];
    for xml in &files {
        parse(xml);
        match junit_xsd(xml) {
            None => crate::support::tool_missing("xmllint is not installed: only the structural check ran"),
            Some(result) => result.unwrap_or_else(|e| panic!("{e}\n{xml}")),
        }
    }
    // The schema check can fail: what the report wrote before (properties inside a test
    // case, `skipped` on testsuites) is refused.
    let old = files[0].replacen(
        "<testsuites name=\"drivescript\"",
        "<testsuites skipped=\"0\" name=\"drivescript\"",
        1,
    );
    if let Some(result) = junit_xsd(&old) {
        assert!(result.unwrap_err().contains("skipped"));
    }
}

#[test]
fn written_atomically() {
    let dir = std::env::temp_dir().join(format!("drivescript-junit-{}", std::process::id()));
    let path = dir.join("ci/junit.xml");
    write_junit(&error_report(), &[], &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text, junit_xml(&error_report(), &[]));
    assert!(!dir.join("ci/junit.xml.tmp").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The checks above would notice a broken file: each of these edits of a good one is
/// refused, saying why.
#[test]
fn a_broken_junit_file_is_refused() {
    let xml = junit_xml(&error_report(), &[]);
    parse(&xml);
    for (broken, why) in [
        (xml.replacen("&lt;mean&gt;", "<mean>", 1), "not well-formed"),
        (xml.replacen("speed &amp;", "speed &", 1), "not well-formed"),
        (xml.replacen("</testcase>", "", 1), "not well-formed"),
        (
            xml.replacen(" classname=\"Acceptance\"", "", 1),
            "<testcase> lacks classname",
        ),
        (
            xml.replacen(" message=\"mean 5800 rpm", " note=\"mean 5800 rpm", 1),
            "<failure> lacks message",
        ),
        (
            xml.replacen(
                "name=\"Acceptance\" tests=\"3\"",
                "name=\"Acceptance\" tests=\"4\"",
                1,
            ),
            "testsuite tests=Some(\"4\"), but it holds 3",
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
        (
            xml.replacen("time=\"9.000\">", "time=\"9.000\" timestamp=\"2024\">", 1),
            "attribute timestamp outside the schemas",
        ),
        (
            xml.replacen("</testsuite>", "<system-out>log</system-out></testsuite>", 1),
            "<system-out> inside Some(\"testsuite\")",
        ),
        (xml.replacen(XML_DECLARATION, "", 1), "XML declaration"),
    ] {
        assert_ne!(broken, xml, "the edit for {why:?} changed nothing");
        let refused = junit(&broken).map(|_| ()).unwrap_err();
        assert!(refused.contains(why), "{why:?}: {refused}");
    }
}

/// A pass outside its warning band stays a passing case (CI must not go red) and says
/// MARGINAL in its output.
#[test]
fn a_marginal_pass_is_a_passing_case_that_says_so() {
    let mut r = passed_report();
    r.checks[0].marginal = true;
    let xml = junit_xml(&r, &[]);
    let doc = parse(&xml);
    let suite = xml_elements(&doc, "testsuite")[0];
    assert_eq!(suite.attribute("failures"), Some("0"));
    assert_has(
        case_out(&doc, "speed_actual mean near").unwrap_or_default(),
        &["MARGINAL: passed outside the warning band"],
    );
    r.checks[0].marginal = false;
    let again = junit_xml(&r, &[]);
    assert_lacks(
        case_out(&parse(&again), "speed_actual mean near").unwrap_or_default(),
        &["MARGINAL"],
    );
}

/// A failure of an attempt that was tried again stays in the file as a skipped case that
/// says so; it does not fail the suite.
#[test]
fn a_retried_failure_is_kept_as_skipped() {
    let mut r = passed_report();
    r.checks[0].passed = false;
    r.checks[0].retried = true;
    let xml = junit_xml(&r, &[]);
    let doc = parse(&xml);
    let suite = xml_elements(&doc, "testsuite")[0];
    assert_eq!(suite.attribute("failures"), Some("0"));
    assert_eq!(suite.attribute("skipped"), Some("1"));
    assert_has(&xml, &["RETRIED: failed in an attempt that was tried again"]);
    r.checks[0].retried = false;
    let doc = junit_xml(&r, &[]);
    assert_eq!(
        xml_elements(&parse(&doc), "testsuite")[0].attribute("failures"),
        Some("1")
    );
}
