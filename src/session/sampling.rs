//! What a sample step reads, how often, for how long and where its rows also go: the same
//! facts for a recipe's `sample` step and a script's `d.sample(...)`, which the session
//! samples. Plain data; it must not read anything.

use super::{show_duration, ObjectRef};
use std::path::PathBuf;
use std::time::Duration;

/// Read `objects` every `every` for `duration`, keeping statistics; optionally to CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct Sampling {
    pub objects: Vec<ObjectRef>,
    pub every: Duration,
    pub duration: Duration,
    /// The rows also go to this file (under `--output-dir`).
    pub csv: Option<PathBuf>,
}

impl Sampling {
    /// `sample speed_actual every 100 ms for 2 s`: the step's label.
    pub fn label(&self) -> String {
        format!(
            "sample {} every {} for {}",
            ObjectRef::names(&self.objects),
            show_duration(self.every),
            show_duration(self.duration)
        )
    }
}
