//! Stored runs as files other tools read: JSON (each run with its end and checks), CSV
//! (one row per check, with the run's unit and verdict) and JUnit XML (a suite per run, a
//! case per check). Text only; the command line writes it where asked. A CSV field shows
//! control characters as escapes (a spreadsheet or a terminal never acts on them).

use super::StoredRun;
use crate::report::XmlWriter;

/// One JSON array, a run an element.
pub fn json(runs: &[StoredRun]) -> String {
    let list: Vec<serde_json::Value> = runs.iter().map(run_json).collect();
    serde_json::to_string_pretty(&list).unwrap_or_default()
}

/// A run as JSON: its start, its end (`null` when it never finished), checks and steps.
pub fn run_json(r: &StoredRun) -> serde_json::Value {
    serde_json::json!({
        "id": r.run.id,
        "verdict": r.verdict(),
        "run": r.run,
        "end": r.end,
        "checks": r.checks,
        "steps": r.steps,
        "void": r.void.as_ref().map(|v| serde_json::json!({"voided_at": v.voided_at, "voided_by": v.voided_by, "why": v.why})),
    })
}

/// The header of [`csv`].
pub const CSV_COLUMNS: [&str; 20] = [
    "run",
    "started_at",
    "recipe",
    "serial",
    "part",
    "operator",
    "station",
    "simulated",
    "run_verdict",
    "check",
    "measured",
    "measured_text",
    "unit",
    "low",
    "high",
    "passed",
    "marginal",
    "step",
    "attempt",
    // Last, so the columns before keep their places: the check without its limits.
    "check_key",
];

/// One row per check (a run without checks: one row with its verdict and no check).
pub fn csv(runs: &[StoredRun]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let _ = w.write_record(CSV_COLUMNS);
    let num = |v: Option<f64>| v.map(|v| v.to_string()).unwrap_or_default();
    for r in runs {
        let u = &r.run.unit;
        let run = [
            r.run.id.clone(),
            r.run.started_at.clone(),
            r.run.recipe.clone(),
            u.serial.clone().unwrap_or_default(),
            u.part.clone().unwrap_or_default(),
            u.operator.clone().unwrap_or_default(),
            u.station.clone().unwrap_or_default(),
            r.run.simulated.to_string(),
            r.verdict().to_string(),
        ];
        if r.checks.is_empty() {
            let mut row = run.to_vec();
            row.resize(CSV_COLUMNS.len(), String::new());
            let _ = w.write_record(row.iter().map(|f| crate::report::visible(f).into_owned()));
        }
        for c in &r.checks {
            let mut row = run.to_vec();
            row.extend([
                c.name.clone(),
                num(c.measured),
                c.measured_text.clone().unwrap_or_default(),
                c.unit.clone().unwrap_or_default(),
                num(c.limits.low),
                num(c.limits.high),
                c.passed.to_string(),
                c.marginal.to_string(),
                c.step.clone(),
                c.attempt.to_string(),
                c.key.clone().unwrap_or_else(|| c.name.clone()),
            ]);
            let _ = w.write_record(row.iter().map(|f| crate::report::visible(f).into_owned()));
        }
    }
    w.into_inner()
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .unwrap_or_default()
}

/// JUnit XML: a `<testsuite>` per run (named by recipe and unit), a `<testcase>` per check;
/// a run that never finished has a failing case `run` saying so.
pub fn junit(runs: &[StoredRun]) -> String {
    let mut x = XmlWriter::new();
    let failures: usize = runs
        .iter()
        .map(|r| r.checks.iter().filter(|c| !c.passed).count())
        .sum();
    let tests: usize = runs.iter().map(|r| r.checks.len()).sum();
    x.open(
        "testsuites",
        &[("tests", &tests.to_string()), ("failures", &failures.to_string())],
    );
    for r in runs {
        let name = match &r.run.unit.serial {
            Some(s) => format!("{} / {s}", r.run.recipe),
            None => r.run.recipe.clone(),
        };
        let incomplete = r.end.is_none();
        let failed = r.checks.iter().filter(|c| !c.passed).count() + usize::from(incomplete);
        x.open(
            "testsuite",
            &[
                ("name", &name),
                ("id", &r.run.id),
                ("timestamp", r.run.started_at.trim_end_matches('Z')),
                ("tests", &(r.checks.len() + usize::from(incomplete)).to_string()),
                ("failures", &failed.to_string()),
                ("errors", "0"),
            ],
        );
        for c in &r.checks {
            let classname = format!("{}.{}", r.run.recipe, r.run.id);
            if c.passed {
                x.empty("testcase", &[("name", &c.name), ("classname", &classname)]);
            } else {
                x.open("testcase", &[("name", &c.name), ("classname", &classname)]);
                x.text_element("failure", &[("message", &c.message)], &c.message);
                x.close("testcase");
            }
        }
        if incomplete {
            x.open("testcase", &[("name", "run"), ("classname", &r.run.recipe)]);
            let why = "the run never finished (killed, power cut, or still running)";
            x.text_element("failure", &[("message", why)], why);
            x.close("testcase");
        }
        x.close("testsuite");
    }
    x.close("testsuites");
    x.finish()
}
