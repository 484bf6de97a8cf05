//! `results yield`: first-pass and final yield per recipe, station and day (UTC) over the
//! runs a filter takes. A unit is its serial number (a run without one is a unit of its
//! own); its first run in a group decides first pass, its last run final pass. Runs that
//! never started (refused) or never finished (incomplete) say nothing of a unit and are
//! left out; voided runs too unless the filter asks for them. Queries only.

use super::record::NOT_STARTED;
use super::store::{text, where_clause};
use super::stored_run::RunFilter;
use super::{Store, StoreError};
use std::collections::BTreeMap;

/// The yield of one recipe at one station on one day.
#[derive(Debug, Clone, PartialEq)]
pub struct YieldRow {
    pub recipe: String,
    /// Empty when the runs named no station.
    pub station: String,
    /// `2026-11-28` (UTC).
    pub day: String,
    pub units: usize,
    /// Units whose first run passed, and whose last run passed.
    pub first_pass: usize,
    pub final_pass: usize,
    pub runs: usize,
}

impl YieldRow {
    /// First-pass and final yield in %.
    pub fn first_pass_percent(&self) -> f64 {
        percent(self.first_pass, self.units)
    }

    pub fn final_percent(&self) -> f64 {
        percent(self.final_pass, self.units)
    }
}

fn percent(part: usize, of: usize) -> f64 {
    match of {
        0 => 0.0,
        _ => part as f64 * 100.0 / of as f64,
    }
}

impl Store {
    /// The yield per recipe, station and day of the runs `filter` takes (its limit is not
    /// used: a yield counts every run), ordered by recipe, station and day.
    pub fn yields(&mut self, filter: &RunFilter) -> Result<Vec<YieldRow>, StoreError> {
        let (clause, mut params) = where_clause(filter, "r.");
        params.push(NOT_STARTED.into());
        let and = if clause.is_empty() { " WHERE" } else { " AND" };
        let rows = self.backend.query(
            &format!(
                "SELECT r.id, r.recipe, r.station, r.started_at, r.serial, r.verdict FROM runs r{clause}{and} \
                 r.verdict IS NOT NULL AND r.drive <> ${} ORDER BY r.started_at, r.id",
                params.len()
            ),
            &params,
        )?;
        // (recipe, station, day) → unit → (first passed, last passed), and the run count.
        type Units = BTreeMap<String, (bool, bool)>;
        let mut groups: BTreeMap<(String, String, String), (Units, usize)> = BTreeMap::new();
        for r in &rows {
            let started = text(&r[3]);
            let day = started.get(..10).unwrap_or(&started).to_string();
            let passed = text(&r[5]) == "passed";
            let unit = r[4]
                .text()
                .map_or_else(|| format!("run {}", text(&r[0])), str::to_string);
            let (units, runs) = groups.entry((text(&r[1]), text(&r[2]), day)).or_default();
            *runs += 1;
            units
                .entry(unit)
                .and_modify(|(_, last)| *last = passed)
                .or_insert((passed, passed));
        }
        Ok(groups
            .into_iter()
            .map(|((recipe, station, day), (units, runs))| YieldRow {
                recipe,
                station,
                day,
                units: units.len(),
                first_pass: units.values().filter(|(first, _)| *first).count(),
                final_pass: units.values().filter(|(_, last)| *last).count(),
                runs,
            })
            .collect())
    }
}
