//! This bench's record as the station's page shows it: the last runs from the results
//! store the station records in, and the certificate of the unit last tested. Read-only
//! and synchronous (the web layer runs it off its event loop); a store that cannot be read
//! is said, never a reason to stop anything.

use crate::results::{certificate_html, Locator, PageLinks, RunFilter};
use crate::run::RecordArgs;
use serde_json::{json, Value};

/// How many runs the page lists.
const LISTED: u64 = 10;

/// The last runs (of `station` when the command line named one), newest first, as the
/// page's JSON: `{"runs": […]}`, or `{"runs": [], "error": why}`.
pub fn last_runs(record: &RecordArgs, station: Option<String>) -> Value {
    let Some((locator, _)) = Locator::resolve(record.results.as_deref()) else {
        return json!({"runs": [], "error": "no results store: give --results PATH to list this bench's runs"});
    };
    let filter = RunFilter {
        station,
        simulated: true,
        limit: Some(LISTED),
        ..RunFilter::default()
    };
    let listed = locator.open(false).and_then(|mut store| store.list(&filter));
    match listed {
        Ok(runs) => json!({"runs": runs.iter().map(|r| json!({
            "started": r.run.started_at,
            "serial": r.run.unit.serial,
            "recipe": r.run.recipe,
            "operator": r.run.unit.operator,
            "verdict": r.verdict(),
        })).collect::<Vec<_>>()}),
        Err(crate::results::StoreError::NotFound(_)) => json!({"runs": []}),
        Err(e) => json!({"runs": [], "error": format!("the results store cannot be read: {e}")}),
    }
}

/// Why the station has no certificate page to show.
#[derive(Debug, thiserror::Error)]
pub enum NoCertificate {
    #[error("no results store: the station records in none")]
    NoStore,
    #[error("the results store cannot be read: {0}")]
    Unreadable(#[from] crate::results::StoreError),
    #[error("no run of unit {serial} in {store}")]
    NoRuns { serial: String, store: String },
}

/// The certificate page of unit `serial` (its runs in the store), or why there is none.
pub fn certificate(record: &RecordArgs, serial: &str) -> Result<String, NoCertificate> {
    let Some((locator, _)) = Locator::resolve(record.results.as_deref()) else {
        return Err(NoCertificate::NoStore);
    };
    let mut store = locator.open(false)?;
    let filter = RunFilter {
        unit: Some(serial.to_string()),
        simulated: true,
        include_void: true,
        ..RunFilter::default()
    };
    let runs = store.unit_runs_in(&filter)?;
    if runs.is_empty() {
        return Err(NoCertificate::NoRuns {
            serial: serial.to_string(),
            store: store.name().to_string(),
        });
    }
    Ok(certificate_html::unit_certificate(serial, &runs, PageLinks::None))
}
