//! Checks that compare with the unit's last passed run (`compared_with_last_pass`), end to
//! end against a real SQLite file and a real PostgreSQL server: the first run without
//! history (passing or failing as the recipe says), a second that compares and passes, a
//! drifted third that fails, a failed run or another serial never taken as the reference,
//! simulated and real runs kept apart, the reference in console, JUnit, HTML and the
//! store; a store that cannot be read fails the check (never "no history") and the drive
//! still ends in a verified safe stop; the lookup is bounded and a stop signal during it
//! runs the safe stop; a serial typed at an operator step looks up at that point.

use crate::live_run::LiveRun;
use crate::support::{
    assert_exit, assert_has, assert_lacks, cli, command, console, run_recording as run, scratch,
    scratch_file, silent_server, unit_certificate, with_postgres_store, with_sqlite_store, write_changed,
    write_file, InProcessRun, Simulator,
};
use crate::support_store::{
    scratch_sd2_script, scratch_store, sd2_script, shown_run, FailedComparison, Reports,
};
use drivescript::results::{Locator, RunFilter, StoreHistory};
use std::path::Path;
use std::process::Stdio;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The motor's temperature at the start is the simulated ambient (`--sim ambient=…`): a
/// value that drifts between runs on demand.
const RUN_IN: &str = "name: Run-in acceptance
drive: sd2
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: 3000 rpm }
  - wait_until: { speed_actual: { near: 3000 rpm, within: 1 % }, timeout: 10 s }
  - expect:
      motor_temperature:
        below: 90 °C
        compared_with_last_pass: { at_most: 2 K, at_least: -2 K, without_history: pass }
";

/// The id of the run `results: run ID recorded in …` names.
pub(crate) fn run_id(output: &str) -> String {
    output
        .lines()
        .find_map(|l| l.strip_prefix("results: run "))
        .and_then(|rest| rest.split_whitespace().next())
        .unwrap_or_else(|| panic!("no run id in:\n{output}"))
        .to_string()
}

fn history_in(dir: &Path, store: &str) {
    let recipe = write_file(dir, "run-in.yaml", RUN_IN);
    let fast = |serial: &str, more: &[&str]| {
        let unit = format!("serial={serial}");
        let mut args = vec!["--fast", "--unit", unit.as_str()];
        args.extend_from_slice(more);
        run(&recipe, store, &args)
    };
    // The unit's first run: no history, passes as the recipe chooses, said before step 1.
    let first = assert_exit(
        fast("SP-1", &[]),
        0,
        &[
            "history SP-1: no earlier passed run of `Run-in acceptance`",
            "(simulated runs)",
            "     1  ok    go to operation_enabled",
            "PASS  motor_temperature below 90 °C compared with last pass: no earlier passed run of SP-1 for this recipe: passes as `without_history: pass` says",
        ],
    );
    let first_id = run_id(&first);
    // The second compares with the first, says so before anything moves, and passes.
    let second = assert_exit(
        fast("SP-1", &[]),
        0,
        &[
            &format!("history SP-1: compared with its last pass, run {first_id} of 20"),
            "motor_temperature below 90 °C = 25 °C",
            "     1  ok    go to operation_enabled",
            &format!("PASS  motor_temperature below 90 °C compared with last pass: motor_temperature = 25 °C: 0 K against 25 °C in run {first_id}"),
        ],
    );
    let second_id = run_id(&second);
    // Drifted by 5 K: fails, naming the reference in every report.
    let reports = Reports::in_folder(dir, "drift");
    let drift = format!("motor_temperature = 30 °C: +5 K against 25 °C in run {second_id}");
    let third = assert_exit(
        fast(
            "SP-1",
            &[&["--sim", "ambient=30°C"][..], &reports.args()].concat(),
        ),
        1,
        &[
            "PASS  motor_temperature below 90 °C: motor_temperature = 30 °C",
            &format!("FAIL  motor_temperature below 90 °C compared with last pass: {drift}"),
            "expected a change between -2 K and +2 K",
            "FAILED",
        ],
    );
    let third_id = run_id(&third);
    reports.assert_both_have(&["motor_temperature below 90 °C compared with last pass", &drift]);
    // A failed run is never the reference; nor is another unit's run.
    let fourth = assert_exit(fast("SP-1", &[]), 0, &[&format!("run {second_id}")]);
    assert_lacks(&fourth, &[&third_id]);
    // Nor is a voided run (a wrong unit scanned): its values are not this unit's.
    let fourth_id = run_id(&fourth);
    let why = ["--why", "wrong unit scanned", "--by", "A. Lead"];
    cli(
        &[&["results", "void", &fourth_id][..], &why, &["--results", store]].concat(),
        0,
    );
    let fifth = assert_exit(fast("SP-1", &[]), 0, &[&format!("run {second_id}")]);
    assert_lacks(&fifth, &[&fourth_id]);
    assert_exit(fast("SP-2", &[]), 0, &["history SP-2: no earlier passed run"]);
    // A recipe that insists on history fails a unit's first run.
    let strict = write_file(
        dir,
        "strict.yaml",
        &RUN_IN
            .replace("Run-in acceptance", "Strict acceptance")
            .replace("without_history: pass", "without_history: fail"),
    );
    assert_exit(
        run(&strict, store, &["--fast", "--unit", "serial=SP-1"]),
        1,
        &["FAIL  motor_temperature below 90 °C compared with last pass: no earlier passed run of SP-1 for this recipe: fails as `without_history: fail` says"],
    );
    // The store keeps the reference with the comparison.
    FailedComparison {
        reference_run: &second_id,
        reference_value: 25.0,
        change: 5.0,
        unit: "K",
        limits: (Some(-2.0), Some(2.0)),
        within: 0.0,
    }
    .assert_kept(
        store,
        &third_id,
        "motor_temperature below 90 °C compared with last pass",
    );
    assert_has(
        &shown_run(store, &third_id),
        &[&format!("reference: run {second_id} of 20")],
    );
    // The unit's certificate says what each comparison compared with: the change alone
    // (`5 K` beside a check of 30 °C) would read as a measured value.
    let page = unit_certificate(store, "SP-1", &dir.join("SP-1.html"));
    assert_has(&page, &[&drift, "no earlier passed run of SP-1 for this recipe"]);
}

