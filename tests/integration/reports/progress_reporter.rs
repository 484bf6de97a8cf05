//! The live progress line on a terminal: the same permanent lines as the console reporter,
//! and a redrawn line with the running step, its time and the live values.

use super::sample_reports::{passed_report, speed_check, step};
use crate::support::assert_has;
use drivescript::report::{ConsoleReporter, ProgressReporter};
use drivescript::session::{RunInfo, RunObserver, StepInfo, StepOrigin, UnitIdentity};
use indicatif::ProgressBar;
use std::time::Duration;

fn recipe() -> RunInfo {
    RunInfo {
        kind: "recipe",
        name: "Spindle run-in".into(),
        path: "recipes/run-in.yaml".into(),
        params: vec![("speed".into(), "6000 rpm".into())],
        unit: UnitIdentity::default(),
        text_sha256: None,
    }
}

fn info(number: &str, label: &str, phase: &'static str, container: bool) -> StepInfo {
    StepInfo {
        number: number.into(),
        label: label.into(),
        origin: StepOrigin {
            path: "recipes/run-in.yaml".into(),
            line: 7,
            column: 5,
        },
        phase,
        container,
    }
}

/// The same events to any observer.
fn play(o: &mut dyn RunObserver) {
    let report = passed_report();
    o.run_started(&recipe(), "sd2 (simulated)");
    // A serial number scanned at an operator step during the run.
    o.unit_identified(&UnitIdentity {
        serial: Some("SP-104233".into()),
        ..UnitIdentity::default()
    });
    o.step_started(&info("1", "repeat 3 times", "steps", true));
    o.step_progress("1", Duration::ZERO, None, "iteration 1 of 3");
    o.step_started(&info("1.1", "dwell 60 s", "steps", false));
    o.step_progress("1.1", Duration::from_secs(12), Some(Duration::from_secs(60)), "");
    o.step_finished(&step("1.1", "dwell 60 s", true, "", 0, "steps"));
    o.step_finished(&step(
        "1",
        "repeat 3 times",
        true,
        "3 iteration(s) in 180 s",
        0,
        "steps",
    ));
    o.check(&speed_check(
        "speed_actual mean near 6000 rpm ± 0.5 %",
        6000.1,
        true,
    ));
    o.message("speed_actual = 6000.1 rpm");
    o.step_started(&info("finally.1", "dwell 60 s", "finally", false));
    o.step_finished(&step(
        "finally.1",
        "disable_operation",
        false,
        "no reply",
        0,
        "finally",
    ));
    o.run_finished(&report);
}

#[test]
fn permanent_lines_are_the_console_lines() {
    let mut console = ConsoleReporter::new(Vec::new(), true);
    play(&mut console);
    let mut progress = ProgressReporter::new(Vec::new(), ProgressBar::hidden(), true);
    play(&mut progress);
    let want = String::from_utf8(console.into_inner()).unwrap();
    let got = String::from_utf8(progress.into_inner()).unwrap();
    assert_eq!(got, want);
    // And they say what happened.
    assert!(
        got.starts_with("recipe  Spindle run-in (recipes/run-in.yaml)\n"),
        "{got}"
    );
    assert_has(
        &got,
        &["     1  ...   repeat 3 times\n", "   1.1  ok    dwell 60 s\n"],
    );
    assert!(got.contains("        PASS  speed_actual mean near 6000 rpm ± 0.5 %: mean 6000.1 rpm"));
    assert_has(&got, &["finally 1  FAIL  disable_operation  no reply\n"]);
    assert_has(&got, &["        unit: serial SP-104233\n"]);
    // The step lines of the report the summary is made from: four steps and a finally.
    assert!(
        got.contains(
            "PASSED — 5 step(s), 1 check(s) passed, 0 failed, 1 wait(s) met, 1m 6s 250ms of virtual time"
        ),
        "{got}"
    );
}

#[test]
fn the_live_line_shows_step_time_values_and_context() {
    let mut p = ProgressReporter::new(Vec::new(), ProgressBar::hidden(), false).with_width(120);
    p.step_started(&info("4", "repeat 3 times", "steps", true));
    p.step_progress("4", Duration::ZERO, None, "iteration 2 of 3");
    p.step_started(&info("4.1", "dwell 60 s", "steps", false));
    assert_eq!(p.bar().prefix(), "4.1");
    assert_eq!(p.bar().message(), "dwell 60 s [repeat 3 times: iteration 2 of 3]");
    p.step_progress(
        "4.1",
        Duration::from_millis(12_340),
        Some(Duration::from_secs(60)),
        "speed_actual 6001.2 rpm",
    );
    assert_eq!(
        p.bar().message(),
        "12.3 s/1m · speed_actual 6001.2 rpm · dwell 60 s \
         [repeat 3 times: iteration 2 of 3]"
    );
    assert_eq!(p.bar().length(), Some(60_000));
    assert_eq!(p.bar().position(), 12_340);
    // Progress of another step (a stale number) does not overwrite the line.
    p.step_progress("3", Duration::from_secs(1), None, "x");
    assert!(p.bar().message().starts_with("12.3 s/1m"));
    p.step_finished(&step("4.1", "dwell 60 s", true, "", 0, "steps"));
    assert_eq!(p.bar().length(), None);
    assert_eq!(p.bar().message(), "[repeat 3 times: iteration 2 of 3]");
    p.step_finished(&step("4", "repeat 3 times", true, "", 0, "steps"));
    assert_eq!(p.bar().message(), "");
    let out = String::from_utf8(p.into_inner()).unwrap();
    assert_eq!(
        out,
        "     4  ...   repeat 3 times\n   4.1  ok    dwell 60 s\n     4  ok    repeat 3 times\n"
    );
}
