//! The results store end to end: runs recorded as they go into SQLite and into a real
//! PostgreSQL server the test starts, a killed run left incomplete with its checks, a
//! store that cannot be reached spooled and synced with nothing lost, two processes of 200
//! runs each into one store, hostile serial numbers stored verbatim, foreign files refused
//! clearly, and the unit's certificate rendered in headless Chromium.

use crate::live_run::LiveRun;
use crate::support::SHORT_RECIPE as SHORT;
use crate::support::{
    assert_has, assert_lacks, cli, command, console, postgres_with_folder, run_recording, scratch,
    scratch_file, screenshot, silent_server, sqlite_store, unit_certificate, write_file, InProcessRun,
    PostgresServer, Ran, Simulator,
};
use crate::support_store::{run_recorded, scratch_store, shown_run};
use drivescript::results::{Locator, RunFilter, StoredRun};
use drivescript::session::{CheckResult, RunInfo, RunObserver, RunReport, StepRecord, UnitIdentity};
use std::path::Path;
use std::process::Stdio;
use std::sync::{Arc, Mutex};

/// `results list --results STORE --simulated FILTER…`, which must succeed.
fn list(store: &str, filter: &[&str]) -> Ran {
    cli(
        &[&["results", "list", "--results", store, "--simulated"], filter].concat(),
        0,
    )
}

/// The smallest recipe with a check, for many runs.
const TINY: &str = "name: Tiny
drive: sd2
steps:
  - expect: { bus_voltage: { above: 100 V } }
";

const HOSTILE: [&str; 5] = [
    "O'Brien \"SP\"-1",
    "Ünïcødé-主轴-🚀",
    "'); DROP TABLE runs; --",
    "back\\slash %_ like",
    "line\nbreak\ttab",
];

/// Every run, simulated ones too.
fn every_run() -> RunFilter {
    RunFilter {
        simulated: true,
        ..RunFilter::default()
    }
}

/// Every run in `store`, simulated ones too, in detail.
fn all_runs(store: &str) -> Vec<StoredRun> {
    let mut s = Locator::parse(store).open(false).expect("the store opens");
    let runs = s.list(&every_run()).expect("list");
    runs.iter().map(|r| s.run(&r.run.id).expect("the run")).collect()
}

/// Passes every event on to the recorder, with the unit's identity put into the run's
/// `RunInfo` at the start (as `--unit` will) and, when `later` is given, made known again
/// after the first check (as an operator's answer is).
struct WithUnit {
    inner: drivescript::results::ResultsRecorder,
    unit: UnitIdentity,
    later: Option<UnitIdentity>,
}

impl RunObserver for WithUnit {
    fn run_started(&mut self, run: &RunInfo, drive: &str) {
        let run = RunInfo {
            unit: self.unit.clone(),
            ..run.clone()
        };
        self.inner.run_started(&run, drive);
    }
    fn step_finished(&mut self, record: &StepRecord) {
        self.inner.step_finished(record);
    }
    fn check(&mut self, result: &CheckResult) {
        self.inner.check(result);
        if let Some(unit) = self.later.take() {
            self.inner.unit_identified(&unit);
        }
    }
    fn run_finished(&mut self, report: &RunReport) {
        self.inner.run_finished(report);
    }
}

/// Runs `recipe` in process with the recorder writing to `store` for `unit`; the run's
/// exit code.
fn recorded_run(
    recipe: &Path,
    store: &str,
    unit: UnitIdentity,
    later: Option<UnitIdentity>,
    set: &[(&str, &str)],
) -> i32 {
    let recorder = drivescript::results::ResultsRecorder::start(
        Locator::parse(store),
        drivescript::results::RecorderSettings {
            simulated: true,
            quiet: true,
            ..Default::default()
        },
        Arc::new(Mutex::new(std::io::sink())),
    );
    let observer = Arc::new(Mutex::new(WithUnit {
        inner: recorder,
        unit,
        later,
    }));
    let mut run = InProcessRun::new(recipe);
    run.set = set.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
    run.observers.push(observer);
    run.run().0.exit_code
}

fn serial(s: &str) -> UnitIdentity {
    UnitIdentity {
        serial: Some(s.into()),
        ..UnitIdentity::default()
    }
}

