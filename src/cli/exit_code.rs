//! The process exit codes of DESIGN.md, in one place so CI users can rely on them.

/// Everything passed.
pub const PASSED: i32 = 0;
/// An expectation failed, or (for `decode`) a telegram was rejected.
pub const FAILED: i32 = 1;
/// The recipe or the command line is invalid; nothing was sent.
pub const INVALID: i32 = 2;
/// Communication failure or drive fault.
pub const COMMUNICATION: i32 = 3;
/// Interrupted by Ctrl-C (after the safe stop).
pub const INTERRUPTED: i32 = 130;
