//! The results store over one backend: applies records (in batches, each one
//! transaction, so a kill keeps whole batches and never a step without its run; replaying
//! a record changes nothing) and answers the
//! queries of `results`. Every value travels as a parameter, never inside the SQL.

use super::backend::{Backend, Value};
use super::record::{CheckRow, EndRow, Record, RunRow, SeriesRow, StepRow};
use super::stored_run::{RunFilter, StoredRun, VoidRow};
use super::{schema, StoreError};
use crate::session::Limits;
use crate::session::{key_of_name, UnitIdentity};

pub struct Store {
    pub(super) backend: Box<dyn Backend>,
}

const RUN_COLUMNS: &str = "id, kind, recipe, recipe_path, recipe_sha256, tool_version, started_at, \
     simulated, drive, dictionary, port, address, host, serial, part, operator, station, params, \
     ended_at, verdict, exit_code, reason, drive_identity, final_state, final_speed, speed_unit, \
     coasting, stop_confirmed, safe_stop, report_files, omitted_steps, omitted_checks, family";

/// The runs with the void of each (`None` where there is none), for [`RUN_COLUMNS`] and
/// `v.voided_at, v.voided_by, v.why` after them.
const RUNS_WITH_VOIDS: &str = "runs LEFT JOIN voids v ON v.run_id = runs.id";

impl Store {
    /// The store behind `backend`, its schema brought up to date.
    pub fn new(mut backend: Box<dyn Backend>) -> Result<Store, StoreError> {
        schema::migrate(backend.as_mut())?;
        backend.settle()?;
        Ok(Store { backend })
    }

    /// The store as messages name it (no password).
    pub fn name(&self) -> &str {
        self.backend.name()
    }

