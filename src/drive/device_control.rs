//! The device-control vocabulary shared by the drive families: states and commands (the
//! CiA 402 names, which recipes and scripts use whatever the drive), and the CiA 402
//! profile's control-word values and status-word masks, which a family's dictionary may
//! use as they are or replace with its own profile. Pure data and bit arithmetic; no I/O.

use std::fmt;

/// The states of the device-control state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DeviceState {
    NotReadyToSwitchOn,
    SwitchOnDisabled,
    ReadyToSwitchOn,
    SwitchedOn,
    OperationEnabled,
    QuickStopActive,
    FaultReactionActive,
    Fault,
}

impl DeviceState {
    pub const ALL: [DeviceState; 8] = [
        DeviceState::NotReadyToSwitchOn,
        DeviceState::SwitchOnDisabled,
        DeviceState::ReadyToSwitchOn,
        DeviceState::SwitchedOn,
        DeviceState::OperationEnabled,
        DeviceState::QuickStopActive,
        DeviceState::FaultReactionActive,
        DeviceState::Fault,
    ];

    /// The identifier used in recipes and dictionaries: `operation_enabled`.
    pub fn id(self) -> &'static str {
        match self {
            DeviceState::NotReadyToSwitchOn => "not_ready_to_switch_on",
            DeviceState::SwitchOnDisabled => "switch_on_disabled",
            DeviceState::ReadyToSwitchOn => "ready_to_switch_on",
            DeviceState::SwitchedOn => "switched_on",
            DeviceState::OperationEnabled => "operation_enabled",
            DeviceState::QuickStopActive => "quick_stop_active",
            DeviceState::FaultReactionActive => "fault_reaction_active",
            DeviceState::Fault => "fault",
        }
    }

    pub fn from_id(id: &str) -> Option<DeviceState> {
        Self::ALL.into_iter().find(|s| s.id() == id)
    }

    /// The status-word mask and value of the CiA 402 state table.
    pub fn default_mask_value(self) -> (u16, u16) {
        match self {
            DeviceState::NotReadyToSwitchOn => (0x4F, 0x00),
            DeviceState::SwitchOnDisabled => (0x4F, 0x40),
            DeviceState::ReadyToSwitchOn => (0x6F, 0x21),
            DeviceState::SwitchedOn => (0x6F, 0x23),
            DeviceState::OperationEnabled => (0x6F, 0x27),
            DeviceState::QuickStopActive => (0x6F, 0x07),
            DeviceState::FaultReactionActive => (0x4F, 0x0F),
            DeviceState::Fault => (0x4F, 0x08),
        }
    }

    /// The state a status word shows under the default table; `None` for a bit pattern the
    /// table does not list (which a drive should never report).
    pub fn from_status_word(status: u16) -> Option<DeviceState> {
        Self::ALL.into_iter().find(|s| {
            let (mask, value) = s.default_mask_value();
            status & mask == value
        })
    }

    /// True where the power stage can drive the motor.
    pub fn is_powered(self) -> bool {
        matches!(
            self,
            DeviceState::OperationEnabled | DeviceState::QuickStopActive | DeviceState::FaultReactionActive
        )
    }
}

impl fmt::Display for DeviceState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.id().replace('_', " "))
    }
}

/// Device-control commands, written to the control word.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DeviceCommand {
    Shutdown,
    SwitchOn,
    DisableVoltage,
    QuickStop,
    DisableOperation,
    EnableOperation,
    FaultReset,
}

impl DeviceCommand {
    pub const ALL: [DeviceCommand; 7] = [
        DeviceCommand::Shutdown,
        DeviceCommand::SwitchOn,
        DeviceCommand::DisableVoltage,
        DeviceCommand::QuickStop,
        DeviceCommand::DisableOperation,
        DeviceCommand::EnableOperation,
        DeviceCommand::FaultReset,
    ];

    pub fn id(self) -> &'static str {
        match self {
            DeviceCommand::Shutdown => "shutdown",
            DeviceCommand::SwitchOn => "switch_on",
            DeviceCommand::DisableVoltage => "disable_voltage",
            DeviceCommand::QuickStop => "quick_stop",
            DeviceCommand::DisableOperation => "disable_operation",
            DeviceCommand::EnableOperation => "enable_operation",
            DeviceCommand::FaultReset => "fault_reset",
        }
    }

    pub fn from_id(id: &str) -> Option<DeviceCommand> {
        Self::ALL.into_iter().find(|c| c.id() == id)
    }

    /// The control-word value of the CiA 402 command table (don't-care bits 0).
    pub fn default_control_word(self) -> u16 {
        match self {
            DeviceCommand::Shutdown => 6,
            DeviceCommand::SwitchOn => 7,
            DeviceCommand::DisableVoltage => 0,
            DeviceCommand::QuickStop => 2,
            DeviceCommand::DisableOperation => 7,
            DeviceCommand::EnableOperation => 15,
            DeviceCommand::FaultReset => 128,
        }
    }
}

