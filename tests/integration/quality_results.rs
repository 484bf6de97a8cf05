//! What a quality lead asks of the results store, against a real SQLite file and a real
//! PostgreSQL server: a trend is of one measurement (a key shared by two stages or two
//! recipes is refused with the names that tell them apart; the JUnit test-case name and a
//! stage's full name are taken), the comparison with a unit's last pass stays within its
//! stage after the recipe moved its steps; filters by station, operator, part and dates;
//! first-pass and final yield; Cp and Cpk with a histogram page; a void with who, when and
//! why that keeps the run, marks it everywhere and leaves it out of yield and trend.

use crate::history::run_id;
use crate::support::{
    assert_has, assert_lacks, cli, line_with, run_recording as run, with_postgres_store, with_sqlite_store,
    write_file,
};
use drivescript::results::{CheckRow, EndRow, Locator, Record, RunRow};
use drivescript::session::{Limits, UnitIdentity};
use std::path::Path;

/// A recipe of two stages, each holding `speed_actual mean near` at its own speed, compared
/// with the unit's last pass within 1 %; `before` steps come first (a recipe edited later
/// moves every step).
fn staged(dir: &Path, file: &str, name: &str, before: &str, without_history: &str) -> std::path::PathBuf {
    let stage = |n: u32, speed: u32| {
        format!(
            "  - name: \"Stage {n}, {speed} rpm\"
    repeat:
      times: 1
      steps:
        - set: {{ speed_setpoint: {speed} rpm }}
        - wait_until: {{ speed_actual: {{ near: {speed} rpm, within: 1 % }}, timeout: 30 s }}
        - sample: {{ objects: [speed_actual], every: 1 s, for: 10 s }}
        - expect:
            speed_actual:
              mean:
                near: {speed} rpm
                within: 1 %
                compared_with_last_pass: {{ at_most: 1 %, at_least: -1 %, without_history: {without_history} }}
"
        )
    };
    let text = format!(
        "name: {name}\ndrive: sd2\nsteps:\n{before}  - go_to: operation_enabled\n{}{}",
        stage(1, 6000),
        stage(2, 12000)
    );
    write_file(dir, file, &text)
}

/// A recipe of one check at the top level with the same key and name as stage 1's.
fn other(dir: &Path) -> std::path::PathBuf {
    write_file(
        dir,
        "other.yaml",
        "name: Other spindle
drive: sd2
steps:
  - set: { speed_setpoint: 6000 rpm }
  - go_to: operation_enabled
  - wait_until: { speed_actual: { near: 6000 rpm, within: 1 % }, timeout: 30 s }
  - sample: { objects: [speed_actual], every: 1 s, for: 10 s }
  - expect: { speed_actual: { mean: { near: 6000 rpm, within: 1 % } } }
",
    )
}

fn trend(store: &str, check: &str, extra: &[&str], code: i32) -> crate::support::Ran {
    cli(
        &[
            &["results", "trend", check, "--simulated", "--results", store][..],
            extra,
        ]
        .concat(),
        code,
    )
}