    /// Writes one record.
    pub fn apply(&mut self, record: &Record) -> Result<(), StoreError> {
        let b = self.backend.as_mut();
        match record {
            Record::Started(r) => {
                b.execute(
                    "INSERT INTO runs (id, kind, recipe, recipe_path, recipe_sha256, tool_version, \
                     started_at, simulated, drive, dictionary, port, address, host, serial, part, \
                     operator, station, params, family) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, \
                     $10, $11, $12, $13, $14, $15, $16, $17, $18, $19) ON CONFLICT (id) DO NOTHING",
                    &[
                        r.id.as_str().into(),
                        r.kind.as_str().into(),
                        r.recipe.as_str().into(),
                        r.recipe_path.as_str().into(),
                        r.recipe_sha256.clone().into(),
                        r.tool_version.as_str().into(),
                        r.started_at.as_str().into(),
                        r.simulated.into(),
                        r.drive.as_str().into(),
                        r.dictionary.clone().into(),
                        r.port.clone().into(),
                        r.address.clone().into(),
                        r.host.clone().into(),
                        r.unit.serial.clone().into(),
                        r.unit.part.clone().into(),
                        r.unit.operator.clone().into(),
                        r.unit.station.clone().into(),
                        json(&r.params).into(),
                        r.family.clone().into(),
                    ],
                )?;
            }
            Record::Unit { run, unit } => {
                b.execute(
                    "UPDATE runs SET serial = $2, part = $3, operator = $4, station = $5 WHERE id = $1",
                    &[
                        run.as_str().into(),
                        unit.serial.clone().into(),
                        unit.part.clone().into(),
                        unit.operator.clone().into(),
                        unit.station.clone().into(),
                    ],
                )?;
            }
            Record::Step(s) => {
                b.execute(
                    "INSERT INTO steps (run_id, seq, step, label, ok, detail, phase, started_s, \
                     duration_s) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9) ON CONFLICT DO NOTHING",
                    &[
                        s.run.as_str().into(),
                        s.seq.into(),
                        s.step.as_str().into(),
                        s.label.as_str().into(),
                        s.ok.into(),
                        s.detail.as_str().into(),
                        s.phase.as_str().into(),
                        Value::Real(s.started_s),
                        Value::Real(s.duration_s),
                    ],
                )?;
            }
            Record::Check(c) => {
                b.execute(
                    "INSERT INTO checks (run_id, seq, name, measured, measured_text, unit, low, \
                     high, passed, marginal, step, stage, attempt, message, reference_run, \
                     reference_at, reference_value, check_key, inclusive, decimals) VALUES ($1, $2, $3, \
                     $4, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14, $15, $16, $17, $18, $19, $20) \
                     ON CONFLICT DO NOTHING",
                    &[
                        c.run.as_str().into(),
                        c.seq.into(),
                        c.name.as_str().into(),
                        c.measured.into(),
                        c.measured_text.clone().into(),
                        c.unit.clone().into(),
                        c.limits.low.into(),
                        c.limits.high.into(),
                        c.passed.into(),
                        c.marginal.into(),
                        c.step.as_str().into(),
                        c.stage.as_str().into(),
                        c.attempt.into(),
                        c.message.as_str().into(),
                        c.reference_run.clone().into(),
                        c.reference_at.clone().into(),
                        c.reference_value.into(),
                        // A record spooled before keys were: as the migration keys its rows.
                        c.key.clone().or_else(|| key_of_name(&c.name)).into(),
                        c.inclusive.map_or(Value::Null, Value::from),
                        c.decimals.map_or(Value::Null, Value::from),
                    ],
                )?;
            }
            Record::Finished(e) => {
                for (seq, s) in e.series.iter().enumerate() {
                    b.execute(
                        "INSERT INTO series (run_id, seq, object, unit, step, points) VALUES \
                         ($1, $2, $3, $4, $5, $6) ON CONFLICT DO NOTHING",
                        &[
                            e.run.as_str().into(),
                            (seq as i64).into(),
                            s.object.as_str().into(),
                            s.unit.clone().into(),
                            s.step.as_str().into(),
                            json(&s.points).into(),
                        ],
                    )?;
                }
                // Last: a run counts as complete only once everything else is in.
                b.execute(
                    "UPDATE runs SET ended_at = $2, verdict = $3, exit_code = $4, reason = $5, \
                     drive_identity = $6, final_state = $7, final_speed = $8, speed_unit = $9, \
                     coasting = $10, stop_confirmed = $11, safe_stop = $12, report_files = $13, \
                     omitted_steps = $14, omitted_checks = $15 WHERE id = $1",
                    &[
                        e.run.as_str().into(),
                        e.ended_at.as_str().into(),
                        e.verdict.as_str().into(),
                        e.exit_code.into(),
                        e.reason.clone().into(),
                        e.drive_identity.clone().into(),
                        e.final_state.clone().into(),
                        e.final_speed.into(),
                        e.speed_unit.clone().into(),
                        e.coasting.into(),
                        e.stop_confirmed.into(),
                        json(&e.safe_stop).into(),
                        json(&e.report_files).into(),
                        e.omitted_steps.into(),
                        e.omitted_checks.into(),
                    ],
                )?;
            }
        }
        Ok(())
    }

    /// Writes `records` in one transaction: all of them or none.
    pub fn apply_all(&mut self, records: &[Record]) -> Result<(), StoreError> {
        self.backend.begin_write()?;
        for r in records {
            if let Err(e) = self.apply(r) {
                let _ = self.backend.batch("ROLLBACK");
                return Err(e);
            }
        }
        if let Err(e) = self.backend.batch("COMMIT") {
            let _ = self.backend.batch("ROLLBACK");
            return Err(e);
        }
        Ok(())
    }

    /// Moves what is committed into the store's own file (SQLite), so that file alone
    /// holds every finished run; a server keeps it anyway.
    pub fn checkpoint(&mut self) {
        self.backend.checkpoint();
    }

    /// The runs `filter` takes, newest first.
    pub fn list(&mut self, filter: &RunFilter) -> Result<Vec<StoredRun>, StoreError> {
        let (clause, mut params) = where_clause(filter, "");
        let mut sql = format!(
            "SELECT {RUN_COLUMNS}, v.voided_at, v.voided_by, v.why FROM {RUNS_WITH_VOIDS}{clause} \
             ORDER BY started_at DESC, id"
        );
        if let Some(limit) = filter.limit {
            params.push(Value::Int(i64::try_from(limit).unwrap_or(i64::MAX)));
            sql.push_str(&format!(" LIMIT ${}", params.len()));
        }
        let rows = self.backend.query(&sql, &params)?;
        Ok(rows.iter().map(|r| stored_run(r)).collect())
    }

