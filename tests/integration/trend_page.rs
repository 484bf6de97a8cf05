//! `results trend --html` over runs days to months apart and minutes apart, against a real
//! SQLite store: runs of the past written through the store's own API (a run's start
//! cannot be set from the command line), a run on the simulated drive recorded with
//! `--results` after them. The page marks each run that measured a value (a failed one in
//! the fail colour), reads time as dates or as minutes since the first run, tells the
//! units apart, writes changes with their sign and limits with their unit, as the console
//! table does; headless Chromium renders both.

use crate::history::run_id;
use crate::support::{assert_has, cli, line_with, run_recording, scratch, screenshot, write_file};
use drivescript::results::{utc_text, CheckRow, EndRow, Locator, Record, RunRow};
use drivescript::session::{Limits, UnitIdentity};
use scraper::{Html, Selector};
use std::path::Path;
use std::time::{Duration, SystemTime};

const RECIPE: &str = "name: Bearing acceptance
drive: sd2
steps:
  - go_to: operation_enabled
  - expect:
      motor_temperature:
        below: 80 °C
        compared_with_last_pass: { at_most: 3 K, without_history: pass }
";

const CHECK: &str = "motor_temperature below 80 °C";
const COMPARED: &str = "motor_temperature below compared with last pass";

/// A run of the past: how long ago it started, its unit, the bearing temperature, its
/// change since the unit's last pass (none in its first run) and whether that change was
/// marginal.
struct Past {
    ago: Duration,
    serial: &'static str,
    temperature: f64,
    change: Option<f64>,
    marginal: bool,
}

fn past(days: f64, serial: &'static str, temperature: f64, change: Option<f64>) -> Past {
    Past {
        ago: Duration::from_secs_f64(days * 86_400.0),
        serial,
        temperature,
        change,
        marginal: false,
    }
}

/// Writes `runs` into the SQLite store at `store` as a run of [`RECIPE`] on the simulated
/// drive records them: the temperature check and its comparison, a change beyond 3 K failed.
fn recorded(store: &Path, runs: &[Past]) {
    let mut s = Locator::Sqlite(store.to_path_buf())
        .open(true)
        .expect("the store opens");
    let now = SystemTime::now();
    let mut records = Vec::new();
    for (i, r) in runs.iter().enumerate() {
        let id = format!("past{i:012}");
        let started_at = utc_text(now - r.ago);
        let passed = r.change.is_none_or(|c| c <= 3.0);
        records.push(Record::Started(RunRow {
            id: id.clone(),
            kind: "recipe".into(),
            recipe: "Bearing acceptance".into(),
            recipe_path: "bearing.yaml".into(),
            tool_version: "0.1.0".into(),
            started_at: started_at.clone(),
            simulated: true,
            drive: "simulated sd2".into(),
            unit: UnitIdentity {
                serial: Some(r.serial.into()),
                ..UnitIdentity::default()
            },
            ..RunRow::default()
        }));
        let check =
            |seq: i64, name: String, key: &str, measured: Option<f64>, unit: &str, high: f64| CheckRow {
                run: id.clone(),
                seq,
                name,
                key: Some(key.into()),
                measured,
                unit: Some(unit.into()),
                limits: Limits::new(None, Some(high)),
                passed: seq == 1 || passed,
                marginal: seq == 2 && r.marginal,
                step: "2".into(),
                attempt: 1,
                // As a record of before the store kept it: read from the name.
                inclusive: None,
                ..CheckRow::default()
            };
        records.push(Record::Check(check(
            1,
            CHECK.into(),
            "motor_temperature below",
            Some(r.temperature),
            "°C",
            80.0,
        )));
        records.push(Record::Check(check(
            2,
            format!("{CHECK} compared with last pass"),
            COMPARED,
            r.change,
            "K",
            3.0,
        )));
        records.push(Record::Finished(EndRow {
            run: id,
            ended_at: started_at,
            verdict: if passed { "passed" } else { "failed" }.into(),
            exit_code: if passed { 0 } else { 1 },
            final_state: Some("switch on disabled".into()),
            stop_confirmed: true,
            ..EndRow::default()
        }));
    }
    s.apply_all(&records).expect("the runs are stored");
}

