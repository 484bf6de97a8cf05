//! A validated recipe: its name, parameters as resolved, the steps, and what runs when the
//! steps end (`finally`) or the drive faults (`on_fault`).

use super::step::Step;

/// A parameter as it was finally resolved (declared default or `--set`).
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    pub name: String,
    pub value: String,
    /// `recipes/x.yaml:5` for a declared default, `--set` for an override.
    pub origin: String,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Recipe {
    pub name: String,
    pub description: Option<String>,
    /// The drive family (dictionary) it is written for.
    pub drive: String,
    pub path: String,
    pub params: Vec<Param>,
    pub steps: Vec<Step>,
    /// `None`: the safe default (disable operation, then shutdown). `Some(empty)`: the
    /// recipe explicitly asks for nothing to run.
    pub finally: Option<Vec<Step>>,
    pub on_fault: Vec<Step>,
    /// After a successful run, leave the drive as the steps left it (e.g. a spindle that is
    /// meant to keep turning). Every other ending still stops the drive.
    pub leave_enabled: bool,
}
