//! The device-control roles a dictionary's profile assigns to objects: which object is the
//! control word, the status word, the speed setpoint, and so on. Names and constraints
//! only; the assignment lives in the profile.

use super::data_type::DataType;
use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Role {
    ControlWord,
    StatusWord,
    SpeedSetpoint,
    SpeedActual,
    CurrentActual,
    DriveError,
}

impl Role {
    pub const ALL: [Role; 6] = [
        Role::ControlWord,
        Role::StatusWord,
        Role::SpeedSetpoint,
        Role::SpeedActual,
        Role::CurrentActual,
        Role::DriveError,
    ];

    /// The key in a dictionary's `profile:` mapping.
    pub fn id(self) -> &'static str {
        match self {
            Role::ControlWord => "control_word",
            Role::StatusWord => "status_word",
            Role::SpeedSetpoint => "speed_setpoint",
            Role::SpeedActual => "speed_actual",
            Role::CurrentActual => "current_actual",
            Role::DriveError => "drive_error",
        }
    }

    pub fn from_id(id: &str) -> Option<Role> {
        Self::ALL.into_iter().find(|r| r.id() == id)
    }

    /// Device control cannot work without the control and status word; the others are
    /// optional (a drive family may have no current reading).
    pub fn required(self) -> bool {
        matches!(self, Role::ControlWord | Role::StatusWord)
    }

    /// The engine writes the control word and the speed setpoint and reads the others.
    pub fn written(self) -> bool {
        matches!(self, Role::ControlWord | Role::SpeedSetpoint)
    }

    /// Why an object of `data_type` cannot play this role, if it cannot. The control and
    /// status words are matched against 16-bit masks.
    pub fn type_problem(self, data_type: DataType) -> Option<String> {
        if !data_type.is_integer() {
            return Some(format!("the {self} must be an integer, not {data_type}"));
        }
        if matches!(self, Role::ControlWord | Role::StatusWord) && data_type.size() > 2 {
            return Some(format!(
                "the {self} must be 8 or 16 bits wide (u8, u16), not {data_type}: the profile's command values and state masks are 16-bit"
            ));
        }
        None
    }
}

impl fmt::Display for Role {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.id().replace('_', " "))
    }
}