    /// One run with its checks, steps and series, by its id or a prefix only it has.
    pub fn run(&mut self, id: &str) -> Result<StoredRun, StoreError> {
        let pattern = format!(
            "{}%",
            id.replace('\\', "\\\\").replace('%', "\\%").replace('_', "\\_")
        );
        let rows = self.backend.query(
            &format!(
                "SELECT {RUN_COLUMNS}, v.voided_at, v.voided_by, v.why FROM {RUNS_WITH_VOIDS} \
                 WHERE id LIKE $1 ESCAPE '\\' ORDER BY id LIMIT 2"
            ),
            &[pattern.into()],
        )?;
        let run = match rows.as_slice() {
            [one] => stored_run(one),
            [] => return Err(StoreError::NotFound(format!("no run {id} in {}", self.name()))),
            _ => {
                return Err(StoreError::NotFound(format!(
                    "more than one run starts with {id}; give more of the id"
                )))
            }
        };
        self.detailed(run)
    }

    /// Every run of the unit with serial number `serial`, oldest first, in detail.
    /// Voided runs are among them, marked: a certificate shows them.
    pub fn unit_runs(&mut self, serial: &str, simulated: bool) -> Result<Vec<StoredRun>, StoreError> {
        self.unit_runs_in(&RunFilter {
            unit: Some(serial.to_string()),
            simulated,
            include_void: true,
            ..RunFilter::default()
        })
    }

    /// The runs `filter` takes (a unit's, narrowed by station, dates…), oldest first, in
    /// detail.
    pub fn unit_runs_in(&mut self, filter: &RunFilter) -> Result<Vec<StoredRun>, StoreError> {
        let mut runs = self.list(filter)?;
        runs.reverse();
        runs.into_iter().map(|r| self.detailed(r)).collect()
    }

    /// The runs of `filter` with their checks (for export).
    pub fn with_checks(&mut self, filter: &RunFilter) -> Result<Vec<StoredRun>, StoreError> {
        let runs = self.list(filter)?;
        runs.into_iter()
            .map(|mut r| {
                r.checks = self.checks(&r.run.id)?;
                Ok(r)
            })
            .collect()
    }

    fn checks(&mut self, run: &str) -> Result<Vec<CheckRow>, StoreError> {
        let sql = format!("SELECT {CHECK_COLUMNS} FROM checks WHERE run_id = $1 ORDER BY seq");
        let rows = self.backend.query(&sql, &[run.into()])?;
        Ok(rows.iter().map(|r| check_row(run, r)).collect())
    }

    fn detailed(&mut self, mut run: StoredRun) -> Result<StoredRun, StoreError> {
        let id = run.run.id.clone();
        run.checks = self.checks(&id)?;
        let rows = self.backend.query(
            "SELECT seq, step, label, ok, detail, phase, started_s, duration_s FROM steps \
             WHERE run_id = $1 ORDER BY seq",
            &[id.as_str().into()],
        )?;
        run.steps = rows
            .iter()
            .map(|r| StepRow {
                run: id.clone(),
                seq: int(&r[0]),
                step: text(&r[1]),
                label: text(&r[2]),
                ok: int(&r[3]) != 0,
                detail: text(&r[4]),
                phase: text(&r[5]),
                started_s: r[6].real().unwrap_or(0.0),
                duration_s: r[7].real().unwrap_or(0.0),
            })
            .collect();
        if let Some(end) = run.end.as_mut() {
            let rows = self.backend.query(
                "SELECT object, unit, step, points FROM series WHERE run_id = $1 ORDER BY seq",
                &[id.as_str().into()],
            )?;
            end.series = rows
                .iter()
                .map(|r| SeriesRow {
                    object: text(&r[0]),
                    unit: opt(&r[1]),
                    step: text(&r[2]),
                    points: serde_json::from_str(&text(&r[3])).unwrap_or_default(),
                })
                .collect();
        }
        Ok(run)
    }
}

