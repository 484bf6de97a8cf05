//! A drive family's device-control profile: which objects play the roles (control word,
//! status word, speed setpoint, …), the control-word value of each command, and the
//! status-word mask and value of each state. Pure data and bit arithmetic; reading it from
//! a file and checking it against the objects is the reader's and validator's job.

use super::role::Role;
use crate::diag::Span;
use crate::drive::device_control::{DeviceCommand, DeviceState};

/// An object name assigned to a role, with where the assignment is written.
#[derive(Debug, Clone)]
pub struct RoleBinding {
    pub role: Role,
    pub object: String,
    pub span: Span,
}

/// A state's status-word pattern: `status & mask == value`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct StateMask {
    pub mask: u16,
    pub value: u16,
}

impl StateMask {
    pub fn matches(self, status: u16) -> bool {
        status & self.mask == self.value
    }

    /// A status word both patterns match, if any (then the states are ambiguous).
    pub fn overlap(self, other: StateMask) -> Option<u16> {
        let common = self.mask & other.mask;
        ((self.value ^ other.value) & common == 0).then_some(self.value | other.value)
    }
}

#[derive(Debug, Clone)]
pub struct Profile {
    pub(crate) roles: Vec<RoleBinding>,
    /// One value per command, in the order of [`DeviceCommand::ALL`].
    pub(crate) commands: [u16; 7],
    /// One pattern per state, in the order of [`DeviceState::ALL`].
    pub(crate) states: [StateMask; 8],
    pub(crate) span: Span,
}

impl Profile {
    /// The CiA 402 command values and state table (those of
    /// [`crate::drive::device_control`]) with the given role assignments.
    pub fn with_defaults(roles: Vec<RoleBinding>) -> Profile {
        Profile {
            roles,
            commands: DeviceCommand::ALL.map(DeviceCommand::default_control_word),
            states: DeviceState::ALL.map(|s| {
                let (mask, value) = s.default_mask_value();
                StateMask { mask, value }
            }),
            span: Span::unknown(),
        }
    }

    /// The name of the object playing `role`, as written in the profile.
    pub fn object(&self, role: Role) -> Option<&str> {
        self.binding(role).map(|b| b.object.as_str())
    }

    pub fn binding(&self, role: Role) -> Option<&RoleBinding> {
        self.roles.iter().find(|b| b.role == role)
    }

    pub fn bindings(&self) -> impl Iterator<Item = &RoleBinding> {
        self.roles.iter()
    }

    /// The control-word value that issues `command`.
    pub fn command_value(&self, command: DeviceCommand) -> u16 {
        let i = DeviceCommand::ALL.iter().position(|c| *c == command).unwrap_or(0);
        self.commands[i]
    }

    pub fn state_mask(&self, state: DeviceState) -> StateMask {
        let i = DeviceState::ALL.iter().position(|s| *s == state).unwrap_or(0);
        self.states[i]
    }

    /// The state a status word shows; `None` for a pattern the table does not list.
    pub fn state_of(&self, status: u16) -> Option<DeviceState> {
        DeviceState::ALL
            .into_iter()
            .zip(self.states)
            .find(|(_, m)| m.matches(status))
            .map(|(s, _)| s)
    }

    /// Where the `profile:` mapping is written.
    pub fn span(&self) -> &Span {
        &self.span
    }
}

/// The commands that stop the drive, each with the commands whose bits it must not keep
/// all of: a stop that keeps every bit of `enable_operation` leaves the drive enabled, one
/// that keeps every bit of `switch_on` leaves it switched on. The rule uses the profile's
/// own values, so it holds for any family's control word.
const STOPS: [(DeviceCommand, &[DeviceCommand]); 4] = [
    (DeviceCommand::DisableOperation, &[DeviceCommand::EnableOperation]),
    (
        DeviceCommand::Shutdown,
        &[DeviceCommand::EnableOperation, DeviceCommand::SwitchOn],
    ),
    (
        DeviceCommand::QuickStop,
        &[DeviceCommand::EnableOperation, DeviceCommand::SwitchOn],
    ),
    (
        DeviceCommand::DisableVoltage,
        &[DeviceCommand::EnableOperation, DeviceCommand::SwitchOn],
    ),
];

/// The value of `command` in a command table ordered as [`DeviceCommand::ALL`].
pub(crate) fn command_in(commands: &[u16; 7], command: DeviceCommand) -> u16 {
    let i = DeviceCommand::ALL.iter().position(|c| *c == command).unwrap_or(0);
    commands[i]
}

/// Stop commands of `commands` that keep every bit of a command they must undo: pairs of
/// (stop, the command it would keep in force), at most one pair per stop. Commands whose
/// value is 0 are left out: every value keeps all bits of 0, which the reader reports once.
pub(crate) fn stops_keeping_power(commands: &[u16; 7]) -> Vec<(DeviceCommand, DeviceCommand)> {
    let mut found = Vec::new();
    for (stop, undoes) in STOPS {
        let value = command_in(commands, stop);
        let kept = undoes.iter().find(|c| {
            let bits = command_in(commands, **c);
            bits != 0 && value & bits == bits
        });
        if let Some(kept) = kept {
            found.push((stop, *kept));
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stops_must_clear_a_bit_of_what_they_undo() {
        let defaults = DeviceCommand::ALL.map(DeviceCommand::default_control_word);
        assert!(stops_keeping_power(&defaults).is_empty());
        let mut bad = defaults;
        bad[4] = 15; // disable_operation
        bad[0] = 7; // shutdown keeps switch_on
        bad[3] = 0x8F; // quick_stop keeps enable_operation, plus an extra bit
        assert_eq!(
            stops_keeping_power(&bad),
            [
                (DeviceCommand::DisableOperation, DeviceCommand::EnableOperation),
                (DeviceCommand::Shutdown, DeviceCommand::SwitchOn),
                (DeviceCommand::QuickStop, DeviceCommand::EnableOperation),
            ]
        );
        // Another family's bits: enable 0x30, switch on 0x10; stops clearing them pass.
        let other = [0x01, 0x10, 0x00, 0x02, 0x10, 0x30, 0x80];
        assert!(stops_keeping_power(&other).is_empty());
    }

    #[test]
    fn defaults_match_the_device_control_table() {
        let p = Profile::with_defaults(Vec::new());
        for c in DeviceCommand::ALL {
            assert_eq!(p.command_value(c), c.default_control_word());
        }
        for sw in [0x7231u16, 0x7233, 0x7237, 0x6637, 0x0040, 0x0008, 0x0001] {
            assert_eq!(p.state_of(sw), DeviceState::from_status_word(sw), "{sw:#x}");
        }
    }

    #[test]
    fn overlap_gives_a_word_matching_both() {
        let a = StateMask {
            mask: 0x4F,
            value: 0x00,
        };
        let b = StateMask {
            mask: 0x6F,
            value: 0x21,
        };
        assert_eq!(a.overlap(b), None);
        let c = StateMask {
            mask: 0x0F,
            value: 0x07,
        };
        let d = StateMask {
            mask: 0x60,
            value: 0x20,
        };
        let w = c.overlap(d).unwrap();
        assert!(c.matches(w) && d.matches(w));
    }
}
