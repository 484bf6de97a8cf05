//! A check across runs, found by its key (the same whatever its limits,
//! `session::check_key`): the unit's last passed run with its checks, for the comparisons
//! with it, and one check's values in every run for `results trend`. A check stored
//! without a key is found by its full name, which is then its own key. Queries only.

use super::backend::Value;
use super::check_identity::{readings, CheckIdentity};
use super::store::{check_row, opt, run_and_check_columns, run_row, text, where_clause, Store};
use super::stored_run::{RunFilter, TrendPoint};
use super::StoreError;
use crate::session::{key_of_name, PastCheck, PastRun};

impl Store {
    /// The last complete run with verdict passed, not voided (a wrong unit scanned: its
    /// values are not this unit's), of the recipe named `recipe` on the unit `serial`,
    /// among simulated runs or among real ones, with its passed checks that
    /// measured a value; `None` when there is none.
    pub fn last_pass(
        &mut self,
        recipe: &str,
        serial: &str,
        simulated: bool,
    ) -> Result<Option<PastRun>, StoreError> {
        let rows = self.backend.query(
            "SELECT id, started_at FROM runs WHERE recipe = $1 AND serial = $2 AND simulated = $3 \
             AND verdict = 'passed' AND ended_at IS NOT NULL \
             AND NOT EXISTS (SELECT 1 FROM voids v WHERE v.run_id = runs.id) \
             ORDER BY started_at DESC, id DESC LIMIT 1",
            &[recipe.into(), serial.into(), simulated.into()],
        )?;
        let Some(run) = rows.first() else {
            return Ok(None);
        };
        let id = text(&run[0]);
        let checks = self.backend.query(
            "SELECT name, step, measured, unit, check_key, stage FROM checks WHERE run_id = $1 \
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
                        stage: text(&c[5]),
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

    /// The value of check `check` — its key, a full name as the console shows it, or the
    /// JUnit test-case name (`Stage 2, 12000 rpm / speed_actual mean near`) — in every run
    /// `filter` takes, oldest first, each with the limits it had in its run; with a limit,
    /// the newest that many. One measurement only ([`CheckIdentity`]): a text that stands
    /// for several (the same key in several stages, recipes or places) is refused with
    /// the names that tell them apart.
    pub fn trend(&mut self, check: &str, filter: &RunFilter) -> Result<Vec<TrendPoint>, StoreError> {
        let readings = readings(check);
        let mut keys: Vec<String> = Vec::new();
        for asked in readings.iter().flat_map(|r| r.keys.iter()) {
            for key in self.keys_of(asked)? {
                if !keys.contains(&key) {
                    keys.push(key);
                }
            }
        }
        let (clause, mut params) = where_clause(filter, "r.");
        let first = params.len() + 1;
        params.extend(keys.iter().map(|k| Value::from(k.as_str())));
        let list = (first..params.len() + 1)
            .map(|n| format!("${n}"))
            .collect::<Vec<_>>()
            .join(", ");
        let and = if clause.is_empty() { " WHERE" } else { " AND" };
        let (columns, checks_from) = run_and_check_columns();
        let sql = format!(
            "SELECT {columns} FROM checks c JOIN runs r ON r.id = c.run_id{clause}{and} \
             (c.check_key IN ({list}) OR (c.check_key IS NULL AND c.name IN ({list}))) \
             ORDER BY r.started_at, r.id, c.seq"
        );
        let rows = self.backend.query(&sql, &params)?;
        let mut points: Vec<TrendPoint> = rows
            .iter()
            .map(|r| {
                let (run, check) = r.split_at(checks_from);
                let run = run_row(run);
                TrendPoint {
                    check: check_row(&run.id, check),
                    run,
                }
            })
            .filter(|p| {
                let id = p.identity();
                readings.iter().any(|asked| asked.takes(&id, &p.check.name))
            })
            .collect();
        let ids = measurements(&points);
        // A full name as typed (`speed_actual mean near 6000 rpm ± 1 %`) means the checks
        // of that name, not every check its key shares: theirs are the measurements asked
        // for (with their runs of other limits).
        let named: Vec<&CheckIdentity> = points
            .iter()
            .zip(&ids)
            .filter(|(p, _)| readings.iter().any(|r| r.keys.first() == Some(&p.check.name)))
            .map(|(_, id)| id)
            .collect();
        let keep: Vec<bool> = ids
            .iter()
            .map(|id| named.is_empty() || named.contains(&id))
            .collect();
        let mut found: Vec<(CheckIdentity, usize)> = Vec::new();
        for id in ids.iter().zip(&keep).filter(|(_, k)| **k).map(|(id, _)| id) {
            match found.iter_mut().find(|(f, _)| f == id) {
                Some((_, n)) => *n += 1,
                None => found.push((id.clone(), 1)),
            }
        }
        let mut kept = keep.iter();
        points.retain(|_| kept.next().copied().unwrap_or(false));
        if found.len() > 1 {
            return Err(StoreError::Refused(several(check, &found, self.name())));
        }
        if let Some(limit) = filter.limit {
            let keep = usize::try_from(limit).unwrap_or(usize::MAX);
            points.drain(..points.len().saturating_sub(keep));
        }
        Ok(points)
    }

    /// Checks of runs `filter` takes that a user who typed `check` (and found nothing) may
    /// have meant: those whose key holds its object (the first word of its check), else
    /// any; at most `most`, as identities.
    pub fn checks_like(
        &mut self,
        check: &str,
        filter: &RunFilter,
        most: usize,
    ) -> Result<Vec<CheckIdentity>, StoreError> {
        let tail = check.rsplit(" / ").next().unwrap_or(check);
        let word = tail.split(' ').next().unwrap_or("");
        let pattern = format!(
            "%{}%",
            word.replace('\\', "\\\\").replace('%', "\\%").replace('_', "\\_")
        );
        let (clause, mut params) = where_clause(filter, "r.");
        params.push(pattern.into());
        let like = params.len();
        params.push(Value::Int(
            i64::try_from(most.saturating_mul(20)).unwrap_or(i64::MAX),
        ));
        let and = if clause.is_empty() { " WHERE" } else { " AND" };
        let rows = self.backend.query(
            &format!(
                "SELECT r.recipe, c.stage, c.step, COALESCE(c.check_key, c.name) FROM checks c \
                 JOIN runs r ON r.id = c.run_id{clause}{and} COALESCE(c.check_key, c.name) LIKE ${like} ESCAPE '\\' \
                 ORDER BY r.started_at DESC LIMIT ${}",
                params.len()
            ),
            &params,
        )?;
        let mut out: Vec<CheckIdentity> = Vec::new();
        for r in &rows {
            let id = CheckIdentity::of(&text(&r[0]), &text(&r[1]), &text(&r[2]), &text(&r[3]));
            if out.len() < most && !out.contains(&id) {
                out.push(id);
            }
        }
        Ok(out)
    }
}

/// The measurement each point is: its identity, whose place in the recipe (its step's
/// number) counts only where a run held that check (recipe, stage and key) at more than one
/// place; elsewhere a recipe edited so that its steps moved keeps one trend, as the
/// comparison with the last pass keeps comparing it.
fn measurements(points: &[TrendPoint]) -> Vec<CheckIdentity> {
    use std::collections::{HashMap, HashSet};
    let ids: Vec<CheckIdentity> = points.iter().map(TrendPoint::identity).collect();
    let mut places: HashMap<(&str, &str, &str, &str), HashSet<&str>> = HashMap::new();
    for (p, id) in points.iter().zip(&ids) {
        places
            .entry((
                p.run.id.as_str(),
                id.recipe.as_str(),
                id.stage.as_str(),
                id.key.as_str(),
            ))
            .or_default()
            .insert(id.path.as_str());
    }
    let placed: HashSet<(&str, &str, &str)> = places
        .iter()
        .filter(|(_, paths)| paths.len() > 1)
        .map(|((_, recipe, stage, key), _)| (*recipe, *stage, *key))
        .collect();
    ids.iter()
        .map(|id| {
            let mut id = id.clone();
            if !placed.contains(&(id.recipe.as_str(), id.stage.as_str(), id.key.as_str())) {
                id.path.clear();
            }
            id
        })
        .collect()
}

/// The refusal of a check's text that stands for several measurements, with how to name
/// each: its JUnit name, the step where two share it, and `--recipe` where recipes do.
fn several(check: &str, found: &[(CheckIdentity, usize)], store: &str) -> String {
    const SHOWN: usize = 12;
    let recipes = found
        .iter()
        .map(|(f, _)| &f.recipe)
        .collect::<std::collections::BTreeSet<_>>();
    let mut lines = vec![format!(
        "`{check}` is {} different checks in {store}: a trend is of one; name it as the JUnit report does{}:",
        found.len(),
        if recipes.len() > 1 { ", with --recipe" } else { "" }
    )];
    for (id, n) in found.iter().take(SHOWN) {
        let shares_place = found
            .iter()
            .filter(|(o, _)| o.recipe == id.recipe && o.stage == id.stage && o.key == id.key)
            .count()
            > 1;
        let mut name = id.case_name();
        if shares_place && !id.path.is_empty() {
            name.push_str(&format!(" (step {})", id.path));
        }
        let recipe = match recipes.len() > 1 {
            true => format!(" --recipe \"{}\"", id.recipe),
            false => String::new(),
        };
        lines.push(format!(
            "  drivescript results trend \"{name}\"{recipe}    ({n} value(s), recipe `{}`{})",
            id.recipe,
            match id.path.is_empty() {
                true => String::new(),
                false => format!(", step {}", id.path),
            }
        ));
    }
    if found.len() > SHOWN {
        lines.push(format!("  … and {} more", found.len() - SHOWN));
    }
    lines.join("\n")
}
