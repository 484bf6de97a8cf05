//! The simulated drive's CiA 402 device-control state machine, exactly per the command and
//! CiA 402 state tables (as, for example, `shared/protocols/sd2-dnc.md` gives them): control word in, state and status word out.
//! It must not know about time, speed ramps or bytes; the caller reports standstill.

use crate::drive::device_control::{DeviceCommand, DeviceState};

/// Control-word bit 7: fault reset, acting on its rising edge.
const FAULT_RESET_BIT: u16 = 0x80;

/// Status-word bits beyond the state bits.
const VOLTAGE_ENABLED: u16 = 1 << 4;
const QUICK_STOP_OFF: u16 = 1 << 5;
const REMOTE: u16 = 1 << 9;
const TARGET_REACHED: u16 = 1 << 10;

/// State, the last control word (for the bit-7 edge) and the active drive error.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct DeviceStateMachine {
    state: DeviceState,
    control_word: u16,
    drive_error: u16,
}

impl DeviceStateMachine {
    /// After boot: "not ready to switch on" passes by itself once the drive has initialised,
    /// which the simulator does at once, so it starts in switch on disabled.
    pub(crate) fn booted() -> Self {
        Self::in_state(DeviceState::SwitchOnDisabled)
    }

    pub(crate) fn in_state(state: DeviceState) -> Self {
        DeviceStateMachine {
            state,
            control_word: 0,
            drive_error: 0,
        }
    }

    pub(crate) fn state(&self) -> DeviceState {
        self.state
    }

    /// The last control word written (object 68 reads it back).
    pub(crate) fn control_word(&self) -> u16 {
        self.control_word
    }

    /// The active drive error (object 401), 0 when none.
    pub(crate) fn drive_error(&self) -> u16 {
        self.drive_error
    }

    /// What `control_word` would command in the current state.
    pub(crate) fn command_for(&self, control_word: u16) -> DeviceCommand {
        command_of(control_word, self.control_word, self.state)
    }

    /// Evaluates a written control word. A command the current state does not list leaves
    /// the state unchanged; the write itself is always accepted. With `reset_blocked` the
    /// fault cause persists, so a fault reset leaves the drive in fault.
    pub(crate) fn write_control_word(&mut self, control_word: u16, reset_blocked: bool) -> DeviceCommand {
        let command = command_of(control_word, self.control_word, self.state);
        self.control_word = control_word;
        if command == DeviceCommand::FaultReset {
            if !reset_blocked {
                self.state = DeviceState::SwitchOnDisabled;
                self.drive_error = 0;
            }
        } else {
            self.state = next_state(self.state, command);
        }
        command
    }

    /// A fault trips: any state goes to fault reaction active (the motor brakes), a drive
    /// already faulted stays where it is; either way the new error code is shown.
    pub(crate) fn trip(&mut self, drive_error: u16) {
        self.drive_error = drive_error;
        if !matches!(self.state, DeviceState::FaultReactionActive | DeviceState::Fault) {
            self.state = DeviceState::FaultReactionActive;
        }
    }

    /// The motor has come to rest: the braking states end. Returns whether the state changed.
    pub(crate) fn at_standstill(&mut self) -> bool {
        let next = match self.state {
            DeviceState::QuickStopActive => DeviceState::SwitchOnDisabled,
            DeviceState::FaultReactionActive => DeviceState::Fault,
            _ => return false,
        };
        self.state = next;
        true
    }

    /// Status word (object 67). State bits per the manual's table; b5 (quick stop off) is
    /// set only where the table requires 1 (ready, switched on, operation enabled) and left
    /// 0 where it says x, so switch on disabled reads 0x0240. b4 voltage enabled where the
    /// DC link is switched to the power stage, b9 remote always, b10 target reached.
    pub(crate) fn status_word(&self, at_target: bool) -> u16 {
        let state_bits = match self.state {
            DeviceState::NotReadyToSwitchOn => 0x00,
            DeviceState::SwitchOnDisabled => 0x40,
            DeviceState::ReadyToSwitchOn => 0x01 | QUICK_STOP_OFF | VOLTAGE_ENABLED,
            DeviceState::SwitchedOn => 0x03 | QUICK_STOP_OFF | VOLTAGE_ENABLED,
            DeviceState::OperationEnabled => 0x07 | QUICK_STOP_OFF | VOLTAGE_ENABLED,
            DeviceState::QuickStopActive => 0x07 | VOLTAGE_ENABLED,
            DeviceState::FaultReactionActive => 0x0F,
            DeviceState::Fault => 0x08,
        };
        let reached = if self.state == DeviceState::OperationEnabled && at_target {
            TARGET_REACHED
        } else {
            0
        };
        state_bits | REMOTE | reached
    }
}

