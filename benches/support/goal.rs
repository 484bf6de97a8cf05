//! How a benchmark that runs the release binary says its result: a word per figure against
//! its goal, and its exit code. Shared by those benchmarks; measures nothing itself.

use std::process::ExitCode;

/// The word after a figure and its goal.
pub fn verdict(ok: bool) -> &'static str {
    if ok {
        "meets goal"
    } else {
        "BELOW GOAL"
    }
}

/// The exit of a benchmark whose measuring ended with `result`: a failure to measure is
/// said on standard error and fails the run.
pub fn exit_of(result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("benchmark failed: {e}");
            ExitCode::FAILURE
        }
    }
}
