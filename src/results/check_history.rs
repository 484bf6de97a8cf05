//! A check across runs, found by its key (the same whatever its limits,
//! `session::check_key`): the unit's last passed run with its checks, for the comparisons
//! with it, and one check's values in every run for `results trend`. A check stored
//! without a key is found by its full name, which is then its own key. Queries only.

use super::backend::Value;
use super::store::{int, opt, text, where_clause, Store};
use super::stored_run::{RunFilter, TrendPoint};
use super::StoreError;
use crate::session::{key_of_name, PastCheck, PastRun};

impl Store {
    /// The last complete run with verdict passed of the recipe named `recipe` on the unit
    /// `serial`, among simulated runs or among real ones, with its passed checks that
    /// measured a value; `None` when there is none.
    pub fn last_pass(
        &mut self,
        recipe: &str,
        serial: &str,
        simulated: bool,
    ) -> Result<Option<PastRun>, StoreError> {
        let rows = self.backend.query(
            "SELECT id, started_at FROM runs WHERE recipe = $1 AND serial = $2 AND simulated = $3 \
             AND verdict = 'passed' AND ended_at IS NOT NULL ORDER BY started_at DESC, id DESC LIMIT 1",
            &[recipe.into(), serial.into(), simulated.into()],
        )?;
        let Some(run) = rows.first() else {
            return Ok(None);
        };
        let id = text(&run[0]);
        let checks = self.backend.query(
            "SELECT name, step, measured, unit, check_key FROM checks WHERE run_id = $1 \
             AND passed = 1 AND measured IS NOT NULL ORDER BY seq",
            &[id.as_str().into()],
        )?;
        Ok(Some(PastRun {
            id,
            started_at: text(&run[1]),
            checks: checks
                .iter()
                .filter_map(|c| {
                    Some(PastCheck {
                        name: text(&c[0]),
                        key: opt(&c[4]),
                        step: text(&c[1]),
                        measured: c[2].real()?,
                        unit: opt(&c[3]),
                    })
                })
                .collect(),
        }))
    }

    /// The keys `check` stands for: itself (a key, or a name that is its own key), the key
    /// of every check stored under that full name, and the key the name shows.
    fn keys_of(&mut self, check: &str) -> Result<Vec<String>, StoreError> {
        let rows = self.backend.query(
            "SELECT DISTINCT check_key FROM checks WHERE name = $1 AND check_key IS NOT NULL",
            &[check.into()],
        )?;
        let mut keys = vec![check.to_string()];
        let stored = rows
            .iter()
            .filter_map(|r| r.first().and_then(Value::text).map(str::to_string));
        for key in stored.chain(key_of_name(check)) {
            if !keys.contains(&key) {
                keys.push(key);
            }
        }
        Ok(keys)
    }

    /// The value of check `check` — its key or a full name as a report shows it — in every
    /// run `filter` takes, oldest first: every check of that key, each with the limits it
    /// had in its run; with a limit, the newest that many.
    pub fn trend(&mut self, check: &str, filter: &RunFilter) -> Result<Vec<TrendPoint>, StoreError> {
        let keys = self.keys_of(check)?;
        let (clause, mut params) = where_clause(filter, "r.");
        let first = params.len() + 1;
        params.extend(keys.iter().map(|k| Value::from(k.as_str())));
        let list = (first..params.len() + 1)
            .map(|n| format!("${n}"))
            .collect::<Vec<_>>()
            .join(", ");
        let and = if clause.is_empty() { " WHERE" } else { " AND" };
        let mut sql = format!(
            "SELECT r.id, r.started_at, r.serial, c.measured, c.unit, c.low, c.high, c.passed, \
             c.name, c.check_key, c.marginal, c.seq, c.inclusive FROM checks c JOIN runs r ON r.id = c.run_id{clause}{and} \
             (c.check_key IN ({list}) OR (c.check_key IS NULL AND c.name IN ({list})))"
        );
        match filter.limit {
            // The newest that many, then back in the order they were made.
            Some(limit) => {
                params.push(Value::Int(i64::try_from(limit).unwrap_or(i64::MAX)));
                sql = format!(
                    "SELECT * FROM ({sql} ORDER BY r.started_at DESC, r.id DESC, c.seq DESC LIMIT ${}) newest \
                     ORDER BY started_at, id, seq",
                    params.len()
                );
            }
            None => sql.push_str(" ORDER BY r.started_at, r.id, c.seq"),
        }
        let rows = self.backend.query(&sql, &params)?;
        Ok(rows
            .iter()
            .map(|r| TrendPoint {
                run: text(&r[0]),
                started_at: text(&r[1]),
                serial: opt(&r[2]),
                measured: r[3].real(),
                unit: opt(&r[4]),
                low: r[5].real(),
                high: r[6].real(),
                passed: int(&r[7]) != 0,
                marginal: int(&r[10]) != 0,
                inclusive: r[12].int().map(|v| v != 0),
                key: opt(&r[9]).unwrap_or_else(|| text(&r[8])),
                name: text(&r[8]),
            })
            .collect())
    }
}
