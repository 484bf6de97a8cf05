//! A validated recipe: its name, parameters as resolved, the steps, and what runs when the
//! steps end (`finally`) or the drive faults (`on_fault`).

use super::drive_decl::DriveDecl;
use super::step::Step;
use crate::dictionary::Quantity;
use std::time::Duration;

/// The recipe's own choices for the safe stop (`safe_stop:`); the command line's win.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SafeStopChoice {
    /// How long the safe stop waits for standstill.
    pub timeout: Option<Duration>,
    /// Speeds within ± this count as standstill.
    pub standstill: Option<Quantity>,
    /// Where the recipe opts out of braking to standstill before the stop commands
    /// (`brake_to_standstill: false`), as line and column; `None`: the safe stop brakes.
    pub no_brake_at: Option<(usize, usize)>,
}

/// What a failed check does to the rest of the run (`on_failure:` of the recipe or of a
/// block; `run -x` makes it `Stop` everywhere).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum OnFailure {
    /// The run goes on; the verdict is FAILED at its end (as before the key existed).
    #[default]
    Continue,
    /// The first failed check ends the run through the safe stop; the steps after it are
    /// reported as not run.
    Stop,
}

impl OnFailure {
    /// The words a recipe writes, in the order the reference lists them.
    pub const WORDS: [&'static str; 2] = ["stop", "continue"];

    pub fn from_word(word: &str) -> Option<OnFailure> {
        match word {
            "stop" => Some(OnFailure::Stop),
            "continue" => Some(OnFailure::Continue),
            _ => None,
        }
    }
}

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
    /// False when the file names no `drive:` (nor `drives:`) and the dictionary is the
    /// command line's (`--drive`, else the default): said on the run's first line.
    pub drive_named: bool,
    pub path: String,
    pub params: Vec<Param>,
    pub steps: Vec<Step>,
    /// `None`: the safe default (brake to standstill, disable operation, then shutdown).
    /// Either way the safe stop brakes a turning drive first. `Some(empty)`: the
    /// recipe explicitly asks for nothing to run.
    pub finally: Option<Vec<Step>>,
    pub on_fault: Vec<Step>,
    /// After a successful run, leave the drive as the steps left it (e.g. a spindle that is
    /// meant to keep turning): neither the brake nor `finally` runs then. Every other
    /// ending still stops the drive, with `finally` (or the default).
    pub leave_enabled: bool,
    /// `on_failure:` of the recipe: its steps' policy where no block names its own.
    pub on_failure: OnFailure,
    /// `watch:`: limits read all through the steps; one crossed ends the run.
    pub watches: Vec<crate::session::Watch>,
    pub safe_stop: SafeStopChoice,
    /// Settings of the family's link (`link:`), before the command line's.
    pub link: Vec<(String, String)>,
    /// The named drives of `drives:`, in the order written; empty for a recipe with one
    /// `drive:`.
    pub drives: Vec<DriveDecl>,
    /// SHA-256 (hex) of the text the recipe was loaded from with every file it includes
    /// (see `text_digest.rs`).
    pub text_sha256: String,
}
