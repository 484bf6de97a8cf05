//! The results store as the place a run reads the unit's past runs from, for checks that
//! compare with its last passed run: each lookup on a thread of its own, so the session
//! bounds its wait and stays stoppable while a slow or dead store answers (or not). Reads
//! only; a store that cannot be read is an error, never "no history".

use super::Locator;
use crate::session::{History, HistoryError, PastRun};
use std::sync::mpsc::{sync_channel, Receiver};

/// The run's store, read for the unit's last passed run among runs as simulated as this one.
#[derive(Debug, Clone)]
pub struct StoreHistory {
    locator: Locator,
    simulated: bool,
}

impl StoreHistory {
    pub fn new(locator: Locator, simulated: bool) -> StoreHistory {
        StoreHistory { locator, simulated }
    }
}

impl History for StoreHistory {
    fn look_up(&self, recipe: &str, serial: &str) -> Receiver<Result<Option<PastRun>, HistoryError>> {
        let (answer, answered) = sync_channel(1);
        let (locator, recipe, serial, simulated) = (
            self.locator.clone(),
            recipe.to_string(),
            serial.to_string(),
            self.simulated,
        );
        let spawned = std::thread::Builder::new().name("history".into()).spawn({
            let answer = answer.clone();
            move || {
                let _ = answer.send(last_pass(&locator, &recipe, &serial, simulated));
            }
        });
        if let Err(e) = spawned {
            let _ = answer.send(Err(HistoryError {
                store: self.store(),
                why: format!(
                    "cannot read the results store {}: no thread for it ({e})",
                    self.store()
                ),
            }));
        }
        answered
    }

    fn store(&self) -> String {
        self.locator.name()
    }

    fn kind_of_runs(&self) -> &'static str {
        if self.simulated {
            "simulated runs"
        } else {
            "runs on real drives"
        }
    }
}

fn last_pass(
    locator: &Locator,
    recipe: &str,
    serial: &str,
    simulated: bool,
) -> Result<Option<PastRun>, HistoryError> {
    // No file yet: no run was ever recorded there (a query must not create one).
    if let Locator::Sqlite(path) = locator {
        if !path.exists() {
            return Ok(None);
        }
    }
    let failed = |e: super::StoreError| HistoryError {
        store: locator.name(),
        why: e.to_string(),
    };
    locator
        .open(false)
        .and_then(|mut store| store.last_pass(recipe, serial, simulated))
        .map_err(failed)
}