/// ` WHERE …` for `filter` (columns prefixed with `prefix`) and its parameters.
pub(super) fn where_clause(filter: &RunFilter, prefix: &str) -> (String, Vec<Value>) {
    let mut parts: Vec<String> = Vec::new();
    let mut params: Vec<Value> = Vec::new();
    let mut add = |sql: &str, value: Option<Value>, params: &mut Vec<Value>| {
        let sql = match value {
            Some(v) => {
                params.push(v);
                sql.replace('?', &format!("${}", params.len()))
            }
            None => sql.to_string(),
        };
        parts.push(sql.replace("#.", prefix));
    };
    if let Some(unit) = &filter.unit {
        add("#.serial = ?", Some(unit.as_str().into()), &mut params);
    }
    if let Some(recipe) = &filter.recipe {
        add(
            "(#.recipe = ? OR #.recipe_path = ?)",
            Some(recipe.as_str().into()),
            &mut params,
        );
    }
    match filter.verdict.as_deref() {
        Some("incomplete") => add("#.verdict IS NULL", None, &mut params),
        Some(v) => add("#.verdict = ?", Some(v.into()), &mut params),
        None => {}
    }
    if let Some(since) = &filter.since {
        add("#.started_at >= ?", Some(since.as_str().into()), &mut params);
    }
    if let Some(until) = &filter.until {
        add("#.started_at < ?", Some(until.as_str().into()), &mut params);
    }
    for (column, value) in [
        ("station", &filter.station),
        ("operator", &filter.operator),
        ("part", &filter.part),
    ] {
        if let Some(v) = value {
            add(&format!("#.{column} = ?"), Some(v.as_str().into()), &mut params);
        }
    }
    if !filter.include_void {
        add(
            "NOT EXISTS (SELECT 1 FROM voids v WHERE v.run_id = #.id)",
            None,
            &mut params,
        );
    }
    if !filter.simulated {
        add("#.simulated = 0", None, &mut params);
    }
    let clause = if parts.is_empty() {
        String::new()
    } else {
        format!(" WHERE {}", parts.join(" AND "))
    };
    (clause, params)
}

fn json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string(value).unwrap_or_default()
}

pub(super) fn text(v: &Value) -> String {
    v.text().unwrap_or_default().to_string()
}

pub(super) fn opt(v: &Value) -> Option<String> {
    v.text().map(str::to_string)
}

pub(super) fn int(v: &Value) -> i64 {
    v.int().unwrap_or(0)
}

/// The columns of a stored check, in the order [`check_row`] reads them.
const CHECK_COLUMNS: &str = "seq, name, measured, measured_text, unit, low, high, passed, step, stage, \
     attempt, message, marginal, reference_run, reference_at, reference_value, \
     check_key, inclusive, decimals";

/// [`RUN_COLUMNS`] then [`CHECK_COLUMNS`] for a query of checks `c` joined to their runs
/// `r`, and where the check's columns start: [`run_row`] reads a row before it,
/// [`check_row`] from it.
pub(super) fn run_and_check_columns() -> (String, usize) {
    let of = |table: &str, columns: &str| -> Vec<String> {
        columns.split(", ").map(|c| format!("{table}.{c}")).collect()
    };
    let run = of("r", RUN_COLUMNS);
    let checks_from = run.len();
    ([run, of("c", CHECK_COLUMNS)].concat().join(", "), checks_from)
}

/// A check of the run `run` from a row of [`CHECK_COLUMNS`].
pub(super) fn check_row(run: &str, r: &[Value]) -> CheckRow {
    CheckRow {
        run: run.to_string(),
        seq: int(&r[0]),
        name: text(&r[1]),
        key: opt(&r[16]),
        measured: r[2].real(),
        measured_text: opt(&r[3]),
        unit: opt(&r[4]),
        limits: Limits::new(r[5].real(), r[6].real()),
        passed: int(&r[7]) != 0,
        step: text(&r[8]),
        stage: text(&r[9]),
        attempt: int(&r[10]),
        message: text(&r[11]),
        marginal: int(&r[12]) != 0,
        reference_run: opt(&r[13]),
        reference_at: opt(&r[14]),
        reference_value: r[15].real(),
        inclusive: r[17].int().map(|v| v != 0),
        decimals: r[18].int(),
    }
}