fn stages_in(dir: &Path, store: &str) {
    let first = staged(dir, "stages.yaml", "Spindle stages", "", "pass");
    let junit = dir.join("first.xml");
    let (code, out) = run(
        &first,
        store,
        &[
            "--fast",
            "--unit",
            "serial=SP-1",
            "--junit",
            junit.to_str().unwrap(),
            "--report",
            dir.join("first.html").to_str().unwrap(),
        ],
    );
    assert_eq!(code, 0, "{out}");
    // The run report: simulated beside its verdict, the recipe's hash and the tool.
    let report = std::fs::read_to_string(dir.join("first.html")).expect("the run report");
    assert_has(
        &report,
        &[
            "id=\"verdict\">✔ PASSED <span class=\"simulated\">(SIMULATED DRIVE)</span>",
            "<th scope=\"row\">Recipe SHA-256</th><td>",
            &format!(
                "<th scope=\"row\">Tool</th><td>drivescript {}",
                env!("CARGO_PKG_VERSION")
            ),
            ">12000.060 rpm<",
        ],
    );
    // The checks counted passed are the PASS lines shown; the waits are met on their
    // step lines and counted apart.
    assert_eq!(out.matches("        PASS  ").count(), 4, "{out}");
    assert_has(&out, &["4 check(s) passed, 0 failed, 2 wait(s) met"]);
    let sp1 = run_id(&out);
    // The recipe edited: a step before the stages moves each of them; a unit's second run
    // compares each stage with its own (on a store that merged them, stage 1's 6000 rpm
    // would be compared with stage 2's 12000 rpm: -50 %).
    let edited = staged(dir, "edited.yaml", "Spindle stages", "  - dwell: 1 s\n", "fail");
    let (code, out) = run(&edited, store, &["--fast", "--unit", "serial=SP-1"]);
    assert_eq!(code, 0, "each stage compared with its own:\n{out}");
    assert_has(
        &out,
        &[
            "PASS  speed_actual mean near 12000 rpm ± 1 % compared with last pass: speed_actual mean = ",
            "PASS  speed_actual mean near 6000 rpm ± 1 % compared with last pass: speed_actual mean = ",
        ],
    );
    assert_lacks(&out, &["-50 %", "has no check"]);
    let (code, out) = run(&first, store, &["--fast", "--unit", "serial=SP-2"]);
    assert_eq!(code, 0, "{out}");
    let sp2 = run_id(&out);
    let (code, out) = run(&other(dir), store, &["--fast", "--unit", "serial=SP-3"]);
    assert_eq!(code, 0, "{out}");
    let sp3 = run_id(&out);

    // The key alone stands for three measurements: refused, each named as JUnit does.
    let refused = trend(store, "speed_actual mean near", &[], 2);
    assert_has(
        &refused.stderr,
        &[
            "`speed_actual mean near` is 3 different checks",
            "\"Stage 1, 6000 rpm #1 / speed_actual mean near\" --recipe \"Spindle stages\"",
            "\"Stage 2, 12000 rpm #1 / speed_actual mean near\" --recipe \"Spindle stages\"",
            "\"speed_actual mean near\" --recipe \"Other spindle\"",
        ],
    );
    // The JUnit test-case name, as the report of the first run printed it.
    let xml = std::fs::read_to_string(&junit).expect("the JUnit report");
    let case = "Stage 2, 12000 rpm #1 / speed_actual mean near";
    assert!(xml.contains(&format!("<testcase name=\"{case}\"")), "{xml}");
    let plot = dir.join("stage2.html");
    let stage2 = trend(store, case, &["--html", plot.to_str().unwrap()], 0).stdout;
    // Each run's own limits across its marker (two sides, three runs).
    let html = std::fs::read_to_string(&plot).expect("the trend page");
    assert_eq!(html.matches("class=\"run-limit\"").count(), 6, "{html}");
    assert_has(
        &html,
        &["(limits 11880 .. 12120 rpm)", "Trend of speed_actual mean near"],
    );
    assert_eq!(stage2.lines().count(), 4, "the header and three runs:\n{stage2}");
    assert!(
        stage2.lines().skip(1).all(|l| l.contains("11880 .. 12120 rpm")),
        "{stage2}"
    );
    assert!(line_with(&stage2, &sp2).contains("SP-2"), "{stage2}");
    assert!(
        stage2.lines().skip(1).all(|l| l.contains("PASS (simulated)")),
        "{stage2}"
    );
    // At the resolution of speed_actual (0.001 rpm) in the trend, JUnit and the certificate,
    // never a float's digits.
    assert!(
        stage2.lines().skip(1).all(|l| l.contains(" 12000.060 rpm ")),
        "{stage2}"
    );
    assert_has(
        &xml,
        &[
            "measured: 12000.060 rpm",
            "<property name=\"simulated\" value=\"true\"/>",
            "<property name=\"recipe_sha256\" value=\"",
        ],
    );
    assert_lacks(&xml, &["12000.0595"]);
    let page = dir.join("sp1.html");
    let certificate = crate::support::unit_certificate(store, "SP-1", &page);
    assert_has(&certificate, &["12000.060 rpm", "(SIMULATED DRIVE)"]);
    assert_lacks(&certificate, &["12000.0595"]);
    // The full name the console shows is stage 1's and the other recipe's: refused, and
    // taken with --recipe.
    let name = "speed_actual mean near 6000 rpm ± 1 %";
    let refused = trend(store, name, &[], 2);
    assert_has(
        &refused.stderr,
        &["is 2 different checks", "--recipe \"Other spindle\""],
    );
    assert_lacks(&refused.stderr, &["Stage 2"]);
    let own = trend(store, name, &["--recipe", "Other spindle"], 0).stdout;
    assert_eq!(own.lines().count(), 2, "{own}");
    assert!(own.contains(&sp3) && !own.contains(&sp1), "{own}");
    let stage1 = trend(store, name, &["--recipe", "Spindle stages", "--json"], 0).stdout;
    let points: serde_json::Value = serde_json::from_str(&stage1).expect("JSON");
    let points = points.as_array().expect("a list");
    assert_eq!(points.len(), 3, "{stage1}");
    assert!(
        points
            .iter()
            .all(|p| p["low"] == 5940.0 && p["stage"] == "Stage 1, 6000 rpm #1"),
        "{stage1}"
    );
    assert!(points
        .iter()
        .all(|p| p["recipe_sha256"].as_str().is_some_and(|h| h.len() == 64)));
    // A check no run has: the hint quotes this store's checks of that object.
    let none = trend(store, "speed_actual max below", &[], 0).stdout;
    assert_has(
        &none,
        &[
            "no run has the check `speed_actual max below`",
            "\"Stage 2, 12000 rpm #1 / speed_actual mean near\"  (recipe `Spindle stages`, step",
        ],
    );
}

