//! What a run writes to the store as it goes, one record at a time: the run at its start,
//! the unit's identity when it becomes known, each step and check as decided, and the end.
//! Plain data, also the lines of the spool file (JSON), so a record that could not be
//! delivered is delivered later exactly as it was.

use crate::session::{Limits, UnitIdentity};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "record", rename_all = "snake_case")]
pub enum Record {
    Started(RunRow),
    Unit { run: String, unit: UnitIdentity },
    Step(StepRow),
    Check(CheckRow),
    Finished(EndRow),
}

impl Record {
    /// The run the record belongs to.
    pub fn run(&self) -> &str {
        match self {
            Record::Started(r) => &r.id,
            Record::Unit { run, .. } => run,
            Record::Step(s) => &s.run,
            Record::Check(c) => &c.run,
            Record::Finished(e) => &e.run,
        }
    }
}

/// The `drive` of a run refused before it started (nothing was opened or sent).
pub const NOT_STARTED: &str = "not started";

/// A run as it starts.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RunRow {
    pub id: String,
    /// `recipe` or `script`.
    pub kind: String,
    pub recipe: String,
    pub recipe_path: String,
    /// SHA-256 of the exact text it ran with, in hex: a recipe's file and every file it
    /// includes (`recipe/text_digest.rs`), a script's file.
    pub recipe_sha256: Option<String>,
    pub tool_version: String,
    /// UTC, RFC 3339 with milliseconds (sorts as text).
    pub started_at: String,
    pub simulated: bool,
    /// How the drive was reached: `drive 2 on /dev/ttyUSB0`.
    pub drive: String,
    /// The dictionary the run used, and its drive family.
    pub dictionary: Option<String>,
    pub family: Option<String>,
    pub port: Option<String>,
    pub address: Option<String>,
    pub host: Option<String>,
    pub unit: UnitIdentity,
    /// (name, value) as resolved.
    pub params: Vec<(String, String)>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepRow {
    pub run: String,
    pub seq: i64,
    /// The iteration-aware id (`4[2].1`).
    pub step: String,
    pub label: String,
    pub ok: bool,
    pub detail: String,
    pub phase: String,
    pub started_s: f64,
    pub duration_s: f64,
}

/// `Default` for fixtures that set only what they are about; the recorder and the stores
/// name every field.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CheckRow {
    pub run: String,
    pub seq: i64,
    pub name: String,
    /// The check's key, the same in every run whatever its limits
    /// (`session::check_key`); `None` in a record written before keys were (the store
    /// derives it from the name where it can).
    #[serde(default)]
    pub key: Option<String>,
    pub measured: Option<f64>,
    pub measured_text: Option<String>,
    pub unit: Option<String>,
    #[serde(flatten)]
    pub limits: Limits,
    pub passed: bool,
    /// A pass outside the check's warning band.
    #[serde(default)]
    pub marginal: bool,
    pub step: String,
    pub stage: String,
    /// 1 for the first time this check was decided at this step, 2 for a retry…
    pub attempt: i64,
    pub message: String,
    /// A comparison with the unit's last passed run: that run's id, when it started and
    /// what its check measured (the change is `measured`).
    #[serde(default)]
    pub reference_run: Option<String>,
    #[serde(default)]
    pub reference_at: Option<String>,
    #[serde(default)]
    pub reference_value: Option<f64>,
    /// Whether its limits include the values at them (`≤ 2.8 mm/s`) or not (`< 5 A`);
    /// `None` in a record written before the store kept it.
    #[serde(default)]
    pub inclusive: Option<bool>,
    /// The decimal places its object resolves (the dictionary's scale), which every page
    /// shows the value at; `None` when none applies or in a record written before the
    /// store kept it (shown to three places at most then).
    #[serde(default)]
    pub decimals: Option<i64>,
}

/// How the run ended.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct EndRow {
    pub run: String,
    pub ended_at: String,
    /// `passed`, `failed`, `error`, `interrupted`, `panic`; for a run that never started
    /// `refused` (exit code 2) or `error` (its drive could not be reached).
    pub verdict: String,
    pub exit_code: i64,
    pub reason: Option<String>,
    pub drive_identity: Option<String>,
    pub final_state: Option<String>,
    pub final_speed: Option<f64>,
    pub speed_unit: Option<String>,
    pub coasting: bool,
    pub stop_confirmed: bool,
    pub safe_stop: Vec<String>,
    pub report_files: Vec<String>,
    pub series: Vec<SeriesRow>,
    /// Passed steps and checks not stored (past the report's limit per run).
    pub omitted_steps: i64,
    pub omitted_checks: i64,
}

/// A sampled series as the HTML report plots it: at most twice its bucket count of points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeriesRow {
    pub object: String,
    pub unit: Option<String>,
    pub step: String,
    pub points: Vec<(f64, f64)>,
}

/// A passed run of the unit `serial` with one check, as the store's and the spool's tests
/// write it.
#[cfg(test)]
pub(super) fn passed_run(id: &str, serial: &str) -> Vec<Record> {
    vec![
        Record::Started(RunRow {
            id: id.into(),
            recipe: "R".into(),
            started_at: format!("2026-01-01T00:00:00.000Z{id}"),
            unit: UnitIdentity {
                serial: Some(serial.into()),
                ..UnitIdentity::default()
            },
            ..RunRow::default()
        }),
        Record::Check(CheckRow {
            run: id.into(),
            seq: 1,
            name: "c".into(),
            measured: Some(1.5),
            unit: Some("A".into()),
            limits: Limits::new(None, Some(2.0)),
            passed: true,
            step: "1".into(),
            attempt: 1,
            ..CheckRow::default()
        }),
        Record::Finished(EndRow {
            run: id.into(),
            verdict: "passed".into(),
            ..EndRow::default()
        }),
    ]
}
