//! The service-data-channel error byte of SD2 replies and its meaning. Pure.

use crate::family::documented_code::documented_code;

/// The `error` byte of a reply. Drives set bit 7 or not; both forms mean the same.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ErrorCode(pub u8);

impl ErrorCode {
    pub const OK: ErrorCode = ErrorCode(0);

    pub fn is_ok(self) -> bool {
        self.0 == 0
    }

    /// The manual's text for this code, `None` for a code the manual does not list.
    pub fn meaning(self) -> Option<&'static str> {
        if self.0 == 0 {
            return Some("no error");
        }
        Some(match self.0 & 0x7F {
            0x01 => "toggle bit not alternated",
            0x06 => "CRC error",
            0x07 => "no free memory",
            0x08 => "unsupported access to an object",
            0x09 => "attempt to read a write-only object",
            0x0A => "attempt to write a read-only object",
            0x0B => "object does not exist in the object dictionary",
            0x0C | 0x0D => "reserved",
            0x0E => "general parameter incompatibility",
            0x0F => "general internal incompatibility in the device",
            0x10 => "access failed due to hardware error",
            0x11 => "data type wrong, service parameter length wrong",
            0x12 => "data type wrong, service parameter too long",
            0x13 => "data type wrong, service parameter too short",
            0x14 => "subindex does not exist",
            0x15 => "value range exceeded (write)",
            0x16 => "written value too high",
            0x17 => "written value too low",
            0x18 => "maximum value less than minimum value",
            0x19 => "general error",
            0x1A => "data cannot be transferred or stored in the application",
            0x1B => "data cannot be transferred or stored because of the state of the control",
            0x1C => "data cannot be transferred or stored because of the device reset",
            0x1D => "object dictionary cannot be generated or does not exist",
            0x1E => "read access denied",
            0x1F => "write access denied",
            _ => return None,
        })
    }

    /// The canonical code (bit 7 set) the simulator sends.
    pub const OBJECT_DOES_NOT_EXIST: ErrorCode = ErrorCode(0x8B);
    pub const READ_ONLY: ErrorCode = ErrorCode(0x8A);
    pub const WRITE_ONLY: ErrorCode = ErrorCode(0x89);
    pub const LENGTH_WRONG: ErrorCode = ErrorCode(0x91);
    pub const TOO_LONG: ErrorCode = ErrorCode(0x92);
    pub const TOO_SHORT: ErrorCode = ErrorCode(0x93);
    pub const SUBINDEX_DOES_NOT_EXIST: ErrorCode = ErrorCode(0x94);
    pub const RANGE_EXCEEDED: ErrorCode = ErrorCode(0x95);
    pub const TOO_HIGH: ErrorCode = ErrorCode(0x96);
    pub const TOO_LOW: ErrorCode = ErrorCode(0x97);
    pub const STATE_OF_CONTROL: ErrorCode = ErrorCode(0x9B);
}

// `0x95 value range exceeded (write)`.
documented_code!(ErrorCode, "0x{:02X}", "a code the SD2 manual does not list");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_seven_does_not_change_the_meaning() {
        for low in 1u8..=0x1F {
            assert_eq!(
                ErrorCode(low).meaning(),
                ErrorCode(low | 0x80).meaning(),
                "{low:#x}"
            );
        }
        assert_eq!(
            ErrorCode(0x8B).meaning(),
            Some("object does not exist in the object dictionary")
        );
        assert_eq!(
            ErrorCode(0x0A).meaning(),
            Some("attempt to write a read-only object")
        );
    }

    #[test]
    fn unlisted_codes_say_so() {
        for code in [0x02u8, 0x05, 0x20, 0x80, 0xFF] {
            assert_eq!(ErrorCode(code).meaning(), None, "{code:#x}");
            assert!(ErrorCode(code).to_string().contains("does not list"));
        }
        assert!(ErrorCode::OK.is_ok());
        assert_eq!(ErrorCode(0x95).to_string(), "0x95 value range exceeded (write)");
    }
}
