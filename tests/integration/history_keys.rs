//! A check stays the same check across runs when its limits change, against a real SQLite
//! file and a real PostgreSQL server: a unit's run after a limit was tightened (and a
//! coast-down's, also one the recipe names) still compares with the run before it and
//! names it; `results trend` lists the runs before and after the change, each with its
//! own limits; a store written by the version-2 schema migrates, and its runs still serve
//! as history (a check the recipe named by its full name).

use crate::history::run_id;
use crate::support::{
    assert_exit, assert_has, assert_lacks, cli, line_with, postgres_with_folder, run_recording as run,
    scratch, sqlite_store, with_postgres_store, with_sqlite_store, write_file,
};
use std::path::Path;

/// The recipe `Bearing history` with the motor temperature's limit and what a run without
/// history does; the simulated motor is at 25 °C.
fn bearing(dir: &Path, file: &str, limit: &str, without_history: &str) -> std::path::PathBuf {
    let text = format!(
        "name: Bearing history
drive: sd2
steps:
  - go_to: operation_enabled
  - expect:
      motor_temperature:
        below: {limit}
        compared_with_last_pass: {{ at_most: 2 K, at_least: -2 K, without_history: {without_history} }}
"
    );
    write_file(dir, file, &text)
}

/// A limit tightened from 90 °C to 80 °C: the second run compares with the first (its
/// `without_history: fail` would fail it otherwise), then `results trend` by the new name
/// and by the key lists both runs with the limits each had.
fn tightened_limit_in(dir: &Path, store: &str) {
    let before = bearing(dir, "before.yaml", "90 °C", "pass");
    let after = bearing(dir, "after.yaml", "80 °C", "fail");
    let unit = ["--fast", "--unit", "serial=SP-7"];
    let (code, first) = run(&before, store, &unit);
    assert_eq!(code, 0, "{first}");
    let first_id = run_id(&first);
    let (code, second) = run(&after, store, &unit);
    assert_eq!(code, 0, "compared with the run before the change:\n{second}");
    assert_has(
        &second,
        &[
            &format!("history SP-7: compared with its last pass, run {first_id} of 20"),
            "motor_temperature below 80 °C = 25 °C",
            &format!("PASS  motor_temperature below 80 °C compared with last pass: motor_temperature = 25 °C: 0 K against 25 °C in run {first_id}"),
        ],
    );
    assert_lacks(&second, &["has no check", "not in that run", "without_history"]);
    let second_id = run_id(&second);
    let page = dir.join("trend.html");
    for check in ["motor_temperature below 80 °C", "motor_temperature below"] {
        let args = ["results", "trend", check, "--simulated", "--results", store];
        let trend = cli(&[&args[..], &["--html", page.to_str().unwrap()]].concat(), 0);
        let row = |id: &str| line_with(&trend.stdout, id);
        assert!(row(&first_id).contains("< 90 °C"), "{}", trend.stdout);
        assert!(row(&second_id).contains("< 80 °C"), "{}", trend.stdout);
        assert_eq!(trend.stdout.lines().count(), 3, "{}", trend.stdout);
        let html = std::fs::read_to_string(&page).expect("the trend page");
        // The limit line steps down from 90 to 80 °C where the limit was changed.
        assert_has(
            &html,
            &[
                "Trend of motor_temperature below",
                "<path class=\"limit\"",
                "&lt; 80 °C</text>",
                "<td class=\"num\">&lt; 90 °C</td>",
            ],
        );
        // --limit keeps the newest.
        let newest = cli(&[&args[..], &["--limit", "1"]].concat(), 0).stdout;
        assert!(
            newest.contains(&second_id) && !newest.contains(&first_id),
            "{newest}"
        );
    }
    // The comparisons too: one key whatever the limits of the check they compare.
    let trend = cli(
        &[
            "results",
            "trend",
            "motor_temperature below compared with last pass",
            "--simulated",
            "--json",
            "--results",
            store,
        ],
        0,
    );
    let points: serde_json::Value = serde_json::from_str(&trend.stdout).expect("JSON");
    let names: Vec<&str> = points
        .as_array()
        .expect("a list")
        .iter()
        .filter_map(|p| p["check"].as_str())
        .collect();
    assert_eq!(
        names,
        [
            "motor_temperature below 90 °C compared with last pass",
            "motor_temperature below 80 °C compared with last pass"
        ]
    );
}

