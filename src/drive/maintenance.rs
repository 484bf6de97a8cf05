//! Maintenance actions a family's drives offer beside object access (Lenze 931: hardware
//! reset, default parameters, parameters from flash, baud rate): what the command line
//! lists and asks about, and what one action came to. Family-neutral: names, texts and
//! flags only, never a telegram.

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
