//! What the store gives back: a run with how it ended (if it did), its checks and steps
//! and series when asked for one run, the filters of `results list`, and one point of a
//! trend. Plain data for the command line and the HTML pages.

use super::record::{CheckRow, EndRow, RunRow, StepRow};

/// A stored run; `end` is `None` for a run that never finished (killed, or still going).
#[derive(Debug, Clone, PartialEq)]
pub struct StoredRun {
    pub run: RunRow,
    pub end: Option<EndRow>,
    /// Filled when one run (or one unit's runs) is asked for.
    pub checks: Vec<CheckRow>,
    pub steps: Vec<StepRow>,
}

impl StoredRun {
    /// `passed`, `failed`, `error`, `interrupted`, `panic`, `refused` (never started), or
    /// `incomplete`.
    pub fn verdict(&self) -> &str {
        self.end.as_ref().map_or("incomplete", |e| e.verdict.as_str())
    }

    /// Whether it started: a run refused before it started (recorded for its unit) did
    /// not, and tells nothing of the unit itself.
    pub fn started(&self) -> bool {
        self.run.drive != super::record::NOT_STARTED
    }
}

/// Which runs `results list`, `export` and `trend` take.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunFilter {
    /// The unit's serial number, exactly.
    pub unit: Option<String>,
    /// The recipe's name or path, exactly.
    pub recipe: Option<String>,
    /// A verdict word, or `incomplete`.
    pub verdict: Option<String>,
    /// Runs started at or after this UTC time (RFC 3339).
    pub since: Option<String>,
    /// Runs on the built-in simulated drive too.
    pub simulated: bool,
    /// The newest this many (`None`: all).
    pub limit: Option<u64>,
}

/// One check's value in one run, for `results trend`.
#[derive(Debug, Clone, PartialEq)]
pub struct TrendPoint {
    /// The check's name in that run (with the limits it had there) and its key.
    pub name: String,
    pub key: String,
    pub run: String,
    pub started_at: String,
    pub serial: Option<String>,
    pub measured: Option<f64>,
    pub unit: Option<String>,
    pub low: Option<f64>,
    pub high: Option<f64>,
    pub passed: bool,
}