/// What a control word commands in `state`, given the previous control word: a rising
/// bit 7 in fault is a fault reset; otherwise the low bits decide, bit 1 first. Value 7 is
/// disable operation in operation enabled and switch on everywhere else.
pub(crate) fn command_of(control_word: u16, previous: u16, state: DeviceState) -> DeviceCommand {
    let rising_reset = control_word & FAULT_RESET_BIT != 0 && previous & FAULT_RESET_BIT == 0;
    if rising_reset && state == DeviceState::Fault {
        DeviceCommand::FaultReset
    } else if control_word & 0x02 == 0 {
        DeviceCommand::DisableVoltage
    } else if control_word & 0x04 == 0 {
        DeviceCommand::QuickStop
    } else if control_word & 0x01 == 0 {
        DeviceCommand::Shutdown
    } else if control_word & 0x08 == 0 {
        if state == DeviceState::OperationEnabled {
            DeviceCommand::DisableOperation
        } else {
            DeviceCommand::SwitchOn
        }
    } else {
        DeviceCommand::EnableOperation
    }
}

/// The transition table; anything not listed keeps the state.
pub(crate) fn next_state(state: DeviceState, command: DeviceCommand) -> DeviceState {
    use DeviceCommand as C;
    use DeviceState as S;
    match (state, command) {
        (S::SwitchOnDisabled, C::Shutdown) => S::ReadyToSwitchOn,
        (S::ReadyToSwitchOn, C::SwitchOn) => S::SwitchedOn,
        (S::SwitchedOn, C::EnableOperation) => S::OperationEnabled,
        (S::OperationEnabled, C::DisableOperation) => S::SwitchedOn,
        (S::SwitchedOn | S::OperationEnabled, C::Shutdown) => S::ReadyToSwitchOn,
        (
            S::ReadyToSwitchOn | S::SwitchedOn | S::OperationEnabled | S::QuickStopActive,
            C::DisableVoltage,
        ) => S::SwitchOnDisabled,
        (S::ReadyToSwitchOn | S::SwitchedOn, C::QuickStop) => S::SwitchOnDisabled,
        (S::OperationEnabled, C::QuickStop) => S::QuickStopActive,
        (S::QuickStopActive, C::EnableOperation) => S::OperationEnabled,
        (S::Fault, C::FaultReset) => S::SwitchOnDisabled,
        (s, _) => s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use DeviceState as S;

    /// Control words, one per command of the manual's table, plus the don't-care variants.
    const DISABLE_VOLTAGE: [u16; 3] = [0x00, 0x05, 0x0D];
    const QUICK_STOP: [u16; 3] = [0x02, 0x03, 0x0B];
    const SHUTDOWN: [u16; 2] = [0x06, 0x0E];
    const SWITCH_ON: u16 = 0x07;
    const ENABLE_OPERATION: u16 = 0x0F;

    fn after(state: DeviceState, control_word: u16) -> DeviceState {
        let mut m = DeviceStateMachine::in_state(state);
        m.write_control_word(control_word, false);
        m.state()
    }

    /// Expected next state for every (state, command) pair; each row of the table.
    #[test]
    fn every_command_in_every_state() {
        const NR: DeviceState = S::NotReadyToSwitchOn;
        const SD: DeviceState = S::SwitchOnDisabled;
        const RS: DeviceState = S::ReadyToSwitchOn;
        const SO: DeviceState = S::SwitchedOn;
        const OE: DeviceState = S::OperationEnabled;
        const QS: DeviceState = S::QuickStopActive;
        const FR: DeviceState = S::FaultReactionActive;
        const F: DeviceState = S::Fault;
        // state, then after: disable voltage, quick stop, shutdown, 0111, 1111
        let table = [
            (NR, NR, NR, NR, NR, NR),
            (SD, SD, SD, RS, SD, SD),
            (RS, SD, SD, RS, SO, RS),
            (SO, SD, SD, RS, SO, OE),
            (OE, SD, QS, RS, SO, OE),
            (QS, SD, QS, QS, QS, OE),
            (FR, FR, FR, FR, FR, FR),
            (F, F, F, F, F, F),
        ];
        assert_eq!(table.len(), DeviceState::ALL.len());
        for (state, dv, qs, sd, on, en) in table {
            for cw in DISABLE_VOLTAGE {
                assert_eq!(after(state, cw), dv, "{state} + disable voltage {cw:#x}");
            }
            for cw in QUICK_STOP {
                assert_eq!(after(state, cw), qs, "{state} + quick stop {cw:#x}");
            }
            for cw in SHUTDOWN {
                assert_eq!(after(state, cw), sd, "{state} + shutdown {cw:#x}");
            }
            assert_eq!(after(state, SWITCH_ON), on, "{state} + 0111");
            assert_eq!(after(state, ENABLE_OPERATION), en, "{state} + 1111");
        }
    }

    #[test]
    fn fault_reset_only_on_a_rising_edge_and_only_in_fault() {
        for state in DeviceState::ALL {
            // Outside fault, 0x80 is read by its low bits: disable voltage.
            let expected = if state == S::Fault {
                S::SwitchOnDisabled
            } else {
                after(state, 0x00)
            };
            assert_eq!(after(state, 0x80), expected, "{state}");
        }
        // Held high, no edge: no reset.
        let mut m = DeviceStateMachine::in_state(S::FaultReactionActive);
        m.trip(0x1234);
        m.write_control_word(0x80, false);
        assert!(m.at_standstill());
        assert_eq!(m.state(), S::Fault);
        m.write_control_word(0x80, false);
        assert_eq!(m.state(), S::Fault);
        assert_eq!(m.drive_error(), 0x1234);
        m.write_control_word(0x00, false);
        assert_eq!(m.write_control_word(0x86, false), DeviceCommand::FaultReset);
        assert_eq!(m.state(), S::SwitchOnDisabled);
        assert_eq!(m.drive_error(), 0);
    }

    #[test]
    fn blocked_fault_reset_keeps_the_fault_and_its_error() {
        let mut m = DeviceStateMachine::booted();
        m.trip(7);
        m.at_standstill();
        m.write_control_word(0x80, true);
        assert_eq!((m.state(), m.drive_error()), (S::Fault, 7));
        m.write_control_word(0x00, false);
        m.write_control_word(0x80, false);
        assert_eq!((m.state(), m.drive_error()), (S::SwitchOnDisabled, 0));
    }

    #[test]
    fn trip_from_every_state_and_standstill() {
        for state in DeviceState::ALL {
            let mut m = DeviceStateMachine::in_state(state);
            m.trip(3);
            let expected = if state == S::Fault {
                S::Fault
            } else {
                S::FaultReactionActive
            };
            assert_eq!(m.state(), expected, "{state}");
            assert_eq!(m.drive_error(), 3);
        }
        for (state, rest) in [
            (S::QuickStopActive, S::SwitchOnDisabled),
            (S::FaultReactionActive, S::Fault),
            (S::OperationEnabled, S::OperationEnabled),
            (S::SwitchedOn, S::SwitchedOn),
        ] {
            let mut m = DeviceStateMachine::in_state(state);
            assert_eq!(m.at_standstill(), state != rest);
            assert_eq!(m.state(), rest);
        }
    }

    #[test]
    fn status_words() {
        let sw = |s, at| DeviceStateMachine::in_state(s).status_word(at);
        assert_eq!(sw(S::NotReadyToSwitchOn, false), 0x0200);
        assert_eq!(sw(S::SwitchOnDisabled, false), 0x0240);
        assert_eq!(sw(S::ReadyToSwitchOn, false), 0x0231);
        assert_eq!(sw(S::SwitchedOn, true), 0x0233);
        assert_eq!(sw(S::OperationEnabled, false), 0x0237);
        assert_eq!(sw(S::OperationEnabled, true), 0x0637);
        assert_eq!(sw(S::QuickStopActive, true), 0x0217);
        assert_eq!(sw(S::FaultReactionActive, false), 0x020F);
        assert_eq!(sw(S::Fault, false), 0x0208);
        for s in DeviceState::ALL {
            assert_eq!(DeviceState::from_status_word(sw(s, true)), Some(s), "{s}");
        }
    }

    #[test]
    fn the_written_control_word_is_remembered() {
        let mut m = DeviceStateMachine::booted();
        assert_eq!(m.control_word(), 0);
        assert_eq!(m.write_control_word(0x0E, false), DeviceCommand::Shutdown);
        assert_eq!(m.control_word(), 0x0E);
        assert_eq!(m.write_control_word(7, false), DeviceCommand::SwitchOn);
        assert_eq!(m.write_control_word(15, false), DeviceCommand::EnableOperation);
        assert_eq!(m.write_control_word(7, false), DeviceCommand::DisableOperation);
    }
}