#[test]
fn a_check_compares_with_the_units_last_passed_run_in_sqlite() {
    with_sqlite_store("history", history_in);
}

#[test]
fn a_check_compares_with_the_units_last_passed_run_in_postgresql() {
    with_postgres_store("history", history_in);
}

/// Real runs compare with real runs only, simulated ones with simulated ones.
#[test]
fn simulated_and_real_runs_are_compared_only_with_their_own_kind() {
    let (dir, store) = &scratch_store("history-kinds");
    let recipe = write_file(
        dir,
        "quick.yaml",
        "name: Quick look
drive: sd2
steps:
  - expect:
      motor_temperature: { below: 90 °C, compared_with_last_pass: { at_most: 1 K, without_history: pass } }
",
    );
    let sim = Simulator::pty(&[]);
    let real = |args: &[&str]| {
        let mut all = vec!["--port", sim.endpoint.as_str(), "--unit", "serial=K-1"];
        all.extend_from_slice(args);
        run(&recipe, store, &all)
    };
    let first_real = assert_exit(real(&[]), 0, &["no earlier passed run", "(runs on real drives)"]);
    let real_id = run_id(&first_real);
    assert_exit(
        run(&recipe, store, &["--fast", "--unit", "serial=K-1"]),
        0,
        &["no earlier passed run", "(simulated runs)"],
    );
    assert_exit(
        real(&[]),
        0,
        &[&format!(
            "history K-1: compared with its last pass, run {real_id}"
        )],
    );
}

/// A store that cannot be read is not "no history": the comparison cannot be judged and
/// fails, naming the store; the run goes on and its drive ends in a verified safe stop.
#[test]
fn a_store_that_cannot_be_read_fails_the_comparison_and_the_drive_still_stops() {
    let (dir, recipe) = scratch_file("history-unreadable", "run-in.yaml", RUN_IN);
    let foreign = write_file(&dir, "notes.sqlite", "these are notes, not a database\n");
    let (code, out) = run(
        &recipe,
        foreign.to_str().unwrap(),
        &["--fast", "--unit", "serial=SP-1"],
    );
    assert_eq!(code, 1, "{out}");
    assert_has(
        &out,
        &[
            "history: cannot compare with the last pass:",
            "PASS  motor_temperature below 90 °C: motor_temperature = 25 °C",
            "FAIL  motor_temperature below 90 °C compared with last pass: cannot be judged:",
            &foreign.display().to_string(),
            "drive left in ready to switch on at 0 rpm",
            "FAILED",
        ],
    );
    assert_lacks(&out, &["no earlier passed run", "NOT confirmed"]);
}

