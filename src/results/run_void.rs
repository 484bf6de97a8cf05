//! `results void`: marks a run void (the wrong unit scanned, a bench fault) with who, when
//! and why. The run stays as it was recorded and the void is a row of its own, an audit
//! record: nothing here deletes or changes a run, and a void is never undone or
//! overwritten (a second void of the same run is refused, naming the first).

use super::stored_run::VoidRow;
use super::{Store, StoreError};

impl Store {
    /// Voids the run `id` (or the run whose id starts so) on behalf of `by` at `at` (UTC,
    /// RFC 3339) because of `why`: the void as stored.
    pub fn void(&mut self, id: &str, by: &str, at: &str, why: &str) -> Result<VoidRow, StoreError> {
        if why.trim().is_empty() {
            return Err(StoreError::Refused(
                "a void needs its reason: --why \"wrong unit scanned\"".into(),
            ));
        }
        let run = self.run(id)?;
        if let Some(v) = run.void {
            return Err(StoreError::Refused(format!(
                "run {} was voided already, by {} at {}: {}; a void is never changed",
                v.run, v.voided_by, v.voided_at, v.why
            )));
        }
        let row = VoidRow {
            run: run.run.id,
            voided_at: at.to_string(),
            voided_by: by.to_string(),
            why: why.to_string(),
        };
        // ON CONFLICT: a void written at the same moment by another bench stays the one.
        let written = self.backend.execute(
            "INSERT INTO voids (run_id, voided_at, voided_by, why) VALUES ($1, $2, $3, $4) \
             ON CONFLICT (run_id) DO NOTHING",
            &[
                row.run.as_str().into(),
                row.voided_at.as_str().into(),
                row.voided_by.as_str().into(),
                row.why.as_str().into(),
            ],
        )?;
        if written == 0 {
            return Err(StoreError::Refused(format!(
                "run {} was voided by someone else just now; `drivescript results show {}` says by whom",
                row.run, row.run
            )));
        }
        Ok(row)
    }
}