/// `results trend CHECK --html PAGE` over `store` (simulated runs included, then `extra`):
/// the console table and the page, which must parse as HTML without errors.
pub(crate) fn trend(store: &Path, check: &str, page: &Path, extra: &[&str]) -> (String, String) {
    let args = [
        &[
            "results",
            "trend",
            check,
            "--simulated",
            "--results",
            store.to_str().unwrap(),
            "--html",
            page.to_str().unwrap(),
        ][..],
        extra,
    ]
    .concat();
    let table = cli(&args, 0).stdout;
    let html = std::fs::read_to_string(page).expect("the trend page");
    let doc = Html::parse_document(&html);
    assert!(doc.errors.is_empty(), "{:?}", doc.errors);
    (table, html)
}

fn select<'a>(doc: &'a Html, css: &str) -> Vec<scraper::ElementRef<'a>> {
    doc.select(&Selector::parse(css).expect("a selector")).collect()
}

fn texts(doc: &Html, css: &str) -> Vec<String> {
    select(doc, css).iter().map(|e| e.text().collect()).collect()
}

#[test]
fn a_batch_over_months_reads_as_dates_with_each_run_a_marker_and_its_unit() {
    let dir = scratch("months");
    let store = dir.join("results.sqlite");
    recorded(
        &store,
        &[
            past(180.0, "SP-1", 22.0, None),
            past(170.0, "SP-2", 21.0, None),
            past(160.0, "SP-3", 22.0, None),
            past(150.0, "SP-1", 22.5, Some(0.5)),
            past(140.0, "SP-2", 21.4, Some(0.4)),
            past(120.0, "SP-1", 23.0, Some(0.5)),
            Past {
                marginal: true,
                ..past(110.0, "SP-3", 24.6, Some(2.6))
            },
            past(100.0, "SP-2", 28.7, Some(7.3)),
            past(90.0, "SP-1", 23.2, Some(0.2)),
            past(80.0, "SP-3", 24.9, Some(0.3)),
            past(70.0, "SP-2", 23.0, Some(1.6)),
            past(60.0, "SP-1", 24.0, Some(0.8)),
        ],
    );
    // Today's run on the simulated drive (its motor at 25 °C) compares with SP-1's last pass.
    let recipe = write_file(&dir, "bearing.yaml", RECIPE);
    let (code, out) = run_recording(
        &recipe,
        store.to_str().unwrap(),
        &["--fast", "--unit", "serial=SP-1"],
    );
    assert_eq!(code, 0, "{out}");
    let today = run_id(&out);
    assert_has(&out, &["+1 K against 24 °C in run past000000000011"]);

    let page = dir.join("trend.html");
    let (table, html) = trend(&store, COMPARED, &page, &[]);
    // The console and the page write a change with its sign and the limits with their unit.
    let row = |id: &str| line_with(&table, id);
    assert_has(row("past000000000007"), &["SP-2", "+7.3 K", "≤ 3 K", "FAIL"]);
    assert_has(row("past000000000006"), &["SP-3", "+2.6 K", "MARGINAL"]);
    assert_has(row("past000000000000"), &["SP-1", "—", "≤ 3 K", "PASS"]);
    assert_has(row(&today), &["SP-1", "+1 K", "≤ 3 K", "PASS"]);
    let doc = Html::parse_document(&html);
    // A marker per run that measured a change: not the three first runs.
    assert_eq!(select(&doc, "svg.trend .mark").len(), 13 - 3, "{html}");
    let failed = select(&doc, "svg.trend .mark.failed");
    assert_eq!(failed.len(), 1);
    assert_eq!(failed[0].value().attr("fill"), Some("#8b0000"));
    let tip: String = failed[0].text().collect();
    assert_has(&tip, &["SP-2", "+7.3 K", "FAIL", "past000000000007"]);
    assert_eq!(select(&doc, "svg.trend .mark.marginal").len(), 1);
    // A colour per unit, a thin line joining each unit's runs, the unit named in the legend.
    let fills: std::collections::BTreeSet<&str> = select(&doc, "svg.trend .mark.passed")
        .iter()
        .filter_map(|m| m.value().attr("fill"))
        .collect();
    assert_eq!(fills.len(), 3, "{fills:?}");
    assert_eq!(select(&doc, "svg.trend .trend-line").len(), 3);
    assert_has(&html, &["Units:", "stroke-width=\"1\" points="]);
    // Dates along the time axis at round calendar points; the unit along the value axis.
    let labels = texts(&doc, "svg.trend text");
    assert!(labels.iter().any(|l| l == "date (UTC)"), "{labels:?}");
    let dates: Vec<&String> = labels
        .iter()
        .filter(|l| l.len() == 7 && l.as_bytes()[4] == b'-' && l[..4].parse::<u32>().is_ok())
        .collect();
    assert!(dates.len() >= 5, "a tick on the 1st of each month: {labels:?}");
    assert!(labels.iter().any(|l| l == "change [K]"), "{labels:?}");
    assert!(!html.contains("time [s]"));
    // The table: every run with its unit, its change and the limit in K.
    let rows = select(&doc, "#values tbody tr");
    assert_eq!(rows.len(), 13);
    let units = texts(&doc, "#values tbody td:nth-child(2)");
    assert!(
        ["SP-1", "SP-2", "SP-3"]
            .iter()
            .all(|u| units.iter().any(|c| c == u)),
        "{units:?}"
    );
    assert_has(
        &html,
        &[
            "<td class=\"num\">+7.3 K</td><td class=\"num\">≤ 3 K</td><td class=\"fail\">FAIL (simulated)</td>",
            "<tr class=\"marginal\">",
        ],
    );
    assert!(!html.contains("<script") && !html.contains(" src=") && !html.contains("href="));
    // Kept for a look: target/trend-months.png.
    screenshot(&page, "1200,1400", "trend-months");
}

