//! CiA 301 network management on the wire, pure: the NMT command frame (identifier 0x000,
//! bytes `command node`, node 0 meaning every node), the heartbeat (0x700 + node, one byte
//! of NMT state; 0x00 is the boot-up message) and their names for messages and `decode`.

/// The identifier of NMT commands.
pub const NMT_ID: u32 = 0x000;

/// The identifier of `node`'s heartbeat and boot-up message: 0x700 + node.
pub fn heartbeat_id(node: u8) -> u32 {
    0x700 + u32::from(node)
}

/// An NMT command specifier.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NmtCommand {
    Start,
    Stop,
    EnterPreOperational,
    ResetNode,
    ResetCommunication,
}

const COMMANDS: [(u8, NmtCommand, &str); 5] = [
    (0x01, NmtCommand::Start, "start (enter operational)"),
    (0x02, NmtCommand::Stop, "stop (enter stopped)"),
    (0x80, NmtCommand::EnterPreOperational, "enter pre-operational"),
    (0x81, NmtCommand::ResetNode, "reset node"),
    (0x82, NmtCommand::ResetCommunication, "reset communication"),
];

impl NmtCommand {
    pub fn from_byte(byte: u8) -> Option<NmtCommand> {
        of_byte(&COMMANDS, byte)
    }
    pub fn byte(self) -> u8 {
        row(&COMMANDS, self).map_or(0, |(b, _, _)| *b)
    }
    pub fn name(self) -> &'static str {
        row(&COMMANDS, self).map_or("", |(_, _, n)| n)
    }
}

/// A node's NMT state as its heartbeat carries it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NmtState {
    BootUp,
    Stopped,
    Operational,
    PreOperational,
}

const STATES: [(u8, NmtState, &str); 4] = [
    (0x00, NmtState::BootUp, "boot-up"),
    (0x04, NmtState::Stopped, "stopped"),
    (0x05, NmtState::Operational, "operational"),
    (0x7F, NmtState::PreOperational, "pre-operational"),
];

impl NmtState {
    /// The state of a heartbeat byte; bit 7 is a toggle bit of node guarding, ignored here.
    pub fn from_byte(byte: u8) -> Option<NmtState> {
        let state = if byte == 0x7F { byte } else { byte & 0x7F };
        of_byte(&STATES, state)
    }
    pub fn byte(self) -> u8 {
        row(&STATES, self).map_or(0, |(b, _, _)| *b)
    }
    pub fn name(self) -> &'static str {
        row(&STATES, self).map_or("", |(_, _, n)| n)
    }
    /// SDO is served in pre-operational and operational, not in stopped (CiA 301).
    pub fn serves_sdo(self) -> bool {
        matches!(self, NmtState::Operational | NmtState::PreOperational)
    }
}

/// A table of byte, value and name (`COMMANDS`, `STATES`): the value a byte stands for.
fn of_byte<T: Copy>(table: &[(u8, T, &'static str)], byte: u8) -> Option<T> {
    table
        .iter()
        .find(|(b, _, _)| *b == byte)
        .map(|(_, value, _)| *value)
}

/// The row of `value` in a table of byte, value and name.
fn row<'t, T: PartialEq>(table: &'t [(u8, T, &'static str)], value: T) -> Option<&'t (u8, T, &'static str)> {
    table.iter().find(|(_, v, _)| *v == value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_and_states_round_trip() {
        for (b, c, _) in COMMANDS {
            assert_eq!(NmtCommand::from_byte(b), Some(c));
            assert_eq!(c.byte(), b);
        }
        for (b, s, _) in STATES {
            assert_eq!(NmtState::from_byte(b), Some(s));
            assert_eq!(s.byte(), b);
        }
        assert_eq!(NmtState::from_byte(0x85), Some(NmtState::Operational));
        assert_eq!(NmtState::from_byte(0x03), None);
        assert_eq!(NmtCommand::from_byte(0x03), None);
        assert_eq!(heartbeat_id(5), 0x705);
        assert!(!NmtState::Stopped.serves_sdo() && NmtState::PreOperational.serves_sdo());
    }
}
