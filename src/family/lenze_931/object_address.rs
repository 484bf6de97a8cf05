//! The 931's objects as drivescript addresses them, and its notation in dictionaries and
//! on the command line: a communication object `0x0011` (the manual gives object numbers
//! as 4 hex digits), an identification command `TYPE?`, `VERSION?`, `BOOT?`, `BUS?`, or a
//! CANopen object through the SDO simulation, `sdo:0x6041/0`.
//!
//! Each maps onto the dictionary's index/subindex pair: a communication object is
//! (number, 0); a CANopen object (index, 0x100 + subindex); an identification command
//! (0, 0x1000 + n). Pure.

use crate::dictionary::{Address, AddressError};

/// Subindexes from here on are CANopen objects (subindex + this).
const SDO_BASE: u32 = 0x100;
/// Subindexes from here on (at index 0) are identification commands.
const IDENT_BASE: u32 = 0x1000;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ident {
    Type,
    Version,
    Boot,
    Bus,
}

impl Ident {
    pub const ALL: [Ident; 4] = [Ident::Type, Ident::Version, Ident::Boot, Ident::Bus];

    pub fn command(self) -> &'static str {
        match self {
            Ident::Type => "TYPE?",
            Ident::Version => "VERSION?",
            Ident::Boot => "BOOT?",
            Ident::Bus => "BUS?",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LenzeObject {
    /// A communication object (`OR`/`OW`/`OI`/`ON`/`OX`).
    Communication(u16),
    /// A CANopen object through the SDO simulation (`?iiiiss`, `=iiiiss:dd..`).
    CanOpen { index: u16, subindex: u8 },
    /// An identification command, read-only text.
    Ident(Ident),
}

impl LenzeObject {
    pub fn address(self) -> Address {
        match self {
            LenzeObject::Communication(n) => Address::indexed(n, 0),
            LenzeObject::CanOpen { index, subindex } => {
                Address::indexed(index, SDO_BASE + u32::from(subindex))
            }
            LenzeObject::Ident(i) => {
                let n = Ident::ALL.iter().position(|x| *x == i).unwrap_or(0) as u32;
                Address::indexed(0, IDENT_BASE + n)
            }
        }
    }

    /// The object at `address`, or `None` for a pair no notation of this family gives.
    pub fn of(address: &Address) -> Option<LenzeObject> {
        let Address::Indexed { index, subindex } = *address;
        match subindex {
            0 => Some(LenzeObject::Communication(index)),
            s if (SDO_BASE..SDO_BASE + 0x100).contains(&s) => Some(LenzeObject::CanOpen {
                index,
                subindex: (s - SDO_BASE) as u8,
            }),
            s if index == 0 && s >= IDENT_BASE => Ident::ALL
                .get((s - IDENT_BASE) as usize)
                .map(|i| LenzeObject::Ident(*i)),
            _ => None,
        }
    }

    /// `0x0011`, `sdo:0x6041/0`, `TYPE?`: the notation [`parse`] reads.
    pub fn notation(self) -> String {
        match self {
            LenzeObject::Communication(n) => format!("0x{n:04X}"),
            LenzeObject::CanOpen { index, subindex } => format!("sdo:0x{index:04X}/{subindex}"),
            LenzeObject::Ident(i) => i.command().to_string(),
        }
    }
}

const HELP: &str = "write a communication object number in hex as the manual gives it (`0x0011`), an identification command (`TYPE?`, `VERSION?`, `BOOT?`, `BUS?`), or a CANopen object `sdo:0x6041/0`";

/// Reads the notation (see the module docs); the error says what is accepted.
pub fn parse(text: &str) -> Result<LenzeObject, AddressError> {
    let t = text.trim();
    if let Some(i) = Ident::ALL
        .into_iter()
        .find(|i| i.command().eq_ignore_ascii_case(t))
    {
        return Ok(LenzeObject::Ident(i));
    }
    if let Some(rest) = t.strip_prefix("sdo:") {
        let (index, subindex) = rest.split_once('/').unwrap_or((rest, "0"));
        let index = hex_number(index)
            .and_then(|n| u16::try_from(n).ok())
            .ok_or_else(|| {
                AddressError::from(format!("`{t}`: the CANopen index is 0x0000..=0xFFFF; {HELP}"))
            })?;
        let subindex = number(subindex)
            .and_then(|n| u8::try_from(n).ok())
            .ok_or_else(|| AddressError::from(format!("`{t}`: the CANopen subindex is 0..=255; {HELP}")))?;
        return Ok(LenzeObject::CanOpen { index, subindex });
    }
    if let Some(n) = hex_number(t) {
        return u16::try_from(n).map(LenzeObject::Communication).map_err(|_| {
            AddressError::from(format!(
                "`{t}`: object numbers have 4 hex digits (0x0000..=0xFFFF)"
            ))
        });
    }
    if !t.is_empty() && t.chars().all(|c| c.is_ascii_digit()) {
        return Err(AddressError::from(format!(
            "`{t}`: the manual gives object numbers in hex, so a number without `0x` is ambiguous; write `0x{t:0>4}` for hex {t}"
        )));
    }
    Err(AddressError::from(format!("`{t}` is not a 931 object; {HELP}")))
}

fn hex_number(t: &str) -> Option<u32> {
    let digits = t
        .trim()
        .strip_prefix("0x")
        .or_else(|| t.trim().strip_prefix("0X"))?;
    if digits.is_empty() || digits.len() > 8 {
        return None;
    }
    u32::from_str_radix(digits, 16).ok()
}

fn number(t: &str) -> Option<u32> {
    hex_number(t).or_else(|| t.trim().parse().ok())
}

/// The dictionary reader's view: the notation as an address.
pub fn parse_address(text: &str) -> Result<Address, AddressError> {
    parse(text).map(LenzeObject::address)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_notation_maps_to_an_address_and_back() {
        for (text, object) in [
            ("0x0011", LenzeObject::Communication(0x11)),
            ("0x11", LenzeObject::Communication(0x11)),
            ("0XFFFF", LenzeObject::Communication(0xFFFF)),
            ("TYPE?", LenzeObject::Ident(Ident::Type)),
            ("version?", LenzeObject::Ident(Ident::Version)),
            ("BOOT?", LenzeObject::Ident(Ident::Boot)),
            ("BUS?", LenzeObject::Ident(Ident::Bus)),
            (
                "sdo:0x6041/0",
                LenzeObject::CanOpen {
                    index: 0x6041,
                    subindex: 0,
                },
            ),
            (
                "sdo:0x1018/0x02",
                LenzeObject::CanOpen {
                    index: 0x1018,
                    subindex: 2,
                },
            ),
        ] {
            assert_eq!(parse(text), Ok(object), "{text}");
            assert_eq!(LenzeObject::of(&object.address()), Some(object));
            assert_eq!(parse(&object.notation()), Ok(object));
        }
        assert_eq!(LenzeObject::of(&Address::indexed(5, 7)), None);
    }

    #[test]
    fn refusals_say_what_to_write() {
        assert!(parse("17")
            .unwrap_err()
            .reason
            .contains("write `0x0017` for hex 17"));
        assert!(parse("0x10000").unwrap_err().reason.contains("4 hex digits"));
        assert!(parse("sdo:0x6041/300").unwrap_err().reason.contains("0..=255"));
        assert!(parse("speed").unwrap_err().reason.contains("`0x0011`"));
    }
}