/// What a run says as it starts, from a row of [`RUN_COLUMNS`] (the family, added later, is
/// its last column); the end is [`stored_run`]'s.
pub(super) fn run_row(r: &[Value]) -> RunRow {
    RunRow {
        id: text(&r[0]),
        kind: text(&r[1]),
        recipe: text(&r[2]),
        recipe_path: text(&r[3]),
        recipe_sha256: opt(&r[4]),
        tool_version: text(&r[5]),
        started_at: text(&r[6]),
        simulated: int(&r[7]) != 0,
        drive: text(&r[8]),
        dictionary: opt(&r[9]),
        family: opt(&r[32]),
        port: opt(&r[10]),
        address: opt(&r[11]),
        host: opt(&r[12]),
        unit: UnitIdentity {
            serial: opt(&r[13]),
            part: opt(&r[14]),
            operator: opt(&r[15]),
            station: opt(&r[16]),
        },
        params: serde_json::from_str(&text(&r[17])).unwrap_or_default(),
    }
}

fn stored_run(r: &[Value]) -> StoredRun {
    let run = run_row(r);
    let end = opt(&r[19]).map(|verdict| EndRow {
        run: run.id.clone(),
        ended_at: text(&r[18]),
        verdict,
        exit_code: int(&r[20]),
        reason: opt(&r[21]),
        drive_identity: opt(&r[22]),
        final_state: opt(&r[23]),
        final_speed: r[24].real(),
        speed_unit: opt(&r[25]),
        coasting: int(&r[26]) != 0,
        stop_confirmed: int(&r[27]) != 0,
        safe_stop: serde_json::from_str(&text(&r[28])).unwrap_or_default(),
        report_files: serde_json::from_str(&text(&r[29])).unwrap_or_default(),
        series: Vec::new(),
        omitted_steps: int(&r[30]),
        omitted_checks: int(&r[31]),
    });
    StoredRun {
        run,
        end,
        checks: Vec::new(),
        steps: Vec::new(),
        void: opt(&r[33]).map(|voided_at| VoidRow {
            run: text(&r[0]),
            voided_at,
            voided_by: text(&r[34]),
            why: text(&r[35]),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::record::passed_run;
    use crate::results::Locator;

    #[test]
    fn replaying_records_changes_nothing_and_filters_take_the_right_runs() {
        let dir = std::env::temp_dir().join(format!("drivescript-store-unit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut store = Locator::Sqlite(dir.join("r.sqlite")).open(true).expect("opens");
        let mut all = passed_run("a1", "S-1");
        all.extend(passed_run("b2", "S-2"));
        all.extend(passed_run("c3", "S-1"));
        all.truncate(all.len() - 1); // c3 never finished
        for r in all.iter().chain(all.iter()) {
            store.apply(r).expect("applied");
        }
        let every = RunFilter {
            simulated: true,
            ..RunFilter::default()
        };
        assert_eq!(store.list(&every).expect("list").len(), 3);
        let s1 = RunFilter {
            unit: Some("S-1".into()),
            ..every.clone()
        };
        let ids: Vec<String> = store
            .list(&s1)
            .expect("list")
            .into_iter()
            .map(|r| r.run.id)
            .collect();
        assert_eq!(ids, ["c3", "a1"], "newest first");
        let incomplete = RunFilter {
            verdict: Some("incomplete".into()),
            ..every.clone()
        };
        assert_eq!(store.list(&incomplete).expect("list")[0].run.id, "c3");
        assert_eq!(store.run("b").expect("by prefix").checks.len(), 1);
        assert!(matches!(store.run("x"), Err(StoreError::NotFound(_))));
        assert_eq!(store.trend("c", &every).expect("trend").len(), 3);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