#[test]
fn a_run_is_recorded_with_its_checks_steps_end_state_and_series() {
    let (dir, store) = &scratch_store("recorded");
    let recipe = write_file(dir, "short.yaml", SHORT);
    let ran = run_recorded(&recipe, store, &[], 0);
    assert_has(&ran.stderr, &["results: run ", " recorded in ", store]);
    let runs = all_runs(store);
    assert_eq!(runs.len(), 1);
    let r = &runs[0];
    assert_eq!(r.verdict(), "passed");
    assert!(r.run.simulated);
    assert_eq!(r.run.recipe, "Short acceptance");
    assert_eq!(
        (r.run.dictionary.as_deref(), r.run.family.as_deref()),
        (Some("sd2"), Some("sd2"))
    );
    assert_eq!(r.run.params, vec![("speed".to_string(), "3000 rpm".to_string())]);
    assert_eq!(r.run.recipe_sha256.as_deref().map(str::len), Some(64));
    assert_eq!(r.checks.len(), 2, "{:?}", r.checks);
    assert!(r.checks.iter().all(|c| c.passed && c.attempt == 1));
    assert!(r.steps.iter().any(|s| s.phase == "finally"), "{:?}", r.steps);
    let end = r.end.as_ref().expect("ended");
    assert_eq!(end.final_state.as_deref(), Some("ready to switch on"));
    assert!(end.stop_confirmed);
    assert_eq!(end.series.len(), 1);
    assert!(end.series[0].points.len() > 40, "{}", end.series[0].points.len());
    // Hidden from lists unless asked for.
    let hidden = cli(&["results", "list", "--results", store], 0);
    assert_has(
        &hidden.stdout,
        &["no runs (runs on the simulated drive are hidden"],
    );
    let listed = cli(&["results", "list", "--results", store, "--simulated"], 0);
    assert_has(
        &listed.stdout,
        &[&r.run.id, "PASSED", "Short acceptance", "simulated"],
    );
    let shown = cli(&["results", "show", &r.run.id[..6], "--results", store], 0);
    assert_has(
        &shown.stdout,
        &[
            "PASS  speed_actual mean near",
            "drive left in ready to switch on",
            "PASSED (exit code 0)",
        ],
    );
    let page = cli(&["results", "report", &r.run.id, "--results", store], 0);
    assert_has(
        &page.stdout,
        &[
            "<!DOCTYPE html>",
            "Short acceptance",
            "ready to switch on at 0 rpm (stop confirmed)",
            "<svg",
        ],
    );
    let since = list(store, &["--since", "2999-01-01"]);
    assert_has(&since.stdout, &["no runs"]);
    let recent = list(store, &["--since", "1h", "--json"]);
    assert_has(
        &recent.stdout,
        &[&format!("\"id\": \"{}\"", r.run.id), "\"verdict\": \"passed\""],
    );
    // --no-results records nothing.
    run_recorded(&recipe, store, &["--set", "speed=2000rpm"], 0);
    cli(&["run", recipe.to_str().unwrap(), "--fast", "--no-results"], 0);
    assert_eq!(all_runs(store).len(), 2);
    // Filters, export and trend over the runs.
    let failed = list(store, &["--verdict", "failed"]);
    assert_has(&failed.stdout, &["no runs"]);
    let export = |format: &str| {
        cli(
            &[
                "results",
                "export",
                "--results",
                store,
                "--simulated",
                "--format",
                format,
            ],
            0,
        )
    };
    // JSON is the default format.
    let json = cli(&["results", "export", "--results", store, "--simulated"], 0);
    let parsed: serde_json::Value = serde_json::from_str(&json.stdout).expect("JSON");
    assert_eq!(parsed.as_array().map(Vec::len), Some(2));
    let csv = export("csv");
    assert_eq!(csv.stdout.lines().count(), 1 + 4, "{}", csv.stdout);
    let junit = export("junit");
    let doc = roxmltree::Document::parse(&junit.stdout).expect("well-formed JUnit");
    assert_eq!(
        doc.descendants().filter(|n| n.has_tag_name("testsuite")).count(),
        2
    );
    let check = &r.checks[1].name;
    let trend = cli(
        &[
            "results",
            "trend",
            check,
            "--results",
            store,
            "--simulated",
            "--html",
            dir.join("trend.html").to_str().unwrap(),
        ],
        0,
    );
    // The same check in both runs, each with its own limits: the second's is near 2000
    // rpm (the parameter changed its limits, not the check).
    assert_has(
        &trend.stdout,
        &[
            "3000.",
            "2970 .. 3030",
            "2000.",
            "1980 .. 2020",
            "PASS",
            &r.run.id,
        ],
    );
    assert_eq!(trend.stdout.lines().count(), 3, "{}", trend.stdout);
    let page = std::fs::read_to_string(dir.join("trend.html")).expect("trend page");
    assert_has(&page, &["<svg", "Trend of speed_actual mean near"]);
}

