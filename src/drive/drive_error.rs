//! The one error type of the drive layer: object names, values, states and the drive's own
//! error code, with what to do. Refusals (unknown object, read-only, out of limits) are
//! raised before any byte is sent.

use super::AccessError;
use crate::dictionary::ValueError;
use crate::drive::device_control::{DeviceCommand, DeviceState};
use std::time::Duration;

#[derive(Debug, thiserror::Error)]
pub enum DriveError {
    #[error("unknown object `{name}`{}", suggest(suggestions, drive.as_deref()))]
    UnknownObject {
        name: String,
        suggestions: Vec<String>,
        /// The built-in dictionary's name, for the `--drive` of `drivescript objects`.
        drive: Option<String>,
    },

    #[error("{object} is read-only; nothing was sent")]
    ReadOnly { object: String },

    #[error("{object} is write-only and cannot be read")]
    WriteOnly { object: String },

    #[error("{0}; nothing was sent")]
    Value(#[from] ValueError),

    /// A number was asked of an object that holds text (a name plate, a firmware string).
    #[error("{object} holds text ({data_type}), not a number")]
    NotANumber {
        object: String,
        data_type: crate::dictionary::DataType,
    },

    #[error("reading {object}: {source}")]
    BadReply {
        object: String,
        #[source]
        source: ValueError,
    },

    #[error("the {dictionary} dictionary's profile names no {role} object, which device control needs")]
    NoRole { dictionary: String, role: &'static str },

    #[error("the {dictionary} dictionary's profile has no {command} command (the drive's commands: {has})")]
    NoCommand {
        dictionary: String,
        command: DeviceCommand,
        has: String,
    },

    #[error("the {dictionary} dictionary's profile has no state {state} (the drive's states: {has})")]
    NoState {
        dictionary: String,
        state: DeviceState,
        has: String,
    },

    #[error(transparent)]
    Access(#[from] AccessError),

    /// A destructive maintenance action while the drive is enabled: never sent.
    #[error("the drive is in {state}, and {action} is refused while it is enabled ({why})")]
    EnabledForMaintenance {
        action: String,
        state: DeviceState,
        why: &'static str,
    },

    /// A destructive maintenance action on a drive whose state cannot be read, without
    /// `force`: never sent.
    #[error("{action} is destructive ({why}), and {}", state_unknown(cause))]
    MaintenanceStateUnknown {
        action: String,
        why: &'static str,
        cause: Box<DriveError>,
    },

    #[error("{port} refused {operation} {object}: {text}")]
    Refused {
        port: String,
        operation: &'static str,
        object: String,
        /// The drive's own error code and its meaning.
        code: u32,
        text: String,
    },

    #[error("status word 0x{status:04x} matches no state of the profile's state table")]
    UnknownStatus { status: u16 },

    #[error("stuck in {stuck_in} on the way to {target}: no change within {} ms{}; {hint}", waited.as_millis(), drive_error_text(*drive_error))]
    StateTimeout {
        target: DeviceState,
        stuck_in: DeviceState,
        waited: Duration,
        drive_error: Option<u16>,
        hint: String,
    },

    #[error("no command leads from {from} to {to}; the drive enters {to} by itself")]
    Unreachable { from: DeviceState, to: DeviceState },

    #[error("the drive is in {state}{}; run `fault_reset` once the cause is removed", drive_error_text(*drive_error))]
    Fault {
        state: DeviceState,
        drive_error: Option<u16>,
    },

    #[error("interrupted")]
    Interrupted,

    #[error("{object} changes how the drive talks on the line, after which nothing could reach it at the old settings, not even a stop; {why}; nothing was sent. Disable the drive first (shutdown), then write it as a one-off `drivescript write`")]
    LineChangeRefused { object: String, why: String },
}

fn suggest(s: &[String], drive: Option<&str>) -> String {
    if s.is_empty() {
        format!("; {}", crate::dictionary::objects_command(drive))
    } else {
        format!(
            "; did you mean {}?",
            s.iter()
                .map(|x| format!("`{x}`"))
                .collect::<Vec<_>>()
                .join(" or ")
        )
    }
}

fn drive_error_text(code: Option<u16>) -> String {
    match code {
        Some(0) | None => String::new(),
        Some(c) => format!(" (drive error {c}, 0x{c:04x})"),
    }
}

impl DriveError {
    /// True for errors where the line or the drive is unreachable (exit code 3 territory).
    pub fn is_communication(&self) -> bool {
        matches!(self, DriveError::Access(_))
    }

    /// True when the port itself failed (device gone, connection closed), so that only
    /// reopening it can reach the drive again.
    pub fn is_link_lost(&self) -> bool {
        matches!(self, DriveError::Access(e) if e.is_transport())
    }

    /// True when a stop request ended the operation.
    pub fn is_interrupted(&self) -> bool {
        matches!(self, DriveError::Interrupted) || matches!(self, DriveError::Access(e) if e.is_interrupted())
    }

    /// True when the drive itself is in fault.
    pub fn is_fault(&self) -> bool {
        matches!(self, DriveError::Fault { .. })
    }
}

/// Why nobody can tell whether the drive is enabled, from the error of reading its state.
pub fn state_unknown(cause: &DriveError) -> String {
    match cause {
        DriveError::NoRole { dictionary, .. } => format!(
            "the drive's state cannot be checked: the {dictionary} dictionary has no device-control profile, so drivescript cannot tell whether the drive is enabled"
        ),
        other => format!(
            "the drive's state cannot be read ({other}), so drivescript cannot tell whether the drive is enabled"
        ),
    }
}