/// A coast-down whose limit was raised, and one the recipe names (its `name:` names the
/// check): each second run compares its time with the first's.
fn coast_down_changed_in(dir: &Path, store: &str) {
    let coast = |file: &str, name: &str, step_name: &str, limit: &str, without_history: &str| {
        let text = format!(
            "name: {name}
drive: sd2
steps:
  - set: {{ speed_setpoint: 6000 rpm }}
  - go_to: operation_enabled
  - wait_until: {{ speed_actual: {{ near: 6000 rpm, within: 1 % }} }}
  - coast_down:
      from: 5900 rpm
      below: 100 rpm
      expect: {{ above: {limit}, compared_with_last_pass: {{ at_least: -10 %, without_history: {without_history} }} }}
{step_name}"
        );
        let file = write_file(dir, file, &text);
        run(
            &file,
            store,
            &["--fast", "--unit", "serial=SP-8", "--sim", "coast-rate=300rpm/s"],
        )
    };
    let (code, first) = coast("coast1.yaml", "Coast history", "", "10 s", "pass");
    assert_eq!(code, 0, "{first}");
    let first_id = run_id(&first);
    let (code, second) = coast("coast2.yaml", "Coast history", "", "12 s", "fail");
    assert_eq!(code, 0, "compared with the run before the change:\n{second}");
    assert_has(
        &second,
        &[
            &format!("PASS  coast-down from 5900 rpm below 100 rpm above 12 s compared with last pass: coast-down time = 19.334 s: 0 % against 19.334 s in run {first_id}"),
        ],
    );
    let named = "    name: spindle coast-down\n";
    let first = assert_exit(
        coast("named1.yaml", "Named coast", named, "10 s", "pass"),
        0,
        &["PASS  spindle coast-down: coast-down took 19.334 s"],
    );
    let first_id = run_id(&first);
    assert_exit(
        coast("named2.yaml", "Named coast", named, "15 s", "fail"),
        0,
        &[&format!("PASS  spindle coast-down compared with last pass: coast-down time = 19.334 s: 0 % against 19.334 s in run {first_id}")],
    );
}

#[test]
fn a_tightened_limit_keeps_the_units_history_in_sqlite() {
    with_sqlite_store("keys", |dir, store| {
        tightened_limit_in(dir, store);
        coast_down_changed_in(dir, store);
    });
}

#[test]
fn a_tightened_limit_keeps_the_units_history_in_postgresql() {
    with_postgres_store("keys", |dir, store| {
        tightened_limit_in(dir, store);
        coast_down_changed_in(dir, store);
    });
}

/// What a version-2 drivescript left: the schema of migrations 1 and 2, and a passed run
/// of `Bearing history` on SP-OLD with a check named by its limits (`motor_temperature
/// below 90 °C`), one the recipe named (`bearing temperature`) and one the recipe named as
/// drivescript would have (`Temperature below 95 °C`, which the migration keys by what
/// its name shows).
fn version_2_store(batch: &mut dyn FnMut(&str)) {
    for v in 1..=2 {
        batch(drivescript::results::migration(v).expect("a migration of version 2"));
    }
    batch(
        "INSERT INTO drivescript_store (key, value) VALUES ('application', 'drivescript results');
         INSERT INTO drivescript_store (key, value) VALUES ('schema', '2');
         INSERT INTO runs (id, kind, recipe, recipe_path, tool_version, started_at, simulated,
            drive, serial, params, ended_at, verdict, exit_code)
            VALUES ('0ld5tore', 'recipe', 'Bearing history', 'bearing.yaml', '0.1.0',
            '2026-01-01T08:00:00.000Z', 1, 'drive 2 on built-in simulated drive', 'SP-OLD',
            '[]', '2026-01-01T08:01:00.000Z', 'passed', 0);
         INSERT INTO checks (run_id, seq, name, measured, unit, high, passed, marginal, step,
            stage, attempt, message)
            VALUES ('0ld5tore', 1, 'motor_temperature below 90 °C', 24, '°C', 90, 1, 0, '2', '', 1, 'ok'),
                   ('0ld5tore', 2, 'bearing temperature', 24.5, '°C', 90, 1, 0, '3', '', 1, 'ok'),
                   ('0ld5tore', 3, 'Temperature below 95 °C', 24.8, '°C', 95, 1, 0, '4', '', 1, 'ok');",
    );
}