#[test]
fn the_default_store_is_in_the_data_directory_and_takes_only_real_drives_unless_named() {
    let (dir, recipe) = scratch_file("default", "tiny.yaml", TINY);
    let run = |extra: &[&str]| {
        let out = command()
            .env_remove("DRIVESCRIPT_RESULTS")
            .envs(crate::support::data_home(&dir))
            .args(["run", recipe.to_str().unwrap()])
            .args(extra)
            .stdin(Stdio::null())
            .output()
            .expect("runs");
        Ran::exited(out, 0);
    };
    run(&["--fast"]);
    let default = dir.join("drivescript/results.sqlite");
    assert!(
        !default.exists(),
        "a simulated run stays out of the default store"
    );
    let sim = Simulator::pty(&[]);
    run(&["--port", &sim.endpoint]);
    let runs = all_runs(default.to_str().unwrap());
    assert_eq!(runs.len(), 1);
    assert!(!runs[0].run.simulated);
    assert_eq!(runs[0].run.port.as_deref(), Some(sim.endpoint.as_str()));
}

/// The unit's identity from `--unit` and from an operator's answer, and a marginal pass,
/// are recorded from the command line as the reports show them: `results list --unit`
/// finds the run, `results show` names the unit and says MARGINAL.
#[test]
fn the_unit_from_the_command_line_and_an_answer_and_a_marginal_check_are_recorded() {
    let (dir, recipe) = scratch_file(
        "unit-marginal",
        "marginal.yaml",
        "name: Marginal with a unit
drive: sd2
steps:
  - enter_text: { prompt: Operator, sets: operator }
  - set: { speed_setpoint: 10000 rpm }
  - go_to: operation_enabled
  - dwell: 20 min
  - sample: { objects: [motor_temperature], every: 1 s, for: 10 s }
  - expect:
      motor_temperature: { max: { below: 50 °C, warn: 40 °C } }
",
    );
    let store = &sqlite_store(&dir);
    let run = run_recorded(
        &recipe,
        store,
        &["--unit", "serial=SP-104233", "--answer", "operator=J. Smith"],
        0,
    );
    assert_has(&run.stdout, &["MARGINAL"]);
    let runs = all_runs(store);
    assert_eq!(runs.len(), 1);
    let unit = &runs[0].run.unit;
    assert_eq!(unit.serial.as_deref(), Some("SP-104233"));
    assert_eq!(unit.operator.as_deref(), Some("J. Smith"));
    let temperature = runs[0]
        .checks
        .iter()
        .find(|c| c.name.starts_with("motor_temperature"))
        .expect("the temperature check");
    assert!(temperature.passed && temperature.marginal, "{temperature:?}");

    let listed = list(store, &["--unit", "SP-104233"]);
    assert_has(&listed.stdout, &["Marginal with a unit"]);
    let id = runs[0].run.id.as_str();
    assert_has(
        &shown_run(store, id),
        &[
            "SP-104233",
            "J. Smith",
            "MARGINAL  motor_temperature max below 50 °C",
        ],
    );
}

/// A replayed run is recorded as simulated (nothing moved) and names its capture, so it
/// is told apart from a run on the built-in simulated drive.
#[test]
fn a_replayed_run_is_recorded_with_its_capture() {
    let (_, store) = &scratch_store("replayed");
    let case = crate::support::repo_root().join("tests/cases/replay/sd2_commissioning");
    let capture = case.join("capture.trace");
    cli(
        &[
            "run",
            case.join("recipe.yaml").to_str().expect("utf-8"),
            "--replay",
            capture.to_str().expect("utf-8"),
            "--results",
            store,
        ],
        0,
    );
    let runs = all_runs(store);
    assert_eq!(runs.len(), 1);
    assert!(runs[0].run.simulated);
    let port = runs[0].run.port.clone().unwrap_or_default();
    assert_eq!(port, format!("replay:{}", capture.display()));
}

