//! Lenze codes as the manuals write them — `C00099`, `C99`, `C00002/16` — and their place
//! in the CANopen object dictionary: index = 0x5FFF − code, subindex = subcode. Pure.

use crate::dictionary::AddressError;
use std::fmt;

/// The index the code numbers count down from (24575).
pub const CODE_BASE: u16 = 0x5FFF;
/// Highest index the explainer shows as a code: codes above 16383 would fall into the
/// CiA 301 communication area (below 0x2000), which is not parameter data.
const LOWEST_CODE_INDEX: u16 = 0x2000;

/// A code and its subcode (0 for codes without subcodes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Code {
    pub number: u16,
    pub subcode: u8,
}

impl Code {
    pub fn new(number: u16, subcode: u8) -> Option<Code> {
        (number <= CODE_BASE - LOWEST_CODE_INDEX).then_some(Code { number, subcode })
    }

    /// The CANopen index: 0x5FFF − code.
    pub fn index(self) -> u16 {
        CODE_BASE - self.number
    }

    /// The code at a CANopen index and subindex, when the index is in the codes' range.
    pub fn at(index: u16, subindex: u8) -> Option<Code> {
        (LOWEST_CODE_INDEX..=CODE_BASE).contains(&index).then(|| Code {
            number: CODE_BASE - index,
            subcode: subindex,
        })
    }

    /// Reads `C00099`, `C99`, `c2/16`, `C00002/16`; the error says how codes are written.
    pub fn parse(text: &str) -> Result<Code, AddressError> {
        let help = "write a Lenze code as C followed by its number and an optional /subcode, e.g. `C00099`, `C99` or `C00002/16`";
        let t = text.trim();
        let rest = t
            .strip_prefix('C')
            .or_else(|| t.strip_prefix('c'))
            .ok_or_else(|| AddressError::from(format!("`{t}` is not a Lenze code; {help}")))?;
        let (number, subcode) = rest.split_once('/').unwrap_or((rest, "0"));
        let digits = |s: &str| !s.is_empty() && s.len() <= 5 && s.bytes().all(|b| b.is_ascii_digit());
        if !digits(number) {
            return Err(AddressError::from(format!(
                "`{t}`: the code number must be 1 to 5 digits; {help}"
            )));
        }
        if !digits(subcode) {
            return Err(AddressError::from(format!(
                "`{t}`: the subcode must be a number 0..=255; {help}"
            )));
        }
        let number: u32 = number
            .parse()
            .map_err(|_| AddressError::from(format!("`{t}`: {help}")))?;
        let subcode: u8 = subcode.parse().map_err(|_| {
            AddressError::from(format!(
                "`{t}`: the subcode must be 0..=255 (it is the CANopen subindex)"
            ))
        })?;
        u16::try_from(number)
            .ok()
            .and_then(|n| Code::new(n, subcode))
            .ok_or_else(|| {
                AddressError::from(format!(
                    "`{t}`: codes go up to C{:05} (index 0x{LOWEST_CODE_INDEX:04X}); higher numbers fall outside the parameter area",
                    CODE_BASE - LOWEST_CODE_INDEX
                ))
            })
    }
}

impl fmt::Display for Code {
    /// `C00099`, `C00002/16`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "C{:05}", self.number)?;
        if self.subcode != 0 {
            write!(f, "/{}", self.subcode)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_notes_mapping() {
        let index = |t: &str| Code::parse(t).map(|c| (c.index(), c.subcode));
        assert_eq!(index("C00099"), Ok((0x5F9C, 0)));
        assert_eq!(index("C99"), Ok((0x5F9C, 0)));
        assert_eq!(index("C00061"), Ok((0x5FC2, 0)));
        assert_eq!(index("C00088"), Ok((0x5FA7, 0)));
        assert_eq!(index("C00011"), Ok((0x5FF4, 0)));
        assert_eq!(index("C00002/16"), Ok((0x5FFD, 16)));
        assert_eq!(index("c2/16"), Ok((0x5FFD, 16)));
        assert_eq!(Code::at(0x5F9C, 0).unwrap().to_string(), "C00099");
        assert_eq!(Code::at(0x5FFD, 16).unwrap().to_string(), "C00002/16");
        assert_eq!(Code::at(0x1000, 0), None);
    }

    #[test]
    fn bad_codes_say_how_to_write_them() {
        assert!(Code::parse("99").unwrap_err().to_string().contains("C00099"));
        assert!(Code::parse("C")
            .unwrap_err()
            .to_string()
            .contains("1 to 5 digits"));
        assert!(Code::parse("C2/300").unwrap_err().to_string().contains("0..=255"));
        assert!(Code::parse("C2/x").unwrap_err().to_string().contains("subcode"));
        assert!(Code::parse("C20000").unwrap_err().to_string().contains("C16383"));
        assert!(Code::parse("C123456").is_err());
    }
}