/// `--no-results` with a store (named by the environment) that takes the connection and
/// never answers: the run records nothing and the comparison's lookup is bounded.
pub(crate) fn run_reading_a_silent_store(recipe: &Path, more: &[&str]) -> std::process::Child {
    let mut run = command();
    reading_a_silent_store(&mut run, recipe, more);
    run.stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs")
}

/// [`run_reading_a_silent_store`] to its end: its exit code, how long it took and
/// everything it wrote.
pub(crate) fn ended_reading_a_silent_store(recipe: &Path, more: &[&str]) -> (Option<i32>, Duration, String) {
    let started = Instant::now();
    let out = run_reading_a_silent_store(recipe, more)
        .wait_with_output()
        .expect("the run ends");
    let text = console(&out.stdout, &out.stderr);
    (out.status.code(), started.elapsed(), text)
}

/// Makes `run` the `drivescript run RECIPE --fast MORE` of [`run_reading_a_silent_store`].
fn reading_a_silent_store(run: &mut std::process::Command, recipe: &Path, more: &[&str]) {
    let port = silent_server();
    run.env(
        "DRIVESCRIPT_RESULTS",
        format!("postgres://drivescript@127.0.0.1:{port}/results"),
    )
    .arg("run")
    .arg(recipe)
    .args(["--fast", "--no-results", "--unit", "serial=SP-1"])
    .args(more);
}

/// It is waited for once per serial: the operator steps after it do not wait again.
#[test]
fn the_lookup_of_a_store_that_never_answers_is_bounded() {
    let dir = scratch("history-silent");
    let questions = "  - confirm: { prompt: Guard closed? }\n    name: guard\n  - confirm: { prompt: Adapter fitted? }\n    name: adapter\n";
    let recipe = write_file(
        &dir,
        "run-in.yaml",
        &RUN_IN.replace("steps:\n", &format!("steps:\n{questions}")),
    );
    let answers = ["--answer", "guard=yes", "--answer", "adapter=yes"];
    let (code, took, text) = ended_reading_a_silent_store(&recipe, &answers);
    assert_eq!(code, Some(1), "{text}");
    assert!(took < Duration::from_secs(18), "took {took:?}:\n{text}");
    assert_eq!(
        text.matches("history: cannot compare").count(),
        1,
        "looked up once for the serial, not again after each operator step:\n{text}"
    );
    assert_has(
        &text,
        &[
            "did not answer within 10 s",
            "     3  ok    go to operation_enabled",
            "cannot be judged",
            "drive left in ready to switch on at 0 rpm",
        ],
    );
}

/// [`run_reading_a_silent_store`] of `recipe`, its output read until it shows `marker`,
/// then Ctrl-C (SIGINT; under Wine the console's event) after a moment: the run is then
/// waiting where `marker` says. Its exit code and everything it showed; it must end
/// within 5 s of the signal.
pub(crate) fn interrupted_once_shown(recipe: &Path, marker: &str) -> (Option<i32>, String) {
    let mut run = LiveRun::with(|run| reading_a_silent_store(run, recipe, &[]));
    run.wait_for(marker);
    std::thread::sleep(Duration::from_millis(300));
    let signalled = Instant::now();
    run.signal("INT");
    let (code, seen) = run.finish();
    assert!(signalled.elapsed() < Duration::from_secs(5), "{seen}");
    (code, seen)
}

/// A stop signal while the store is looked up ends the wait at once, with the safe stop.
#[test]
fn a_stop_signal_during_the_lookup_runs_the_safe_stop() {
    let (_, recipe) = scratch_file("history-signal", "run-in.yaml", RUN_IN);
    let (code, seen) = interrupted_once_shown(&recipe, "unit    serial SP-1");
    assert_eq!(code, Some(130), "{seen}");
    // Never enabled, the drive stays in switch on disabled: the stop sends no shutdown,
    // which would move it up to ready to switch on.
    assert_has(&seen, &["drive left in switch on disabled at 0 rpm"]);
    assert_lacks(&seen, &["go to operation_enabled"]);
}

