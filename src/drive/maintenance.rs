//! Maintenance actions a family's drives offer beside object access (Lenze 931: hardware
//! reset, default parameters, parameters from flash, baud rate): what the command line
//! lists and asks about, the clearance the drive layer gives before a destructive one
//! (never while the drive is enabled), and what one action came to. Family-neutral:
//! names, texts and flags only, never a telegram.

use super::DeviceState;

/// One named action, as the family describes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaintenanceAction {
    /// What the user types: `reset`.
    pub name: &'static str,
    /// What the drive is told, in the manual's words: `RESET!`.
    pub command: &'static str,
    /// One line: `hardware reset: the drive restarts`.
    pub summary: &'static str,
    /// Why the action is destructive (it overwrites parameters, restarts the drive,
    /// changes the line), or `None` for a harmless one. Destructive actions need
    /// `--force` or a confirmation, and are refused while the drive is enabled.
    pub destructive: Option<&'static str>,
    /// The name of the number the action takes (`RATE`), or `None`.
    pub argument: Option<&'static str>,
    /// The action changes the line's baud rate to its argument.
    pub changes_line_rate: bool,
}

/// What a maintenance action came to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MaintenanceOutcome {
    /// The drive's reply, as it sent it (a switch-on message's own text).
    pub reply: String,
    /// The baud rate the drive talks at from now on, when the action changed it.
    pub line_rate: Option<u32>,
}

/// Leave to carry out one maintenance action, given by [`Drive::clear_for_maintenance`]
/// (crate::drive::Drive) only: for a destructive action, the drive's state was read and it
/// was not enabled (or, with `force`, the state could not be read at all). The only way
/// to [`Drive::maintain`](crate::drive::Drive::maintain), so no caller can skip the check.
/// Not `Clone`: `maintain` takes it by value, so a clearance given for the state then
/// cannot be kept and used again after the state changed.
#[derive(Debug, PartialEq, Eq)]
pub struct MaintenanceClearance {
    pub(super) action: MaintenanceAction,
    pub(super) argument: Option<u32>,
    pub(super) state: Option<DeviceState>,
    pub(super) unchecked: Option<String>,
}

impl MaintenanceClearance {
    /// The state the drive was in when the clearance was given; `None` for a harmless
    /// action (not read) or a state that could not be read.
    pub fn state(&self) -> Option<DeviceState> {
        self.state
    }

    /// Why the state could not be read, when `force` stood in for it.
    pub fn unchecked(&self) -> Option<&str> {
        self.unchecked.as_deref()
    }

    /// The action as the user names it, with its number: `baud 19200`.
    pub fn shown(&self) -> String {
        shown(&self.action, self.argument)
    }
}

/// `reset`, `baud 19200`.
pub(super) fn shown(action: &MaintenanceAction, argument: Option<u32>) -> String {
    match argument {
        Some(n) => format!("{} {n}", action.name),
        None => action.name.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::MaintenanceClearance;

    /// Compiles only while `MaintenanceClearance` is not `Clone`: with a `Clone` impl the
    /// two blanket impls below both apply and the call is ambiguous.
    #[test]
    fn a_clearance_cannot_be_copied_for_later_use() {
        trait AmbiguousIfClone<A> {
            fn check() {}
        }
        impl<T: ?Sized> AmbiguousIfClone<()> for T {}
        struct IsClone;
        impl<T: Clone> AmbiguousIfClone<IsClone> for T {}
        <MaintenanceClearance as AmbiguousIfClone<_>>::check();
    }
}
