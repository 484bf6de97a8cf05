//! The process exit codes of DESIGN.md, in one place so CI users can rely on them.

/// Everything passed.
pub const PASSED: i32 = 0;
/// An expectation failed, or (for `decode`) a telegram was rejected.
pub const FAILED: i32 = 1;
/// The recipe or the command line is invalid; nothing was sent.
pub const INVALID: i32 = 2;
/// Communication failure, drive fault, or a safe stop that could not be confirmed.
pub const COMMUNICATION: i32 = 3;
// A stop signal ends a run with 128 + its number and a panic with 101, both after the
// safe stop: see `StopSignal::exit_code` and `RunReport::exit_code`.
