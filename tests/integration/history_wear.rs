//! The checks a spindle maker watches for wear, compared with the unit's last passed run
//! against a real SQLite store: a coast-down time that shrinks from one test to the next
//! (`--sim coast-rate=…` changes it between runs, in virtual time) and a vibration value
//! typed in by hand that creeps up (answered with `--answer` and `--answers`). The first
//! run without history passes or fails as the recipe says, a second within the limits
//! passes, a third beyond them fails naming the reference in console, JUnit, HTML, the
//! store, `results show` and `results trend`; the same from a script. A stop during the
//! coast-down or at the question still runs the verified safe stop, makes no comparison,
//! and the store is never waited for on the way to the stop.

use crate::history::{ended_reading_a_silent_store, interrupted_once_shown, run_id};
use crate::support::{
    assert_exit, assert_has, assert_lacks, command, line_with, run_recording as run, scratch, write_changed,
    write_file, InProcessRun,
};
use crate::support_store::{
    scratch_sd2_script, scratch_store, sd2_script, shown_run, FailedComparison, Reports,
};
use drivescript::results::{Locator, StoreHistory};
use drivescript::stop_request::StopSignal;
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

/// Up to speed, then the power stage off: 5800 rpm at the simulated 300 rpm/s take
/// 19.334 s. `COMPARED` is replaced by the comparison.
const COAST: &str = "name: Spindle coast-down
drive: sd2
steps:
  - set: { speed_setpoint: 6000 rpm }
  - go_to: operation_enabled
  - wait_until: { speed_actual: { near: 6000 rpm, within: 1 % } }
  - coast_down:
      from: 5900 rpm
      below: 100 rpm
      expect: { above: 10 s, compared_with_last_pass: COMPARED }
";

const COAST_CHECK: &str = "coast-down from 5900 rpm below 100 rpm above 10 s";