#[test]
fn a_killed_run_is_left_incomplete_with_its_checks() {
    let (dir, store) = &scratch_store("killed");
    let recipe = write_file(dir, "killed.yaml", &format!("{TINY}  - dwell: 60 s\n"));
    let mut run = LiveRun::start([
        "run",
        recipe.to_str().unwrap(),
        "--no-progress",
        "--results",
        store,
    ]);
    run.wait_for("bus_voltage");
    // The check reaches the store while the run dwells.
    let started = std::time::Instant::now();
    while started.elapsed() < std::time::Duration::from_secs(20) {
        if Path::new(store).is_file() && all_runs(store).first().is_some_and(|r| !r.checks.is_empty()) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    run.signal("KILL");
    let (code, _) = run.finish();
    // Windows' TerminateProcess leaves the code it is given (1, as the Task Manager's);
    // Unix says "by a signal".
    assert_eq!(code, if cfg!(windows) { Some(1) } else { None }, "killed");
    let runs = all_runs(store);
    assert_eq!(runs.len(), 1);
    assert_eq!(runs[0].verdict(), "incomplete");
    assert_eq!(runs[0].checks.len(), 1);
    assert!(runs[0].checks[0].passed);
    let listed = list(store, &["--verdict", "incomplete"]);
    assert_has(&listed.stdout, &["INCOMPLETE", "Tiny"]);
}

#[test]
fn a_locked_store_is_spooled_and_synced_with_nothing_lost() {
    let (dir, s) = &scratch_store("locked");
    let recipe = write_file(dir, "short.yaml", SHORT);
    // A first run makes the store; then another process holds it locked for the whole run.
    run_recorded(&recipe, s, &[], 0);
    let lock = rusqlite::Connection::open(s).expect("open");
    lock.execute_batch("BEGIN EXCLUSIVE").expect("lock");
    let ran = run_recorded(&recipe, s, &["--set", "speed=2500rpm"], 0);
    assert_has(&ran.stdout, &["PASSED"]);
    assert_has(
        &ran.stderr,
        &["cannot be reached", "results.sqlite.spool", "results sync"],
    );
    assert!(dir.join("results.sqlite.spool").is_file());
    lock.execute_batch("ROLLBACK").expect("unlock");
    drop(lock);
    assert_eq!(all_runs(s).len(), 1);
    let synced = cli(&["results", "sync", "--results", s], 0);
    assert_has(&synced.stdout, &["delivered", "of 1 run(s)"]);
    assert!(!dir.join("results.sqlite.spool").exists());
    let runs = all_runs(s);
    assert_eq!(runs.len(), 2);
    let spooled = runs
        .iter()
        .find(|r| r.run.params[0].1.contains("2500"))
        .expect("the spooled run");
    assert_eq!(spooled.verdict(), "passed");
    assert_eq!(spooled.checks.len(), 2);
    assert_eq!(spooled.end.as_ref().map(|e| e.series.len()), Some(1));
    let again = cli(&["results", "sync", "--results", s], 0);
    assert_has(&again.stdout, &["nothing to deliver"]);
    // Spooled again; this time the next run delivers it.
    let lock = rusqlite::Connection::open(s).expect("open");
    lock.execute_batch("BEGIN EXCLUSIVE").expect("lock");
    run_recorded(&recipe, s, &["--set", "speed=2600rpm"], 0);
    drop(lock);
    let next = run_recorded(&recipe, s, &[], 0);
    assert_has(&next.stderr, &["delivered 1 spooled run(s)"]);
    let runs = all_runs(s);
    assert_eq!(runs.len(), 4);
    assert!(runs
        .iter()
        .all(|r| r.verdict() == "passed" && r.checks.len() == 2));
}

/// Two processes, each running TINY 200 times, into `store` at once; every run arrives
/// complete with its check.
fn two_processes_of_200_runs(dir: &Path, store: &str) {
    let recipe = write_file(dir, "tiny.yaml", TINY);
    let before = Locator::parse(store)
        .open(true)
        .and_then(|mut s| s.list(&every_run()))
        .expect("the store opens")
        .len();
    let files: Vec<&str> = std::iter::repeat_n(recipe.to_str().unwrap(), 200).collect();
    let children: Vec<_> = (0..2)
        .map(|_| {
            command()
                .args(["run", "--fast", "--quiet", "--results", store])
                .args(&files)
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .expect("runs")
        })
        .collect();
    for child in children {
        let out = child.wait_with_output().expect("ends");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{err}");
        assert_lacks(&err, &["spool", "lost"]);
    }
    let mut s = Locator::parse(store).open(false).expect("opens");
    let runs = s.with_checks(&every_run()).expect("runs");
    assert_eq!(runs.len(), before + 400);
    assert!(runs
        .iter()
        .all(|r| r.verdict() == "passed" && r.checks.len() == 1));
}

#[test]
fn two_processes_of_200_runs_each_lose_nothing_in_one_sqlite_file() {
    let dir = scratch("concurrent");
    two_processes_of_200_runs(&dir, &sqlite_store(&dir));
}

/// Hostile serial numbers stored verbatim, one learnt after the start; `store`'s runs of
/// each unit found by its serial.
fn hostile_serials_round_trip(dir: &Path, store: &str) {
    let recipe = write_file(dir, "tiny.yaml", TINY);
    for s in HOSTILE {
        assert_eq!(recorded_run(&recipe, store, serial(s), None, &[]), 0);
    }
    let late = UnitIdentity {
        serial: Some("late 'one' ✓".into()),
        operator: Some("Zoë \"Robert'); --".into()),
        ..UnitIdentity::default()
    };
    assert_eq!(
        recorded_run(&recipe, store, UnitIdentity::default(), Some(late.clone()), &[]),
        0
    );
    let mut s = Locator::parse(store).open(false).expect("opens");
    for hostile in HOSTILE.iter().chain([&"late 'one' ✓"]) {
        let runs = s.unit_runs(hostile, true).expect("runs of the unit");
        assert_eq!(runs.len(), 1, "{hostile}");
        assert_eq!(runs[0].run.unit.serial.as_deref(), Some(*hostile));
        assert_eq!(runs[0].checks.len(), 1);
    }
    let late_run = s.unit_runs("late 'one' ✓", true).expect("late");
    assert_eq!(late_run[0].run.unit.operator, late.operator);
    let listed = list(store, &["--unit", HOSTILE[2]]);
    assert_has(&listed.stdout, &[HOSTILE[2]]);
    assert_eq!(listed.stdout.lines().count(), 2, "{}", listed.stdout);
}

#[test]
fn hostile_serial_numbers_round_trip_in_sqlite() {
    let dir = scratch("hostile");
    hostile_serials_round_trip(&dir, &sqlite_store(&dir));
}

#[test]
fn a_foreign_or_damaged_file_is_refused_clearly() {
    let (dir, junk) = scratch_file("foreign", "notes.txt", &"not a database at all\n".repeat(200));
    let refused = cli(&["results", "list", "--results", junk.to_str().unwrap()], 2);
    assert_has(
        &refused.stderr,
        &[
            junk.to_str().unwrap(),
            "is not a drivescript results store",
            "damaged or of another kind",
            "--results",
        ],
    );
    let other = dir.join("other.sqlite");
    rusqlite::Connection::open(&other)
        .and_then(|c| c.execute_batch("CREATE TABLE invoices (id INTEGER)"))
        .expect("another application's database");
    let refused = cli(&["results", "list", "--results", other.to_str().unwrap()], 2);
    assert_has(
        &refused.stderr,
        &["is not a drivescript results store", "other tables (invoices)"],
    );
    // A run with such a store still runs and keeps its record in the spool.
    let recipe = write_file(&dir, "tiny.yaml", TINY);
    let ran = run_recorded(&recipe, other.to_str().unwrap(), &[], 0);
    assert_has(
        &ran.stderr,
        &["is not a drivescript results store", "other.sqlite.spool"],
    );
    let missing = cli(
        &[
            "results",
            "list",
            "--results",
            dir.join("none.sqlite").to_str().unwrap(),
        ],
        1,
    );
    assert_has(&missing.stderr, &["there is no results store at"]);
}

#[test]
fn the_unit_certificate_renders_in_headless_chromium() {
    let (dir, s) = &scratch_store("certificate");
    let recipe = write_file(dir, "short.yaml", SHORT);
    let unit = UnitIdentity {
        serial: Some("SP-104233".into()),
        part: Some("HSK-63 spindle <motor & co>".into()),
        operator: Some("J. Smith".into()),
        station: Some("Bench 3".into()),
    };
    assert_eq!(recorded_run(&recipe, s, unit.clone(), None, &[]), 0);
    assert_eq!(recorded_run(&recipe, s, unit, None, &[("speed", "6000rpm")]), 0);
    let page = dir.join("certificate.html");
    let html = unit_certificate(s, "SP-104233", &page);
    let doc = scraper::Html::parse_document(&html);
    assert!(doc.errors.is_empty(), "{:?}", doc.errors);
    let rows = scraper::Selector::parse("#runs tbody tr").expect("selector");
    assert_eq!(doc.select(&rows).count(), 2);
    assert_has(
        &html,
        &[
            "Unit SP-104233",
            "HSK-63 spindle &lt;motor &amp; co&gt;",
            "Bench 3",
            "J. Smith",
            "<svg",
        ],
    );
    assert_lacks(&html, &["<motor"]);
    // Kept for a look: target/results-certificate.png.
    screenshot(&page, "1000,1400", "results-certificate");
}

#[test]
fn postgresql_records_runs_from_a_fleet_and_spools_while_the_server_is_down() {
    let Some((server, dir)) = postgres_with_folder("postgres") else {
        return;
    };
    let url = server.url();
    hostile_serials_round_trip(&dir, &url);
    two_processes_of_200_runs(&dir, &url);
    // The password is never shown.
    let listed = list(&url, &["--limit", "3"]);
    assert_lacks(&format!("{}{}", listed.stdout, listed.stderr), &["pw-s3cret"]);
    // Down during a run: spooled (beside the data directory), delivered after.
    server.down();
    let recipe = write_file(&dir, "short.yaml", SHORT);
    let out = command()
        .envs(crate::support::data_home(&dir))
        .args([
            "run",
            recipe.to_str().unwrap(),
            "--fast",
            "--results",
            &url,
            "--set",
            "speed=4321rpm",
        ])
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert_has(
        &err,
        &[
            "cannot be reached",
            "results sync",
            "postgres://drivescript@127.0.0.1",
        ],
    );
    assert_lacks(&err, &["pw-s3cret"]);
    server.up();
    let synced = command()
        .envs(crate::support::data_home(&dir))
        .args(["results", "sync", "--results", &url])
        .output()
        .expect("syncs");
    Ran::exited(synced, 0);
    let runs = all_runs(&url);
    let spooled = runs
        .iter()
        .find(|r| r.run.params.first().is_some_and(|p| p.1.contains("4321")))
        .expect("delivered");
    assert_eq!(spooled.verdict(), "passed");
    assert_eq!(spooled.checks.len(), 2);
    assert_eq!(spooled.end.as_ref().map(|e| e.series.len()), Some(1));
}

#[test]
fn postgresql_over_tls_checks_the_certificate_against_the_given_ca() {
    let Some((server, ca)) = PostgresServer::start_tls("postgres-tls") else {
        return;
    };
    let url = server.url();
    // The server takes only TLS: without it, refused.
    let plain = cli(
        &["results", "sync", "--results", &format!("{url}?sslmode=disable")],
        0,
    );
    assert_has(&plain.stdout, &["nothing to deliver"]);
    let refused = cli(
        &["results", "list", "--results", &format!("{url}?sslmode=disable")],
        3,
    );
    assert_has(&refused.stderr, &["cannot be reached"]);
    // TLS with a certificate of an unknown CA: refused, whatever sslmode says.
    let unknown = cli(
        &["results", "list", "--results", &format!("{url}?sslmode=require")],
        3,
    );
    assert_has(&unknown.stderr, &["certificate"]);
    // With the factory's CA: the store opens, over TLS only.
    let with_ca = format!("{url}?sslmode=require&sslrootcert={}", ca.display());
    let listed = cli(&["results", "list", "--results", &with_ca, "--simulated"], 0);
    assert_has(&listed.stdout, &["no runs in postgres://drivescript@127.0.0.1"]);
    assert_lacks(&format!("{}{}", listed.stdout, listed.stderr), &["pw-s3cret"]);
}

/// A store that takes the connection and never answers (a PostgreSQL server in trouble, a
/// firewall that swallows replies) while a long run fills the recorder's queue: the run
/// still ends, with its exit code, instead of waiting for room in the queue for ever.
#[test]
fn a_store_that_never_answers_does_not_hold_up_the_end_of_a_long_run() {
    // More steps than the recorder's queue holds.
    let (dir, recipe) = scratch_file(
        "silent-store",
        "long.yaml",
        "name: Long\ndrive: sd2\nsteps:\n  - repeat:\n      times: 5000\n      steps:\n        - print: \"pass\"\n",
    );
    let mut child = run_into_a_silent_store(&dir, &recipe, "--quiet");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
    let status = loop {
        if let Some(status) = child.try_wait().expect("waits") {
            break Some(status);
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    let out = child.wait_with_output().expect("output");
    let text = console(&out.stdout, &out.stderr);
    let status = status.unwrap_or_else(|| panic!("the run did not end within 20 s:\n{text}"));
    assert_eq!(status.code(), Some(0), "{text}");
    assert_has(&text, &["PASSED", "did not answer", "results sync"]);
}

/// The end of a run waits for a store that has not taken everything only until a stop
/// signal comes (the drive is stopped by then; the store is never on the stop's path), and
/// what the writer had not taken is kept whole in the spool, the run's start to its end,
/// not lost with the process. The signal is SIGTERM, a service manager's; Windows has
/// none, there it is Ctrl-C.
#[test]
fn a_signal_ends_the_wait_for_a_silent_store_and_the_whole_run_is_spooled() {
    let (dir, recipe) = scratch_file("silent-store-signal", "short.yaml", SHORT);
    let mut run = LiveRun::with(|run| into_a_silent_store(run, &dir, &recipe, "--no-progress"));
    let mut stderr = run.take_stderr();
    let said = std::thread::spawn(move || {
        let mut text = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut text).map(|_| text)
    });
    let seen = run.wait_for("PASSED").to_string();
    // The writer is still trying to reach the store (for up to 10 s): the end waits.
    std::thread::sleep(std::time::Duration::from_millis(500));
    let signalled = std::time::Instant::now();
    run.signal(if cfg!(windows) { "INT" } else { "TERM" });
    let (code, _) = run.finish();
    let waited = signalled.elapsed();
    let text = said.join().expect("stderr reader").expect("stderr");
    assert_eq!(
        code,
        Some(0),
        "the run had passed before the signal:\n{seen}{text}"
    );
    assert!(
        waited < std::time::Duration::from_secs(5),
        "the end waited {waited:?} after the signal:\n{text}"
    );
    assert_has(
        &text,
        &[
            "had not taken the whole run",
            "or a stop signal came",
            "results sync",
        ],
    );
    let spool = std::fs::read_dir(dir.join("drivescript"))
        .expect("the data directory")
        .flatten()
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|x| x == "spool"))
        .expect("a spool file");
    let lines = std::fs::read_to_string(&spool).expect("the spool");
    assert_has(
        &lines,
        &[
            "\"record\":\"started\"",
            "Short acceptance",
            "\"record\":\"check\"",
            "\"record\":\"finished\"",
        ],
    );
}