/// The run after the upgrade: the first check's limit changed since (found by the key its
/// old name shows), the others keep their names (found by them).
fn old_runs_serve_as_history(dir: &Path, store: &str) {
    let recipe = write_file(
        dir,
        "bearing.yaml",
        "name: Bearing history
drive: sd2
steps:
  - go_to: operation_enabled
  - expect:
      motor_temperature: { below: 80 °C, compared_with_last_pass: { at_most: 2 K, without_history: fail } }
  - expect:
      motor_temperature: { below: 90 °C, compared_with_last_pass: { at_most: 2 K, without_history: fail } }
    name: bearing temperature
  - expect:
      motor_temperature: { below: 95 °C, compared_with_last_pass: { at_most: 2 K, without_history: fail } }
    name: Temperature below 95 °C
",
    );
    assert_exit(
        run(&recipe, store, &["--fast", "--unit", "serial=SP-OLD"]),
        0,
        &[
            "history SP-OLD: compared with its last pass, run 0ld5tore of 2026-01-01T08:00:00.000Z",
            "PASS  motor_temperature below 80 °C compared with last pass: motor_temperature = 25 °C: +1 K against 24 °C in run 0ld5tore",
            "PASS  bearing temperature compared with last pass: motor_temperature = 25 °C: +0.5 K against 24.5 °C in run 0ld5tore",
            "PASS  Temperature below 95 °C compared with last pass: motor_temperature = 25 °C: +0.2 K against 24.8 °C in run 0ld5tore",
        ],
    );
    let trend = cli(
        &[
            "results",
            "trend",
            "bearing temperature",
            "--simulated",
            "--results",
            store,
        ],
        0,
    );
    // The new run's value at motor_temperature's resolution (0.1 °C), as the HTML shows it.
    assert_has(&trend.stdout, &["0ld5tore", "24.5 °C", "25.0 °C"]);
}

#[test]
fn a_version_2_sqlite_store_migrates_and_its_runs_still_serve_as_history() {
    let dir = scratch("keys-v2-sqlite");
    let path = dir.join("results.sqlite");
    let db = rusqlite::Connection::open(&path).expect("a version 2 store");
    version_2_store(&mut |sql| db.execute_batch(sql).expect("version 2 SQL"));
    drop(db);
    old_runs_serve_as_history(&dir, path.to_str().unwrap());
    let db = rusqlite::Connection::open(&path).expect("opens");
    let version: String = db
        .query_row(
            "SELECT value FROM drivescript_store WHERE key = 'schema'",
            [],
            |r| r.get(0),
        )
        .expect("its version");
    assert_eq!(version, drivescript::results::current_version().to_string());
    let key = |name: &str| -> Option<String> {
        db.query_row(
            "SELECT check_key FROM checks WHERE run_id = '0ld5tore' AND name = ?1",
            [name],
            |r| r.get(0),
        )
        .expect("the old check")
    };
    assert_eq!(
        key("motor_temperature below 90 °C").as_deref(),
        Some("motor_temperature below")
    );
    assert_eq!(key("bearing temperature"), None, "a given name is its own key");
}

#[test]
fn a_version_2_postgresql_store_migrates_and_its_runs_still_serve_as_history() {
    let Some((server, dir)) = postgres_with_folder("keys-v2-postgres") else {
        return;
    };
    let mut db = postgres::Client::connect(&server.url(), postgres::NoTls).expect("connects");
    version_2_store(&mut |sql| db.batch_execute(sql).expect("version 2 SQL"));
    old_runs_serve_as_history(&dir, &server.url());
    let row = db
        .query_one(
            "SELECT check_key FROM checks WHERE run_id = '0ld5tore' AND seq = 1",
            &[],
        )
        .expect("the old check");
    assert_eq!(
        row.get::<_, Option<String>>(0).as_deref(),
        Some("motor_temperature below")
    );
}

/// A check the recipe named keeps its limit as the run wrote it in the store's pages:
/// `below: 90 °C` is `< 90 °C` in `results trend`, its page and the unit certificate (as
/// on the console), an `enter_value`'s `at_most` `≤`; the name alone cannot say which.
#[test]
fn a_named_checks_limit_reads_in_the_stores_pages_as_in_the_run() {
    let dir = scratch("named-limits");
    let store = &sqlite_store(&dir);
    let recipe = write_file(
        &dir,
        "named.yaml",
        "name: Named limits
drive: sd2
steps:
  - expect: { motor_temperature: { below: 90 °C } }
    name: bearing temperature
  - enter_value: { prompt: Vibration, unit: mm/s, at_most: 2.8 mm/s }
    name: vibration
",
    );
    assert_exit(
        run(
            &recipe,
            store,
            &["--fast", "--unit", "serial=SP-9", "--answer", "vibration=1.2"],
        ),
        0,
        &["bearing temperature: motor_temperature = 25 °C (limit < 90 °C)"],
    );
    let page = dir.join("trend.html");
    let trend = |check: &str| crate::trend_page::trend(Path::new(store), check, &page, &[]);
    let (table, page) = trend("bearing temperature");
    assert_has(&table, &["< 90 °C"]);
    assert_lacks(&table, &["≤ 90 °C"]);
    assert_has(&page, &["&lt; 90 °C"]);
    assert_lacks(&page, &["≤ 90 °C"]);
    let (table, _) = trend("Vibration");
    assert_has(&table, &["≤ 2.8 mm/s"]);
    let certificate = crate::support::unit_certificate(store, "SP-9", &dir.join("unit.html"));
    assert_has(&certificate, &["&lt; 90 °C", "≤ 2.8 mm/s"]);
    assert_lacks(&certificate, &["≤ 90 °C"]);
}