/// The serial scanned, then the vibration on the hand-held meter typed in.
const VIBRATION: &str = "name: Balancing check
drive: sd2
steps:
  - enter_text: { prompt: \"Scan the spindle's serial number\", pattern: \"SP-[0-9]{6}\", sets: serial }
    name: serial
  - go_to: operation_enabled
  - set: { speed_setpoint: 3000 rpm }
  - wait_until: { speed_actual: { near: 3000 rpm, within: 1 % }, timeout: 10 s }
  - enter_value: { prompt: Vibration on the hand-held meter, unit: mm/s, at_most: 2.8 mm/s, compared_with_last_pass: COMPARED }
    name: vibration
";

/// `text` with its comparison; named `name`.
fn recipe(dir: &Path, file: &str, text: &str, name: Option<&str>, compared: &str) -> std::path::PathBuf {
    let mut text = text.replace("COMPARED", compared);
    if let Some(name) = name {
        let first = text.lines().next().unwrap_or_default().to_string();
        text = text.replacen(&first, &format!("name: {name}"), 1);
    }
    write_file(dir, file, &text)
}

/// COAST as `coast.yaml`: within -10 % of the last pass, passing without one.
fn coast_recipe(dir: &Path) -> std::path::PathBuf {
    recipe(
        dir,
        "coast.yaml",
        COAST,
        None,
        "{ at_least: -10 %, without_history: pass }",
    )
}

/// VIBRATION as `vibration.yaml`: at most 0.3 mm/s above the last pass, passing without
/// one.
fn vibration_recipe(dir: &Path) -> std::path::PathBuf {
    recipe(
        dir,
        "vibration.yaml",
        VIBRATION,
        None,
        "{ at_most: 0.3 mm/s, without_history: pass }",
    )
}

/// `text` as `strict.yaml` named `name`, insisting on history: within `limit` of the last
/// pass (`at_most: 10 %`), failing a unit's first run.
fn strict_recipe(dir: &Path, text: &str, name: &str, limit: &str) -> std::path::PathBuf {
    let compared = format!("{{ {limit}, without_history: fail }}");
    recipe(dir, "strict.yaml", text, Some(name), &compared)
}

/// A script's spindle brought up to speed, as COAST does.
const SCRIPT_UP_TO_SPEED: &str = "let d = drive();
d.set(\"speed_setpoint\", 6000.0, \"rpm\");
d.go_to(\"operation_enabled\");
d.wait_until(\"speed_actual\", |v| v > 5950.0, \"10 s\");
";

/// A script's coast-down compared with the last pass as COAST's is.
const SCRIPT_COAST_DOWN: &str = "d.coast_down(\"5900 rpm\", \"100 rpm\", \"10 s\", \"30 s\", #{ at_least: \"-10 %\", without_history: \"pass\" });
";

#[test]
fn a_coast_down_compares_its_time_with_the_units_last_pass() {
    let (dir, store) = &scratch_store("wear-coast-down");
    let percent = coast_recipe(dir);
    let coast = |file: &Path, rate: &str, more: &[&str]| {
        let rate = format!("coast-rate={rate}");
        let mut args = vec!["--fast", "--unit", "serial=SP-1", "--sim", rate.as_str()];
        args.extend_from_slice(more);
        run(file, store, &args)
    };
    let compared = format!("{COAST_CHECK} compared with last pass");
    // The unit's first run: no history, passes as the recipe chooses.
    let first = assert_exit(
        coast(&percent, "300rpm/s", &[]),
        0,
        &[
            "history SP-1: no earlier passed run of `Spindle coast-down`",
            &format!("PASS  {COAST_CHECK}: coast-down took 19.334 s"),
            &format!("PASS  {compared}: no earlier passed run of SP-1 for this recipe: passes as `without_history: pass` says"),
        ],
    );
    let first_id = run_id(&first);
    // A recipe that insists on history fails a unit's first run.
    let strict = strict_recipe(dir, COAST, "Strict coast-down", "at_least: -10 %");
    assert_exit(
        coast(&strict, "300rpm/s", &[]),
        1,
        &[
            &format!("PASS  {COAST_CHECK}: coast-down took 19.334 s"),
            &format!("FAIL  {compared}: no earlier passed run of SP-1 for this recipe: fails as `without_history: fail` says"),
        ],
    );
    // A little more drag: within 10 %, compared with the first run.
    let second = assert_exit(
        coast(&percent, "310rpm/s", &[]),
        0,
        &[
            &format!("history SP-1: compared with its last pass, run {first_id} of 20"),
            &format!("{COAST_CHECK} = 19.334 s"),
            &format!("PASS  {compared}: coast-down time = 18.708 s: -3.235 % against 19.334 s in run {first_id} of 20"),
        ],
    );
    let second_id = run_id(&second);
    // Bearing drag: the time shrinks by a fifth, still above its limit; the comparison
    // fails and names the run it compared with in every report.
    let reports = Reports::in_folder(dir, "drag");
    let drag = format!("coast-down time = 14.5 s: -22.496 % against 18.708 s in run {second_id}");
    let third = assert_exit(
        coast(&percent, "400rpm/s", &reports.args()),
        1,
        &[
            &format!("PASS  {COAST_CHECK}: coast-down took 14.5 s"),
            &format!("FAIL  {compared}: {drag}"),
            "expected a change at least -10 %",
            "coasted to standstill",
            "drive left in ready to switch on at 0 rpm",
            "FAILED",
        ],
    );
    let third_id = run_id(&third);
    reports.assert_both_have(&[&compared, &drag]);
    // The store keeps the change in % with the reference.
    FailedComparison {
        reference_run: &second_id,
        reference_value: 18.708,
        change: -22.496,
        unit: "%",
        limits: (Some(-10.0), None),
        within: 0.001,
    }
    .assert_kept(store, &third_id, &compared);
    assert_has(
        &shown_run(store, &third_id),
        &[&format!("reference: run {second_id} of 20")],
    );
    // The change from run to run, the first without one.
    let trend = command()
        .args([
            "results",
            "trend",
            &compared,
            "--unit",
            "SP-1",
            // The strict recipe's check is another measurement: a trend is of one.
            "--recipe",
            "Spindle coast-down",
            "--simulated",
            "--results",
            store,
        ])
        .output()
        .expect("trend");
    let trend = String::from_utf8_lossy(&trend.stdout).to_string();
    let row = |id: &str| line_with(&trend, id);
    assert!(row(&first_id).contains("PASS"), "{trend}");
    assert!(
        row(&second_id).contains("-3.235") && row(&second_id).contains("PASS"),
        "{trend}"
    );
    assert!(
        row(&third_id).contains("-22.496") && row(&third_id).contains("FAIL"),
        "{trend}"
    );
    // In seconds instead of %, both ends included.
    let seconds = recipe(
        dir,
        "seconds.yaml",
        COAST,
        Some("Coast-down in seconds"),
        "{ at_least: -0.626 s, at_most: 2 s, without_history: pass }",
    );
    assert_exit(coast(&seconds, "300rpm/s", &[]), 0, &[]);
    assert_exit(
        coast(&seconds, "310rpm/s", &[]),
        0,
        &["coast-down time = 18.708 s: -0.625 s against 19.334 s"],
    );
    assert_exit(
        coast(&seconds, "400rpm/s", &[]),
        1,
        &[
            "coast-down time = 14.5 s: -4.209 s against 18.708 s",
            "expected a change between -0.626 s and +2 s",
        ],
    );
}

#[test]
fn a_typed_value_compares_with_the_units_last_pass() {
    let (dir, store) = &scratch_store("wear-vibration");
    let lenient = vibration_recipe(dir);
    let answered = |file: &Path, value: &str| {
        let vibration = format!("vibration={value}");
        let args = ["--fast", "--answer", "serial=SP-104233", "--answer", &vibration];
        run(file, store, &args)
    };
    let question = "Vibration on the hand-held meter";
    let compared = format!("{question} compared with last pass");
    // Answered beforehand, the serial is known at the start: looked up before step 1.
    let (code, first) = answered(&lenient, "1.2");
    assert_eq!(code, 0, "{first}");
    let said = first
        .find("history SP-104233: no earlier passed run of `Balancing check`")
        .unwrap_or_else(|| panic!("the lookup is said:\n{first}"));
    assert!(said < first.find("     1  ").expect("step 1"), "{first}");
    assert_has(
        &first,
        &[
            &format!("PASS  {question}: answered `1.2 mm/s` (given with --answer)"),
            &format!("PASS  {compared}: no earlier passed run of SP-104233 for this recipe: passes as `without_history: pass` says"),
        ],
    );
    let first_id = run_id(&first);
    let strict = strict_recipe(dir, VIBRATION, "Strict balancing check", "at_most: 10 %");
    assert_exit(
        answered(&strict, "1.2"),
        1,
        &[&format!("FAIL  {compared}: no earlier passed run of SP-104233 for this recipe: fails as `without_history: fail` says")],
    );
    // From an answers file: a little more, within 0.3 mm/s.
    let answers = write_file(dir, "answers.yaml", "serial: SP-104233\nvibration: 1.4 mm/s\n");
    let second = assert_exit(
        run(
            &lenient,
            store,
            &["--fast", "--answers", answers.to_str().unwrap()],
        ),
        0,
        &[
            &format!("history SP-104233: compared with its last pass, run {first_id} of 20"),
            &format!("{question} = 1.2 mm/s"),
            &format!("PASS  {compared}: answer = 1.4 mm/s: +0.2 mm/s against 1.2 mm/s in run {first_id}"),
        ],
    );
    let second_id = run_id(&second);
    // Creeping up: still within its limit, but 0.4 mm/s more than last time.
    let creep = format!("answer = 1.8 mm/s: +0.4 mm/s against 1.4 mm/s in run {second_id}");
    let third = assert_exit(
        answered(&lenient, "1.8"),
        1,
        &[
            &format!("PASS  {question}: answered `1.8 mm/s`"),
            &format!("FAIL  {compared}: {creep}"),
            "expected a change at most +0.3 mm/s",
            "FAILED",
        ],
    );
    let third_id = run_id(&third);
    FailedComparison {
        reference_run: &second_id,
        reference_value: 1.4,
        change: 0.4,
        unit: "mm/s",
        limits: (None, Some(0.3)),
        within: 1e-9,
    }
    .assert_kept(store, &third_id, &compared);
}

/// A script's `d.coast_down` and `enter_value` take the same comparison as a map.
#[test]
fn a_scripts_coast_down_and_typed_value_compare_with_the_units_last_pass() {
    let (dir, store) = &scratch_store("wear-script");
    let script = sd2_script(
        dir,
        "wear.rhai",
        "Scripted wear check",
        &format!("{SCRIPT_UP_TO_SPEED}{SCRIPT_COAST_DOWN}let v = enter_value(\"Vibration\", #{{ unit: \"mm/s\", name: \"vibration\", compared_with_last_pass: #{{ at_most: 0.3, without_history: \"pass\" }} }});\n"),
    );
    let scripted = |rate: &str, value: &str| {
        let (rate, value) = (format!("coast-rate={rate}"), format!("vibration={value}"));
        run(
            &script,
            store,
            &[
                "--fast",
                "--unit",
                "serial=SC-1",
                "--sim",
                &rate,
                "--answer",
                &value,
            ],
        )
    };
    let coast = "coast-down from 5900 rpm below 100 rpm between 10 s and 30 s compared with last pass";
    let first = assert_exit(
        scripted("300rpm/s", "1.2"),
        0,
        &[
            &format!("PASS  {coast}: no earlier passed run of SC-1"),
            "PASS  Vibration compared with last pass: no earlier passed run of SC-1",
        ],
    );
    let first_id = run_id(&first);
    assert_exit(
        scripted("400rpm/s", "1.3"),
        1,
        &[
            &format!("FAIL  {coast}: coast-down time = 14.5 s: -25.004 % against 19.334 s in run {first_id}"),
            &format!("PASS  Vibration compared with last pass: answer = 1.3 mm/s: +0.1 mm/s against 1.2 mm/s in run {first_id}"),
        ],
    );
    // A comparison written wrongly is a script error at its call: line 7 of the script
    // (the 2 header lines, the 4 of SCRIPT_UP_TO_SPEED, then SCRIPT_COAST_DOWN).
    let wrong = write_changed(
        dir,
        "wrong.rhai",
        &script,
        "at_least: \"-10 %\", without_history: \"pass\"",
        "at_least: \"-10 %\"",
    );
    let (code, out) = run(
        &wrong,
        store,
        &["--fast", "--unit", "serial=SC-1", "--answer", "vibration=1"],
    );
    assert_ne!(code, 0, "{out}");
    assert_has(
        &out,
        &["coast_down: give `without_history: \"pass\"`", "wrong.rhai:7:3"],
    );
}

/// The recipe `written` makes in the scratch folder `name`, run once through the command
/// line for SP-000009 (with `args`), recorded as the passed run the next compares with;
/// the recipe, the store and that run's id.
fn passed_once(
    name: &str,
    written: fn(&Path) -> std::path::PathBuf,
    args: &[&str],
) -> (std::path::PathBuf, std::path::PathBuf, String) {
    let dir = scratch(name);
    let recipe = written(&dir);
    let store = dir.join("results.sqlite");
    let all = [&["--fast", "--unit", "serial=SP-000009"][..], args].concat();
    let (code, out) = run(&recipe, store.to_str().unwrap(), &all);
    assert_eq!(code, 0, "{out}");
    (recipe, store, run_id(&out))
}

/// `recipe` in this process for SP-000009, reading `store`, with a Ctrl-C at `at` (virtual
/// time).
fn interrupted_at<'a>(recipe: &Path, store: std::path::PathBuf, at: Duration) -> InProcessRun<'a> {
    let mut r = InProcessRun::new(recipe);
    r.operator.unit = vec![("serial".into(), "SP-000009".into())];
    r.history = Some(Arc::new(StoreHistory::new(Locator::Sqlite(store), true)));
    r.stop.schedule(at, StopSignal::INT);
    r
}

/// What every such ending must show: looked up before anything moved, interrupted,
/// stopped and verified, no comparison made, the comparison planned in JUnit (its `case`
/// named by its key) as not reached.
fn assert_stopped_without_a_comparison(
    result: &drivescript::run::RunResult,
    out: &str,
    reference: &str,
    (compared, case): (&str, &str),
) {
    assert_eq!(result.exit_code, 130, "{out}");
    let said = out
        .find(&format!(
            "history SP-000009: compared with its last pass, run {reference}"
        ))
        .unwrap_or_else(|| panic!("looked up at the start:\n{out}"));
    assert!(said < out.find("     1  ").expect("step 1"), "{out}");
    assert_has(out, &["INTERRUPTED: interrupted by Ctrl-C"]);
    assert_lacks(
        out,
        &[
            &format!("PASS  {compared}"),
            &format!("FAIL  {compared}"),
            "NOT confirmed",
        ],
    );
    let report = result.report.as_ref().expect("a report");
    assert!(
        report.checks.iter().all(|c| c.name != compared),
        "{:?}",
        report.checks
    );
    let junit = drivescript::report::junit_document([result.junit.as_ref().expect("a suite")]);
    let case = junit
        .split("<testcase ")
        .find(|c| c.contains(&format!("name=\"{case}\"")))
        .unwrap_or_else(|| panic!("the comparison is a JUnit case:\n{junit}"));
    assert!(case.contains("not reached: the run ended early"), "{case}");
}

/// Ctrl-C while the spindle coasts: the safe stop at once (it still coasts by design).
#[test]
fn a_stop_during_a_compared_coast_down_runs_the_safe_stop_and_no_comparison() {
    let (file, store, reference) = passed_once("wear-coast-ctrl-c", coast_recipe, &[]);
    let (result, out) = interrupted_at(&file, store, Duration::from_secs(10)).run();
    assert_stopped_without_a_comparison(
        &result,
        &out,
        &reference,
        (
            &format!("{COAST_CHECK} compared with last pass"),
            "coast-down from 5900 rpm below 100 rpm compared with last pass",
        ),
    );
    assert_has(
        &out,
        &[
            &format!("FAIL  {COAST_CHECK} (power stage off, timeout 10m)  interrupted"),
            "safe stop: the drive coasts by design",
            "coasted to standstill",
            "drive left in ready to switch on at",
        ],
    );
}

/// Ctrl-C while the operator is asked for the value: the safe stop at once, braked.
#[test]
fn a_stop_at_a_compared_value_question_runs_the_safe_stop_and_no_comparison() {
    let (file, store, reference) = passed_once(
        "wear-value-ctrl-c",
        vibration_recipe,
        &["--answer", "serial=SP-000009", "--answer", "vibration=1.2"],
    );
    // The serial answered beforehand; the value typed by nobody.
    let mut r = interrupted_at(&file, store, Duration::from_secs(8));
    r.operator.answer = vec![("serial".into(), "SP-000009".into())];
    let (result, out) = r.run_at_a_silent_terminal();
    assert_stopped_without_a_comparison(
        &result,
        &out,
        &reference,
        (
            "Vibration on the hand-held meter compared with last pass",
            "Vibration on the hand-held meter compared with last pass",
        ),
    );
    assert_has(
        &out,
        &[
            "5  ?     Vibration on the hand-held meter [in mm/s, at most 2.8 mm/s]",
            "5  FAIL  enter_value \"Vibration on the hand-held meter\"  interrupted",
            "drive left in ready to switch on at 0 rpm",
        ],
    );
}

/// A script looks the unit up at its first comparison: for a coast-down, before the power
/// stage goes off. A store that never answers holds it there; Ctrl-C then ends the wait at
/// once and the safe stop brakes the spindle, which never coasted.
#[test]
fn a_stop_while_a_scripts_coast_down_waits_for_the_store_brakes_the_spindle() {
    let script = scratch_sd2_script(
        "wear-script-lookup",
        "wear.rhai",
        "Scripted coast-down",
        &format!("{SCRIPT_UP_TO_SPEED}{SCRIPT_COAST_DOWN}"),
    );
    let (code, seen) = interrupted_once_shown(&script, "wait_until speed_actual");
    assert_eq!(code, Some(130), "{seen}");
    assert_has(&seen, &["drive left in ready to switch on at 0 rpm"]);
    assert_lacks(
        &seen,
        &["coasting by design", "STILL COASTING", "coast-down took"],
    );
}

/// The safe stop never waits for a store: a comparison in a script's `finally` judges by
/// what was looked up before (here nothing), at once.
#[test]
fn a_comparison_in_a_scripts_finally_never_waits_for_the_store() {
    let script = scratch_sd2_script(
        "wear-finally",
        "finally.rhai",
        "Coast-down at the end",
        &format!("//! safe_stop: brake_to_standstill=false\n{SCRIPT_UP_TO_SPEED}fn finally(d) {{\n    {SCRIPT_COAST_DOWN}    d.disable_voltage();\n}}\n"),
    );
    let (_, took, text) = ended_reading_a_silent_store(&script, &[]);
    assert!(
        took < drivescript::session::LOOKUP_LIMIT,
        "took {took:?}, as long as a lookup:\n{text}"
    );
    assert_has(
        &text,
        &[
            "coast-down took 19.334 s",
            "compared with last pass: not looked up: the safe stop (finally, on_fault) never waits for the results store",
        ],
    );
    assert_has(&text, &["drive left in switch on disabled at"]);
    assert_lacks(&text, &["history:", "NOT confirmed"]);
}
