//! What `check` prints about a recipe's or script's own choices for the end of a run
//! (an opt-out from braking, `leave_enabled`), shared by the recipe and script checks so
//! that neither choice is ever silent. It prints only; it decides nothing.

use crate::recipe::SafeStopChoice;

/// What `check` says about a recipe's or script's opt-out from braking and about
/// `leave_enabled`, so that neither is silent.
pub(super) fn print(path: &std::path::Path, choice: &SafeStopChoice, leave_enabled: bool) {
    if leave_enabled {
        println!(
            "    leave_enabled: a run that succeeds leaves the drive as its steps left it (no brake, \
             no finally); every other ending stops it. `drivescript stop` stops it later"
        );
    }
    if let Some((line, column)) = choice.no_brake_at {
        println!(
            "    safe stop does not brake: brake_to_standstill is false at {}:{line}:{column}; \
             a drive still turning at the end is disabled at speed and coasts",
            path.display()
        );
    }
}
