//! The 32-bit error codes an object command answers with (`OW:00000004`), their meaning
//! from the manual, and which of them mean "written, but limited".

use crate::family::documented_code::documented_code;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ErrorCode(pub u32);

impl ErrorCode {
    pub const TOO_LOW: ErrorCode = ErrorCode(0x0000_0002);
    pub const TOO_HIGH: ErrorCode = ErrorCode(0x0000_0003);
    pub const TOO_LOW_LIMITED: ErrorCode = ErrorCode(0x0000_0004);
    pub const TOO_HIGH_LIMITED: ErrorCode = ErrorCode(0x0000_0005);
    pub const BIT_CONSTANT: ErrorCode = ErrorCode(0x0000_0008);
    pub const BIT_IN_MODE: ErrorCode = ErrorCode(0x0000_0009);
    pub const FLASH: ErrorCode = ErrorCode(0x0000_0010);
    pub const NO_LOWER_LIMIT: ErrorCode = ErrorCode(0x0002_0000);
    pub const NO_UPPER_LIMIT: ErrorCode = ErrorCode(0x0003_0000);
    pub const NO_OBJECT: ErrorCode = ErrorCode(0x0004_0000);
    pub const READ_ONLY: ErrorCode = ErrorCode(0x0005_0000);

    /// Every code the manual lists.
    pub const ALL: [ErrorCode; 11] = [
        Self::TOO_LOW,
        Self::TOO_HIGH,
        Self::TOO_LOW_LIMITED,
        Self::TOO_HIGH_LIMITED,
        Self::BIT_CONSTANT,
        Self::BIT_IN_MODE,
        Self::FLASH,
        Self::NO_LOWER_LIMIT,
        Self::NO_UPPER_LIMIT,
        Self::NO_OBJECT,
        Self::READ_ONLY,
    ];

    /// The manual's text, or `None` for a code it does not list.
    pub fn meaning(self) -> Option<&'static str> {
        Some(match self {
            Self::TOO_LOW => "value too low, not written",
            Self::TOO_HIGH => "value too high, not written",
            Self::TOO_LOW_LIMITED => "value too low, written but limited",
            Self::TOO_HIGH_LIMITED => "value too high, written but limited",
            Self::BIT_CONSTANT => "bit constant not permitted",
            Self::BIT_IN_MODE => "bit value not permitted in this operating mode",
            Self::FLASH => "flash read or write error",
            Self::NO_LOWER_LIMIT => "object has no lower limit",
            Self::NO_UPPER_LIMIT => "object has no upper limit",
            Self::NO_OBJECT => "no object with this number",
            // The manual's text is cut off after "object must not"; read-only is inferred.
            Self::READ_ONLY => "object must not be written (read-only)",
            _ => return None,
        })
    }

    /// Codes 4 and 5: the write took effect with a limited value; neither success nor
    /// failure.
    pub fn is_limited(self) -> bool {
        matches!(self, Self::TOO_LOW_LIMITED | Self::TOO_HIGH_LIMITED)
    }
}

// `0x00000003 value too high, not written`.
documented_code!(ErrorCode, "0x{:08X}", "a code the manual does not list");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_has_its_text_and_only_4_and_5_are_limited() {
        for code in ErrorCode::ALL {
            assert!(code.meaning().is_some(), "{code:?}");
        }
        let limited: Vec<u32> = ErrorCode::ALL
            .into_iter()
            .filter(|c| c.is_limited())
            .map(|c| c.0)
            .collect();
        assert_eq!(limited, vec![4, 5]);
        assert_eq!(ErrorCode(3).to_string(), "0x00000003 value too high, not written");
        assert_eq!(
            ErrorCode(0x0005_0000).to_string(),
            "0x00050000 object must not be written (read-only)"
        );
        assert_eq!(
            ErrorCode(0x77).to_string(),
            "0x00000077 (a code the manual does not list)"
        );
    }
}
