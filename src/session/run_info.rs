//! What a run and each of its steps are, as the reports show them: the recipe or script
//! with its parameters, and a step's number, one-line label, origin and phase. Plain data,
//! so recipes and scripts report alike.

use super::{StepOrigin, UnitIdentity};

/// A run, for the header of every report.
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// `recipe` or `script`.
    pub kind: &'static str,
    pub name: String,
    pub path: String,
    /// Parameters as resolved: (name, value).
    pub params: Vec<(String, String)>,
    /// The unit under test, as far as known when the run starts.
    pub unit: UnitIdentity,
    /// SHA-256 (hex) of the text it runs with, includes too, when the front end knows it;
    /// `None`: the file's own (a script, which includes nothing).
    pub text_sha256: Option<String>,
}

/// One step or operation as it starts.
#[derive(Debug, Clone, PartialEq)]
pub struct StepInfo {
    /// `3`, or `7.2.1` inside repeat/include, or `finally.2`.
    pub number: String,
    /// `set speed_setpoint = 6000 rpm`.
    pub label: String,
    pub origin: StepOrigin,
    /// `steps`, `finally` or `on_fault`.
    pub phase: &'static str,
    /// A step that only holds others (repeat, include): reports announce it and show its
    /// nested steps under it.
    pub container: bool,
}