impl fmt::Display for DeviceCommand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.id().replace('_', " "))
    }
}

/// What a control word commands, read as the drive reads it (bit 7 first, then the
/// low bits with their don't-cares). Switch on and disable operation share value 7; which
/// one it is depends on the state the drive is in, so both are named.
pub fn control_word_meaning(control: u16) -> &'static str {
    if control & 0x80 != 0 {
        "fault reset (on the rising edge of bit 7)"
    } else if control & 0x02 == 0 {
        "disable voltage"
    } else if control & 0x06 == 0x02 {
        "quick stop"
    } else if control & 0x07 == 0x06 {
        "shutdown"
    } else if control & 0x0F == 0x07 {
        "switch on / disable operation"
    } else {
        "enable operation"
    }
}

/// Names of the set control-word bits.
pub fn control_word_bits(control: u16) -> Vec<String> {
    bit_names(control, |bit| match bit {
        0 => Some("switch on"),
        1 => Some("enable voltage"),
        2 => Some("quick stop off"),
        3 => Some("enable operation"),
        7 => Some("fault reset"),
        8 => Some("hold"),
        _ => None,
    })
}

/// Names of the set status-word bits CiA 402 defines; other set bits by number.
pub fn status_word_bits(status: u16) -> Vec<String> {
    bit_names(status, |bit| match bit {
        0 => Some("ready to switch on"),
        1 => Some("switched on"),
        2 => Some("operation enabled"),
        3 => Some("fault"),
        5 => Some("quick stop off"),
        6 => Some("switch on disabled"),
        _ => None,
    })
}

fn bit_names(word: u16, name: impl Fn(u32) -> Option<&'static str>) -> Vec<String> {
    (0..16)
        .filter(|bit| word & (1 << bit) != 0)
        .map(|bit| match name(bit) {
            Some(n) => format!("{bit} {n}"),
            None => format!("{bit}"),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn observed_status_words_map_to_their_states() {
        use DeviceState::*;
        for (status_word, state) in [
            (0x7231, Some(ReadyToSwitchOn)),
            (0x7233, Some(SwitchedOn)),
            (0x7237, Some(OperationEnabled)),
            (0x6637, Some(OperationEnabled)),
            (0x0040, Some(SwitchOnDisabled)),
            (0x0007, Some(QuickStopActive)),
            (0x000F, Some(FaultReactionActive)),
            (0x0008, Some(Fault)),
            (0x0000, Some(NotReadyToSwitchOn)),
            (0x0001, None),
        ] {
            assert_eq!(
                DeviceState::from_status_word(status_word),
                state,
                "{status_word:#06x}"
            );
        }
    }

    #[test]
    fn the_state_table_masks_are_disjoint() {
        for sw in 0..=0x7Fu16 {
            let n = DeviceState::ALL
                .iter()
                .filter(|s| {
                    let (m, v) = s.default_mask_value();
                    sw & m == v
                })
                .count();
            assert!(n <= 1, "status word {sw:#x} matches {n} states");
        }
    }

    #[test]
    fn command_table_values() {
        let cw: Vec<u16> = DeviceCommand::ALL
            .iter()
            .map(|c| c.default_control_word())
            .collect();
        assert_eq!(cw, vec![6, 7, 0, 2, 7, 15, 128]);
        for c in DeviceCommand::ALL {
            assert_eq!(DeviceCommand::from_id(c.id()), Some(c));
            assert!(control_word_meaning(c.default_control_word()).contains(&c.to_string()));
        }
    }

    #[test]
    fn bits_are_named() {
        assert_eq!(
            control_word_bits(15),
            vec![
                "0 switch on",
                "1 enable voltage",
                "2 quick stop off",
                "3 enable operation"
            ]
        );
        assert_eq!(
            status_word_bits(0x0231),
            vec!["0 ready to switch on", "4", "5 quick stop off", "9"]
        );
    }
}
