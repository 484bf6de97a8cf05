//! A drive family's device-control profile: which objects play the roles (control word,
//! status word, speed setpoint, …), what each command writes (a control-word value, or a
//! value to another object), the writes made before every command (a control-word enable),
//! and the status-word mask and value of each state. A drive without some of the CiA 402
//! commands or states leaves them out; paths and recipes then use only what it has.
//! Pure data and bit arithmetic; reading it from a file and checking it against the
//! objects is the reader's and validator's job.

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

/// What a command writes: a value to the control word, or (`object`) to another object,
/// as Control Techniques drives reset a trip by writing 100 to #10.38.
#[derive(Debug, Clone)]
pub struct CommandWrite {
    /// `None`: the control word.
    pub object: Option<String>,
    pub value: u16,
    pub span: Span,
}

/// A write the profile makes before every command (Control Techniques: the control-word
/// enable #6.43 = 1, without which the control word does nothing).
#[derive(Debug, Clone)]
pub struct ObjectWrite {
    pub object: String,
    pub value: u16,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct Profile {
    pub(crate) roles: Vec<RoleBinding>,
    /// One entry per command, in the order of [`DeviceCommand::ALL`]; `None` where the
    /// drive has no such command.
    pub(crate) commands: [Option<CommandWrite>; 7],
    /// One pattern per state, in the order of [`DeviceState::ALL`]; `None` where the
    /// drive has no such state (or cannot show it apart from another).
    pub(crate) states: [Option<StateMask>; 8],
    /// Written in this order before every command.
    pub(crate) before_commands: Vec<ObjectWrite>,
    /// Further patterns of a state given with `values: [..]` (an inverter's status
    /// register shows "running" as several codes: accelerating, at speed, decelerating).
    pub(crate) more_states: Vec<(DeviceState, StateMask)>,
    pub(crate) span: Span,
}

impl Profile {
    /// The CiA 402 command values and state table (those of
    /// [`crate::drive::device_control`]) with the given role assignments.
    pub fn with_defaults(roles: Vec<RoleBinding>) -> Profile {
        Profile {
            roles,
            commands: DeviceCommand::ALL.map(|c| {
                Some(CommandWrite {
                    object: None,
                    value: c.default_control_word(),
                    span: Span::unknown(),
                })
            }),
            states: DeviceState::ALL.map(|s| {
                let (mask, value) = s.default_mask_value();
                Some(StateMask { mask, value })
            }),
            before_commands: Vec::new(),
            more_states: Vec::new(),
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

    /// The value `command` writes (0 when the profile has no such command).
    pub fn command_value(&self, command: DeviceCommand) -> u16 {
        self.command(command).map_or(0, |c| c.value)
    }

    /// What `command` writes; `None` when the drive has no such command.
    pub fn command(&self, command: DeviceCommand) -> Option<&CommandWrite> {
        let i = DeviceCommand::ALL.iter().position(|c| *c == command)?;
        self.commands[i].as_ref()
    }

    pub fn has_command(&self, command: DeviceCommand) -> bool {
        self.command(command).is_some()
    }

    /// `control word 131`, or `user_trip = 100` for a command writing another object.
    pub fn command_text(&self, command: DeviceCommand) -> String {
        match self.command(command) {
            Some(CommandWrite {
                object: Some(o),
                value,
                ..
            }) => format!("{o} = {value}"),
            Some(c) => format!("control word {}", c.value),
            None => format!("no {command} command"),
        }
    }

    /// The commands the profile has, by id (for messages).
    pub fn command_ids(&self) -> Vec<&'static str> {
        ids_present(&DeviceCommand::ALL, &self.commands, DeviceCommand::id)
    }

    /// The writes made before every command.
    pub fn before_commands(&self) -> &[ObjectWrite] {
        &self.before_commands
    }

    /// The pattern of `state`; for a state the profile lacks, one no status word matches.
    pub fn state_mask(&self, state: DeviceState) -> StateMask {
        self.state_pattern(state)
            .unwrap_or(StateMask { mask: 0, value: 1 })
    }

    /// The pattern of `state`; `None` when the profile has no such state.
    pub fn state_pattern(&self, state: DeviceState) -> Option<StateMask> {
        let i = DeviceState::ALL.iter().position(|s| *s == state)?;
        self.states[i]
    }

    pub fn has_state(&self, state: DeviceState) -> bool {
        self.state_pattern(state).is_some()
    }

    /// The states the profile has, by id (for messages).
    pub fn state_ids(&self) -> Vec<&'static str> {
        ids_present(&DeviceState::ALL, &self.states, DeviceState::id)
    }

    /// True when the profile has every CiA 402 command and state.
    pub fn is_complete(&self) -> bool {
        self.commands.iter().all(Option::is_some) && self.states.iter().all(Option::is_some)
    }

    /// The state a status word shows; `None` for a pattern the table does not list.
    pub fn state_of(&self, status: u16) -> Option<DeviceState> {
        DeviceState::ALL
            .into_iter()
            .zip(self.states)
            .find(|(_, m)| m.is_some_and(|m| m.matches(status)))
            .map(|(s, _)| s)
            .or_else(|| {
                self.more_states
                    .iter()
                    .find(|(_, m)| m.matches(status))
                    .map(|(s, _)| *s)
            })
    }

    /// Objects other than the control word that the profile writes, with where each is
    /// named and what for (the validator checks they exist and are writable integers).
    pub fn object_writes(&self) -> Vec<(&str, &Span, String)> {
        let mut out: Vec<(&str, &Span, String)> = self
            .before_commands
            .iter()
            .map(|w| {
                (
                    w.object.as_str(),
                    &w.span,
                    "written before every command".to_string(),
                )
            })
            .collect();
        for (command, write) in DeviceCommand::ALL.iter().zip(&self.commands) {
            if let Some(CommandWrite {
                object: Some(o),
                span,
                ..
            }) = write
            {
                out.push((o.as_str(), span, format!("written by `{}`", command.id())));
            }
        }
        out
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
pub(crate) const STOPS: [(DeviceCommand, &[DeviceCommand]); 4] = [
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

/// The ids of the entries of `all` whose place in `table` (kept in the same order) is
/// filled: the commands or states a profile has.
fn ids_present<T: Copy, E>(all: &[T], table: &[Option<E>], id: fn(T) -> &'static str) -> Vec<&'static str> {
    all.iter()
        .zip(table)
        .filter(|(_, entry)| entry.is_some())
        .map(|(t, _)| id(*t))
        .collect()
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
        let m = |mask, value| StateMask { mask, value };
        let (a, b) = (m(0x4F, 0x00), m(0x6F, 0x21));
        assert_eq!(a.overlap(b), None);
        let (c, d) = (m(0x0F, 0x07), m(0x60, 0x20));
        let w = c.overlap(d).unwrap();
        assert!(c.matches(w) && d.matches(w));
    }
}