#[test]
fn a_trend_is_of_one_measurement_in_sqlite() {
    with_sqlite_store("quality-identity", stages_in);
}

#[test]
fn a_trend_is_of_one_measurement_in_postgresql() {
    with_postgres_store("quality-identity", stages_in);
}

/// One stored run: id, day, station, operator, part, serial, verdict and the bearing
/// temperature it measured (limit 80 °C).
struct Past(
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    bool,
    f64,
);

fn recorded(store: &str, runs: &[Past]) {
    let mut s = Locator::parse(store).open(true).expect("the store opens");
    let mut records = Vec::new();
    for Past(id, day, station, operator, part, serial, passed, temperature) in runs {
        let started_at = format!("{day}T08:00:00.000Z");
        records.push(Record::Started(RunRow {
            id: id.to_string(),
            kind: "recipe".into(),
            recipe: "Bearing acceptance".into(),
            recipe_path: "bearing.yaml".into(),
            recipe_sha256: Some("ab".repeat(32)),
            tool_version: "0.1.0".into(),
            started_at: started_at.clone(),
            simulated: false,
            drive: "drive 1 on /dev/ttyUSB0".into(),
            unit: UnitIdentity {
                serial: Some(serial.to_string()),
                part: Some(part.to_string()),
                operator: Some(operator.to_string()),
                station: Some(station.to_string()),
            },
            ..RunRow::default()
        }));
        records.push(Record::Check(CheckRow {
            run: id.to_string(),
            seq: 1,
            name: "motor_temperature below 80 °C".into(),
            key: Some("motor_temperature below".into()),
            measured: Some(*temperature),
            unit: Some("°C".into()),
            limits: Limits::new(Some(20.0), Some(80.0)),
            passed: *passed,
            step: "2".into(),
            attempt: 1,
            inclusive: Some(false),
            ..CheckRow::default()
        }));
        records.push(Record::Finished(EndRow {
            run: id.to_string(),
            ended_at: started_at,
            verdict: if *passed { "passed" } else { "failed" }.into(),
            exit_code: i64::from(!passed),
            final_state: Some("switch on disabled".into()),
            stop_confirmed: true,
            ..EndRow::default()
        }));
    }
    s.apply_all(&records).expect("the runs are stored");
}

