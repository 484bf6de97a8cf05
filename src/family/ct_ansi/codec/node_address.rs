//! A drive's serial address: group digit and unit digit (`1.2`), each sent twice (`1122`).
//! Unit 0 addresses the whole group, `0.0` every drive; neither answers. Pure.

use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodeAddress {
    pub group: u8,
    pub unit: u8,
}

impl NodeAddress {
    pub fn new(group: u8, unit: u8) -> Option<NodeAddress> {
        (group <= 9 && unit <= 9).then_some(NodeAddress { group, unit })
    }

    /// `1.2` or `12`; the error says what the notation is (the family wraps it into
    /// `FamilyError::DriveAddress`, the one place it is reported).
    pub fn parse(text: &str) -> Result<NodeAddress, NotAnAddress> {
        let t = text.trim();
        let digits: Vec<u8> = t.bytes().filter(|b| *b != b'.').collect();
        let dots = t.bytes().filter(|b| *b == b'.').count();
        let well_placed = dots == 0 || (dots == 1 && t.len() == 3 && t.as_bytes()[1] == b'.');
        match digits.as_slice() {
            [g, u] if well_placed && g.is_ascii_digit() && u.is_ascii_digit() => Ok(NodeAddress {
                group: g - b'0',
                unit: u - b'0',
            }),
            _ => Err(NotAnAddress {
                text: text.to_string(),
            }),
        }
    }

    /// The four address characters on the wire: each digit twice.
    pub fn wire(self) -> [u8; 4] {
        let (g, u) = (b'0' + self.group, b'0' + self.unit);
        [g, g, u, u]
    }

    /// A group (`G.0`) or global (`0.0`) address: every drive addressed acts, none answers.
    pub fn is_broadcast(self) -> bool {
        self.unit == 0
    }

    /// Whether a drive at `self` acts on a message sent to `to`.
    pub fn accepts(self, to: NodeAddress) -> bool {
        to == self || (to.unit == 0 && (to.group == 0 || to.group == self.group))
    }

    /// One number for [`crate::family::DriveAddress`]: group × 10 + unit.
    pub fn number(self) -> u32 {
        u32::from(self.group) * 10 + u32::from(self.unit)
    }

    pub fn from_number(n: u32) -> Option<NodeAddress> {
        let n = u8::try_from(n).ok()?;
        NodeAddress::new(n / 10, n % 10)
    }

    /// For messages: `drive 1.2`, `group 1 (1.0)`, `every drive (0.0)`.
    pub fn describe(self) -> String {
        match (self.group, self.unit) {
            (0, 0) => "every drive (global address 0.0)".to_string(),
            (g, 0) => format!("every drive of group {g} (group address {g}.0)"),
            _ => format!("drive {self}"),
        }
    }
}

/// Text that is not a drive address, and how one is written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{text}` is not a drive address; write group.unit, e.g. `1.2` (or `12`), each digit 0..9; `G.0` writes to a whole group, `0.0` to every drive")]
pub struct NotAnAddress {
    pub text: String,
}

impl fmt::Display for NodeAddress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.group, self.unit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notation_and_wire() {
        let a = NodeAddress::parse("1.2").unwrap();
        assert_eq!(&a.wire(), b"1122");
        assert_eq!(NodeAddress::parse("12"), Ok(a));
        assert_eq!(&NodeAddress::parse("2.6").unwrap().wire(), b"2266");
        assert_eq!(NodeAddress::from_number(a.number()), Some(a));
        for bad in ["1.23", "123", "1..2", ".12", "a.b", "", "1.", "12."] {
            assert!(NodeAddress::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn group_and_global_addresses_reach_the_drive_but_get_no_answer() {
        let me = NodeAddress::new(1, 2).unwrap();
        let group = NodeAddress::new(1, 0).unwrap();
        let global = NodeAddress::new(0, 0).unwrap();
        assert!(me.accepts(me) && me.accepts(group) && me.accepts(global));
        assert!(!me.accepts(NodeAddress::new(2, 0).unwrap()));
        assert!(!me.accepts(NodeAddress::new(1, 3).unwrap()));
        assert!(group.is_broadcast() && global.is_broadcast() && !me.is_broadcast());
        assert!(global.describe().contains("every drive"));
    }
}
