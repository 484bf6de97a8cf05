//! Why a run's operations stopped early (a failed expectation, an unanswered prompt, a
//! drive fault, a lost port, another error, a stop request, a panic), how each reads in a
//! step line, and the conversions from drive errors and panics. Plain data.

use crate::drive::DriveError;
use std::time::Duration;

/// Why the steps stopped early.
#[derive(Debug)]
pub enum Stop {
    /// An expectation failed in a way the following steps cannot continue from.
    Failed(String),
    /// Nobody answered an operator step within its timeout: its check failed, but nothing
    /// was measured wrong, so an `attempts` block does not try again; the run ends.
    Unanswered(String),
    /// The operator's answer named another unit than the run is for: its check failed, and
    /// as no other attempt changes the unit on the bench, none is made; the run ends.
    OtherUnit(String),
    /// A failed check ended the run because `on_failure: stop` or `run -x` says so: no
    /// `attempts` block tries again and no script's `catch` goes on from it.
    StoppedOnFailure(String),
    /// The drive went to fault.
    Fault(String),
    /// The port failed (device gone, connection closed): only reopening it can help.
    LinkLost(String),
    /// Communication or another drive error.
    Error(String),
    /// A stop request (signal).
    Interrupted,
    /// A panic inside the run: a bug, but the drive must still be stopped.
    Panicked(String),
}

/// Whether an operation went well, and what to say about it.
pub fn outcome(result: &Result<String, Stop>) -> (bool, String) {
    match result {
        Ok(d) => (true, d.clone()),
        Err(
            Stop::Failed(m)
            | Stop::Unanswered(m)
            | Stop::OtherUnit(m)
            | Stop::StoppedOnFailure(m)
            | Stop::Fault(m)
            | Stop::LinkLost(m)
            | Stop::Error(m),
        ) => (false, m.clone()),
        Err(Stop::Interrupted) => (false, "interrupted".to_string()),
        Err(Stop::Panicked(m)) => (false, format!("internal error (panic): {m}")),
    }
}

impl From<DriveError> for Stop {
    fn from(e: DriveError) -> Self {
        if e.is_interrupted() {
            Stop::Interrupted
        } else if e.is_fault() {
            Stop::Fault(e.to_string())
        } else if e.is_link_lost() {
            Stop::LinkLost(e.to_string())
        } else {
            Stop::Error(e.to_string())
        }
    }
}

/// A samples file that cannot be written ends the run: its samples would be lost.
impl From<crate::output_file_error::OutputFileError> for Stop {
    fn from(e: crate::output_file_error::OutputFileError) -> Self {
        Stop::Error(e.to_string())
    }
}

/// The text of a panic's payload (`panic!("...")` carries a `&str` or a `String`).
pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".to_string())
}

/// `start + every × k`, or an error instead of the overflow panic.
pub(crate) fn nth_tick(start: Duration, every: Duration, k: u32) -> Result<Duration, Stop> {
    every
        .checked_mul(k)
        .and_then(|d| start.checked_add(d))
        .ok_or_else(|| Stop::Error(format!("time overflow: {k} × {every:?} after {start:?}")))
}