#[test]
fn runs_minutes_apart_read_as_minutes_since_the_first() {
    let dir = scratch("minutes");
    let store = dir.join("results.sqlite");
    let runs: Vec<Past> = (0..9)
        .map(|k| {
            past(
                f64::from(100 - 5 * k) / 1440.0,
                "SP-7",
                30.0 + f64::from(k) * 0.4,
                None,
            )
        })
        .collect();
    recorded(&store, &runs);
    let page = dir.join("trend.html");
    let (table, html) = trend(&store, "motor_temperature below", &page, &[]);
    assert_has(&table, &["30.4 °C", "< 80 °C", "SP-7"]);
    let doc = Html::parse_document(&html);
    assert_eq!(select(&doc, "svg.trend .mark.passed").len(), 9);
    let labels = texts(&doc, "svg.trend text");
    let first = utc_text(SystemTime::now() - runs[0].ago);
    let title = labels
        .iter()
        .find(|l| l.starts_with("time since "))
        .unwrap_or_else(|| panic!("{labels:?}"));
    assert!(
        title.ends_with(" UTC [min]") && title.contains(&first[..10]),
        "{title}"
    );
    for tick in ["0", "10", "20", "30", "40"] {
        assert!(labels.iter().any(|l| l == tick), "{tick} in {labels:?}");
    }
    assert!(labels.iter().any(|l| l == "[°C]"), "{labels:?}");
    assert_has(
        &html,
        &[
            "<td class=\"num\">&lt; 80 °C</td>",
            "↑ &lt; 80 °C</text>",
            "1 unit(s)",
        ],
    );
    // Kept for a look: target/trend-minutes.png.
    screenshot(&page, "1200,1400", "trend-minutes");
    // --limit keeps the newest runs, oldest first as always.
    let (newest, _) = trend(&store, "motor_temperature below", &page, &["--limit", "2"]);
    let values: Vec<&str> = newest
        .lines()
        .skip(1)
        .filter_map(|l| l.split_whitespace().nth(2))
        .collect();
    assert_eq!(values, ["32.8", "33.2"], "{newest}");
}