fn results(store: &str, args: &[&str], code: i32) -> crate::support::Ran {
    cli(&[&["results"][..], args, &["--results", store]].concat(), code)
}

fn quality_in(dir: &Path, store: &str) {
    // Day 1 at B1: U1 fails then passes, U2 passes. Day 1 at B2: U3 passes. Day 2 at B1:
    // U4 fails twice; U5 (part P-9, by bob) passes.
    recorded(
        store,
        &[
            Past("run-a", "2026-03-01", "B1", "ann", "P-1", "U1", false, 85.0),
            Past("run-b", "2026-03-01", "B1", "ann", "P-1", "U1", true, 40.0),
            Past("run-c", "2026-03-01", "B1", "ann", "P-1", "U2", true, 50.0),
            Past("run-d", "2026-03-01", "B2", "ann", "P-1", "U3", true, 60.0),
            Past("run-e", "2026-03-02", "B1", "ann", "P-1", "U4", false, 81.0),
            Past("run-f", "2026-03-02", "B1", "ann", "P-1", "U4", false, 82.0),
            Past("run-g", "2026-03-02", "B1", "bob", "P-9", "U5", true, 45.0),
        ],
    );
    let yields = results(store, &["yield", "--json"], 0).stdout;
    let rows: serde_json::Value = serde_json::from_str(&yields).expect("JSON");
    let row = |station: &str, day: &str| {
        rows.as_array()
            .expect("a list")
            .iter()
            .find(|r| r["station"] == station && r["day"] == day)
            .map(|r| {
                (
                    r["units"].clone(),
                    r["first_pass"].clone(),
                    r["final_pass"].clone(),
                    r["runs"].clone(),
                )
            })
    };
    let n = |v: u64| serde_json::Value::from(v);
    assert_eq!(
        row("B1", "2026-03-01"),
        Some((n(2), n(1), n(2), n(3))),
        "{yields}"
    );
    assert_eq!(
        row("B2", "2026-03-01"),
        Some((n(1), n(1), n(1), n(1))),
        "{yields}"
    );
    assert_eq!(
        row("B1", "2026-03-02"),
        Some((n(2), n(1), n(1), n(3))),
        "{yields}"
    );
    let table = results(store, &["yield", "--station", "B1", "--since", "2026-03-02"], 0).stdout;
    assert_has(
        &table,
        &[
            "FPY",
            "Bearing acceptance  B1       2026-03-02  2      1           50.0 %",
        ],
    );
    assert_lacks(&table, &["2026-03-01"]);
    // Every filter, on every listing.
    let list = |args: &[&str]| results(store, &[&["list"][..], args].concat(), 0).stdout;
    assert!(
        list(&["--operator", "bob"]).contains("run-g") && !list(&["--operator", "bob"]).contains("run-a")
    );
    assert!(
        list(&["--part", "P-9"]).lines().count() == 2,
        "{}",
        list(&["--part", "P-9"])
    );
    let until = list(&["--until", "2026-03-01"]);
    assert!(
        until.contains("run-d") && !until.contains("run-e"),
        "the whole of that day:\n{until}"
    );
    let export = results(store, &["export", "--format", "csv", "--station", "B2"], 0).stdout;
    assert!(export.contains("run-d") && !export.contains("run-a"), "{export}");

    // Capability: 7 values against 20 .. 80 °C, with its histogram page.
    let page = dir.join("capability.html");
    let cap = results(
        store,
        &[
            "capability",
            "motor_temperature below",
            "--json",
            "--html",
            page.to_str().unwrap(),
        ],
        0,
    )
    .stdout;
    let c: serde_json::Value = serde_json::from_str(&cap).expect("JSON");
    let values = [85.0, 40.0, 50.0, 60.0, 81.0, 82.0, 45.0];
    let mean = values.iter().sum::<f64>() / 7.0;
    let sigma = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 6.0).sqrt();
    let close = |v: &serde_json::Value, want: f64| (v.as_f64().unwrap_or(f64::NAN) - want).abs() < 1e-9;
    assert!(
        c["n"] == 7 && close(&c["mean"], mean) && close(&c["sigma"], sigma),
        "{cap}"
    );
    assert!(close(&c["cp"], 60.0 / (6.0 * sigma)), "{cap}");
    assert!(close(&c["cpk"], (80.0 - mean) / (3.0 * sigma)), "{cap}");
    let html = std::fs::read_to_string(&page).expect("the capability page");
    assert_has(
        &html,
        &[
            "Capability of motor_temperature below",
            "<svg class=\"histogram\"",
            "class=\"bar\"",
            "<line class=\"spec\"",
        ],
    );
    let bars: usize = html.matches("class=\"bar\"").count();
    assert!(bars >= 5, "{bars} bars");
    let text = results(
        store,
        &["capability", "motor_temperature below", "--station", "B2"],
        0,
    )
    .stdout;
    assert_has(&text, &["n        1", "Cpk      — (one value: σ needs two)"]);

    // A void: kept, marked, left out of yield and trend unless asked; never changed.
    let void = results(
        store,
        &["void", "run-a", "--why", "wrong unit scanned", "--by", "A. Lead"],
        0,
    )
    .stdout;
    assert_has(
        &void,
        &["run run-a voided by A. Lead at ", ": wrong unit scanned"],
    );
    let again = results(store, &["void", "run-a", "--why", "other", "--by", "B"], 2);
    assert_has(
        &again.stderr,
        &["run run-a was voided already, by A. Lead", "wrong unit scanned"],
    );
    assert!(
        line_with(&list(&[]), "run-a").contains("FAILED — VOID"),
        "{}",
        list(&[])
    );
    let show = results(store, &["show", "run-a"], 0).stdout;
    assert_has(
        &show,
        &[
            "VOID     voided by A. Lead at ",
            "wrong unit scanned",
            "motor_temperature below 80 °C",
        ],
    );
    // U1's first run now is run-b, which passed.
    let yields = results(
        store,
        &["yield", "--station", "B1", "--until", "2026-03-01", "--json"],
        0,
    )
    .stdout;
    assert!(
        yields.contains("\"first_pass\": 2") && yields.contains("\"runs\": 2"),
        "{yields}"
    );
    let with_void = results(
        store,
        &[
            "yield",
            "--station",
            "B1",
            "--until",
            "2026-03-01",
            "--json",
            "--include-void",
        ],
        0,
    )
    .stdout;
    assert!(
        with_void.contains("\"first_pass\": 1") && with_void.contains("\"runs\": 3"),
        "{with_void}"
    );
    let t = results(store, &["trend", "motor_temperature below"], 0).stdout;
    assert!(!t.contains("run-a") && t.contains("run-b"), "{t}");
    assert!(
        results(store, &["trend", "motor_temperature below", "--include-void"], 0)
            .stdout
            .contains("run-a")
    );
    let certificate = dir.join("u1.html");
    results(
        store,
        &["report", "--unit", "U1", "-o", certificate.to_str().unwrap()],
        0,
    );
    let html = std::fs::read_to_string(&certificate).expect("the certificate");
    assert_has(
        &html,
        &[
            "<p class=\"void\" id=\"void-run-a\">VOID — voided by A. Lead at 20",
            "wrong unit scanned",
            "FAILED <span class=\"void\">VOID</span>",
            "1 of them voided",
            "id=\"approval\"",
            "Approved by",
        ],
    );
    // The latest non-void run decides the unit's verdict.
    assert!(
        html.contains("id=\"verdict\">✔ PASSED"),
        "{}",
        &html[..2000.min(html.len())]
    );
}

#[test]
fn yield_capability_filters_and_voids_in_sqlite() {
    with_sqlite_store("quality-yield", quality_in);
}

#[test]
fn yield_capability_filters_and_voids_in_postgresql() {
    with_postgres_store("quality-yield", quality_in);
}
