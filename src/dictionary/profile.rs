//! A drive family's device-control profile: which objects play the roles (control word,
//! status word, speed setpoint, …), the control-word value of each command, and the
//! status-word mask and value of each state. Pure data and bit arithmetic; reading it from
//! a file and checking it against the objects is the reader's and validator's job.

use super::role::Role;
use super::text_span::TextSpan;
use crate::protocol::device_control::{DeviceCommand, DeviceState};

/// An object name assigned to a role, with where the assignment is written.
#[derive(Debug, Clone)]
pub struct RoleBinding {
    pub role: Role,
    pub object: String,
    pub span: TextSpan,
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
    pub(crate) span: TextSpan,
}

impl Profile {
    /// The SD2 manual's command values and state table (those of
    /// [`crate::protocol::device_control`]) with the given role assignments.
    pub fn with_defaults(roles: Vec<RoleBinding>) -> Profile {
        Profile {
            roles,
            commands: DeviceCommand::ALL.map(DeviceCommand::default_control_word),
            states: DeviceState::ALL.map(|s| {
                let (mask, value) = s.default_mask_value();
                StateMask { mask, value }
            }),
            span: TextSpan::unknown(),
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
    pub fn span(&self) -> &TextSpan {
        &self.span
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