/// A serial typed at an operator step: the lookup comes at that step (the unit was
/// unknown before it), and the check after it compares.
#[test]
fn a_serial_typed_at_an_operator_step_is_looked_up_there() {
    let (dir, store) = &scratch_store("history-typed");
    let recipe = write_file(
        dir,
        "scanned.yaml",
        "name: Scanned acceptance
drive: sd2
steps:
  - enter_text: { prompt: \"Scan the spindle's serial number\", sets: serial }
    name: serial
  - go_to: operation_enabled
  - expect:
      motor_temperature: { below: 90 °C, compared_with_last_pass: { at_most: 1 K, without_history: fail } }
",
    );
    // Answered beforehand, the serial is known at the start: looked up before step 1.
    let (code, given) = run(&recipe, store, &["--fast", "--answer", "serial=SP-77"]);
    assert_eq!(code, 1, "no history fails here:\n{given}");
    let said = given.find("history SP-77: no earlier passed run").expect("said");
    assert!(said < given.find("     1  ").expect("step 1"), "{given}");
    // One passed run of the unit (a failed one is no reference).
    {
        let recorder = drivescript::results::ResultsRecorder::start(
            Locator::Sqlite(store.into()),
            drivescript::results::RecorderSettings {
                simulated: true,
                quiet: true,
                ..Default::default()
            },
            Arc::new(Mutex::new(std::io::sink())),
        );
        let lenient = write_changed(
            dir,
            "lenient.yaml",
            &recipe,
            "without_history: fail",
            "without_history: pass",
        );
        let mut run = InProcessRun::new(&lenient);
        run.operator.answer = vec![("serial".into(), "SP-77".into())];
        run.observers.push(Arc::new(Mutex::new(recorder)));
        run.history = Some(Arc::new(StoreHistory::new(Locator::Sqlite(store.into()), true)));
        let (result, out) = run.run();
        assert_eq!(result.exit_code, 0, "{out}");
    }
    let mut s = Locator::Sqlite(store.into()).open(false).expect("opens");
    let passed = s
        .list(&RunFilter {
            simulated: true,
            verdict: Some("passed".into()),
            ..RunFilter::default()
        })
        .expect("list");
    let [reference] = passed.as_slice() else {
        panic!("one passed run: {passed:?}");
    };
    // Typed at the terminal during the run.
    let (reader, mut typing) = std::io::pipe().expect("pipe");
    std::io::Write::write_all(&mut typing, b"SP-77\n").expect("typed");
    let mut run = InProcessRun::new(&recipe);
    run.input = Some(drivescript::run::TerminalInput::of(reader));
    run.history = Some(Arc::new(StoreHistory::new(Locator::Sqlite(store.into()), true)));
    let (result, out) = run.run();
    drop(typing);
    assert_eq!(result.exit_code, 0, "{out}");
    let asked = out.find("Scan the spindle's serial number").expect("asked");
    let said = out
        .find(&format!(
            "history SP-77: compared with its last pass, run {}",
            reference.run.id
        ))
        .unwrap_or_else(|| panic!("the lookup is said:\n{out}"));
    let moved = out.find("go to operation_enabled").expect("step 2");
    assert!(asked < said && said < moved, "looked up at the step:\n{out}");
    assert_has(
        &out,
        &["PASS  motor_temperature below 90 °C compared with last pass: motor_temperature = 25 °C: 0 K against 25 °C"],
    );
}

/// The shipped example: a spindle's second run compares with its first; a spindle that
/// warms more than 3 K above its last pass fails, though still within its limit.
#[test]
fn the_bearing_acceptance_example_compares_a_spindle_with_its_last_pass() {
    let (_, store) = &scratch_store("history-example");
    let recipe = crate::support::repo_root().join("recipes/operator/bearing-acceptance.yaml");
    let example = |heating: &str| {
        run(
            &recipe,
            store,
            &["--fast", "--answer", "serial=SP-104233", "--sim", heating],
        )
    };
    // `check` says where the comparisons are and where the serial will come from.
    let checked = crate::support::cli(&["check", recipe.to_str().unwrap()], 0);
    assert_has(
        &checked.stdout,
        &[
            "compares with the unit's last passed run (",
            "bearing-acceptance.yaml:25:29); the serial from --unit serial=… or the operator step serial (",
        ],
    );
    let (code, first) = example("heating=25K/A");
    assert_eq!(code, 0, "{first}");
    let first_id = run_id(&first);
    assert_exit(
        example("heating=25K/A"),
        0,
        &[
            &format!("history SP-104233: compared with its last pass, run {first_id}"),
            "PASS  bearing current at 18000 rpm compared with last pass: current_actual mean = ",
            "(limits -10 .. 10 %)",
        ],
    );
    assert_exit(
        example("heating=30K/A"),
        1,
        &[
            "PASS  motor temperature after 10 min at 18000 rpm: motor_temperature max = 52.5 °C",
            "FAIL  motor temperature after 10 min at 18000 rpm compared with last pass: motor_temperature max = 52.5 °C: +4.5 K against 48 °C",
            "expected a change at most +3 K (limit ≤ 3 K)",
        ],
    );
}

/// A script compares its own check with the unit's last passed run of the script, looked
/// up at the first comparison; a comparison it writes wrongly is a script error.
#[test]
fn a_script_compares_its_check_with_the_units_last_pass() {
    let (dir, store) = &scratch_store("history-script");
    let script = sd2_script(
        dir,
        "bearing.rhai",
        "Scripted bearing check",
        "let d = drive();
d.go_to(\"operation_enabled\");
let t = d.read(\"motor_temperature\");
expect_near(\"motor temperature\", t, 25.0, \"50 %\");
expect_compared_with_last_pass(\"motor temperature\", t, #{ at_most: 2.0, at_least: -2.0, without_history: \"pass\" });
",
    );
    let unit = ["--fast", "--unit", "serial=SC-1", "--sim"];
    let first = assert_exit(
        run(&script, store, &[&unit[..], &["ambient=25°C"]].concat()),
        0,
        &["PASS  motor temperature compared with last pass: no earlier passed run of SC-1"],
    );
    let first_id = run_id(&first);
    assert_exit(
        run(&script, store, &[&unit[..], &["ambient=30°C"]].concat()),
        1,
        &[
            &format!("history SC-1: compared with its last pass, run {first_id}"),
            &format!("FAIL  motor temperature compared with last pass: motor temperature = 30: +5 against 25 in run {first_id}"),
            "expected a change between -2 and +2",
        ],
    );
    let wrong = write_changed(dir, "wrong.rhai", &script, ", without_history: \"pass\"", "");
    let (code, out) = run(&wrong, store, &unit[..3]);
    assert_ne!(code, 0, "{out}");
    assert_has(&out, &["give `without_history: \"pass\"`", "wrong.rhai:7:1"]);
}

/// A script's comparison in its `finally` is part of the safe stop, which never waits for
/// a store: it is judged by what was looked up before (here nothing), says so, and the
/// stop goes on at once to disable the drive, even with a store that never answers.
#[test]
fn a_comparison_in_a_scripts_finally_never_waits_for_the_store() {
    let script = scratch_sd2_script(
        "history-script-finally",
        "finally.rhai",
        "Compared in finally",
        "let d = drive();
d.go_to(\"operation_enabled\");
fn finally(d) {
    let t = d.read(\"motor_temperature\");
    expect_near(\"motor temperature\", t, 25.0, \"50 %\");
    expect_compared_with_last_pass(\"motor temperature\", t, #{ at_most: 2.0, without_history: \"pass\" });
    d.disable_operation();
    d.shutdown();
}
",
    );
    let (_, _, text) = ended_reading_a_silent_store(&script, &[]);
    assert_has(
        &text,
        &[
            "FAIL  motor temperature compared with last pass: not looked up: the safe stop (finally, on_fault) never waits for the results store",
            "ok    disable_operation",
            "drive left in ready to switch on at 0 rpm",
        ],
    );
    assert_lacks(&text, &["did not answer within 10 s", "history: cannot compare"]);
}