/// `run RECIPE --fast OUTPUT` recording into a PostgreSQL "server" that takes the
/// connection and never answers, with `dir` as the data directory (for the spool).
fn run_into_a_silent_store(dir: &Path, recipe: &Path, output: &str) -> std::process::Child {
    let mut run = command();
    into_a_silent_store(&mut run, dir, recipe, output);
    run.stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs")
}

/// Makes `run` the command of [`run_into_a_silent_store`].
fn into_a_silent_store(run: &mut std::process::Command, dir: &Path, recipe: &Path, output: &str) {
    let url = format!("postgres://drivescript@127.0.0.1:{}/results", silent_server());
    run.envs(crate::support::data_home(dir)).args([
        "run",
        recipe.to_str().unwrap(),
        "--fast",
        output,
        "--results",
        &url,
    ]);
}

/// The connect timeout bounds only the socket's connection; the handshake after it is
/// bounded too, so `results` commands (and the recorder's writer) do not wait for ever.
#[test]
fn a_server_that_takes_the_connection_and_never_answers_is_unreachable_in_time() {
    let url = format!("postgres://drivescript@127.0.0.1:{}/results", silent_server());
    let started = std::time::Instant::now();
    let mut child = command()
        .args(["results", "list", "--results", &url])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let ended = loop {
        if child.try_wait().expect("waits").is_some() {
            break true;
        }
        if started.elapsed() > std::time::Duration::from_secs(30) {
            let _ = child.kill();
            break false;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    let out = child.wait_with_output().expect("output");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(ended, "`results list` still waited after 30 s:\n{err}");
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert_has(&err, &["cannot be reached", "did not answer within 10 s"]);
}

/// The stored hash is of the recipe's text with every file it includes: an edit of an
/// included stage changes it, as an edit of the recipe does; a recipe without includes
/// hashes as `sha256sum` of its file.
#[test]
fn the_recipe_hash_covers_every_included_file() {
    let (dir, store) = &scratch_store("hash-includes");
    let stage = write_file(dir, "stage.yaml", TINY);
    let recipe = write_file(
        dir,
        "main.yaml",
        "name: With a stage\ndrive: sd2\nsteps:\n  - include: stage.yaml\n  - include: stage.yaml\n",
    );
    let hash_of_a_run = |file: &Path| {
        let (code, out) = run_recording(file, store, &["--fast"]);
        assert_eq!(code, 0, "{out}");
        let mut s = Locator::parse(store).open(false).expect("opens");
        let runs = s.list(&every_run()).expect("list");
        runs[0].run.recipe_sha256.clone().expect("a hash")
    };
    let before = hash_of_a_run(&recipe);
    assert_eq!(hash_of_a_run(&recipe), before, "the same text, the same hash");
    std::fs::write(&stage, TINY.replace("100 V", "200 V")).expect("the stage edited");
    let after = hash_of_a_run(&recipe);
    assert_ne!(after, before, "an included file's edit changes the hash");
    // Alone, a file hashes as sha256sum does.
    let alone = hash_of_a_run(&stage);
    if let Ok(out) = std::process::Command::new("sha256sum").arg(&stage).output() {
        let sum = String::from_utf8_lossy(&out.stdout);
        assert_eq!(sum.split_whitespace().next(), Some(alone.as_str()));
    }
}

/// A run refused before it started is kept for its unit when the unit is known (by
/// `--unit` or an answer given beforehand): verdict refused (exit code 2) or error (its
/// drive could not be reached), with the reason and no checks. Without a serial it is a
/// file being written and is not recorded. The unit's certificate still heads with its
/// latest run that started.
#[test]
fn a_run_refused_before_it_started_is_kept_for_its_unit() {
    let dir = scratch("refused-runs");
    let store = dir.join("results.sqlite");
    let s = store.to_str().unwrap();
    let good = write_file(&dir, "tiny.yaml", TINY);
    let broken = write_file(
        &dir,
        "broken.yaml",
        "name: Broken\ndrive: sd2\nsteps:\n  - set: { speed_setpont: 5 rpm }\n",
    );
    let scanned = write_file(
        &dir,
        "scanned.yaml",
        "name: Scanned\ndrive: sd2\nsteps:\n  - enter_text: { prompt: Serial, sets: serial }\n    name: serial\n  - expect: { bus_voltage: { above: 100 V } }\n",
    );
    let run = |args: &[&str], code: i32| {
        let (got, text) = run_recording(Path::new(args[0]), s, &args[1..]);
        assert_eq!(got, code, "{text}");
    };
    let good_path = good.to_str().unwrap();
    run(&[good_path, "--fast", "--unit", "serial=RF-1"], 0);
    run(&[broken.to_str().unwrap(), "--fast", "--unit", "serial=RF-1"], 2);
    run(&[broken.to_str().unwrap(), "--fast"], 2);
    run(
        &[
            scanned.to_str().unwrap(),
            "--fast",
            "--port",
            "/dev/null",
            "--answer",
            "serial=RF-2",
        ],
        2,
    );
    run(
        &[
            good_path,
            "--port",
            "/dev/drivescript-no-such-port",
            "--unit",
            "serial=RF-1",
        ],
        3,
    );
    // A report file that cannot be written is an invalid command line like the others.
    let not_a_dir = write_file(&dir, "not-a-directory", "");
    let junit = not_a_dir.join("junit.xml");
    run(
        &[
            good_path,
            "--fast",
            "--unit",
            "serial=RF-3",
            "--junit",
            junit.to_str().unwrap(),
        ],
        2,
    );
    let runs = all_runs(s);
    assert_eq!(
        runs.len(),
        5,
        "the run without a serial is not recorded: {runs:#?}"
    );
    let [unwritable] = runs
        .iter()
        .filter(|r| r.run.unit.serial.as_deref() == Some("RF-3") && r.verdict() == "refused")
        .collect::<Vec<_>>()[..]
    else {
        panic!("the run refused for its report file is kept for RF-3: {runs:#?}");
    };
    assert_has(
        unwritable
            .end
            .as_ref()
            .and_then(|e| e.reason.as_deref())
            .unwrap_or(""),
        &["not-a-directory"],
    );
    let of = |serial: &str, verdict: &str| {
        runs.iter()
            .filter(|r| r.run.unit.serial.as_deref() == Some(serial) && r.verdict() == verdict)
            .collect::<Vec<_>>()
    };
    let [refused] = of("RF-1", "refused")[..] else {
        panic!("one refused run of RF-1: {runs:#?}");
    };
    assert!(!refused.started() && refused.checks.is_empty() && refused.steps.is_empty());
    let end = refused.end.as_ref().expect("ended");
    assert_eq!(end.exit_code, 2);
    assert_has(
        end.reason.as_deref().unwrap_or(""),
        &["speed_setpont", "nothing was sent"],
    );
    assert_eq!(refused.run.recipe_path, broken.display().to_string());
    let [answered] = of("RF-2", "refused")[..] else {
        panic!("the serial answered beforehand names the unit: {runs:#?}");
    };
    assert_eq!(answered.run.recipe, "Scanned");
    let [unreachable] = of("RF-1", "error")[..] else {
        panic!("one run of RF-1 whose drive could not be reached: {runs:#?}");
    };
    assert_eq!(unreachable.end.as_ref().map(|e| e.exit_code), Some(3));
    assert_has(
        unreachable
            .end
            .as_ref()
            .and_then(|e| e.reason.as_deref())
            .unwrap_or(""),
        &["drivescript-no-such-port"],
    );
    // Listed and filtered like any run; the certificate heads with the passed run.
    let listed = list(s, &["--verdict", "refused"]);
    assert_has(&listed.stdout, &["REFUSED", "RF-1", "RF-2"]);
    let html = unit_certificate(s, "RF-1", &dir.join("RF-1.html"));
    assert_has(
        &html,
        &["id=\"verdict\">✔ PASSED", "3 run(s) recorded", "REFUSED", "ERROR"],
    );
    // Each attempt that never started says why, and never that a stop failed: nothing
    // was sent to the drive.
    assert_has(
        &html,
        &[
            "speed_setpont",
            "drivescript-no-such-port",
            "not started: nothing was sent to the drive",
        ],
    );
    assert_lacks(&html, &["NOT CONFIRMED"]);
}
