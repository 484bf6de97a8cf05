//! The 32-bit error codes an object command answers with (`OW:00000004`), their meaning
//! from the manual, and which of them mean "written, but limited".

use crate::family::documented_code::{code_table, documented_code};

code_table! {
    pub struct ErrorCode(pub u32);
    TOO_LOW = 0x0000_0002 => "value too low, not written",
    TOO_HIGH = 0x0000_0003 => "value too high, not written",
    TOO_LOW_LIMITED = 0x0000_0004 => "value too low, written but limited",
    TOO_HIGH_LIMITED = 0x0000_0005 => "value too high, written but limited",
    BIT_CONSTANT = 0x0000_0008 => "bit constant not permitted",
    BIT_IN_MODE = 0x0000_0009 => "bit value not permitted in this operating mode",
    FLASH = 0x0000_0010 => "flash read or write error",
    NO_LOWER_LIMIT = 0x0002_0000 => "object has no lower limit",
    NO_UPPER_LIMIT = 0x0003_0000 => "object has no upper limit",
    NO_OBJECT = 0x0004_0000 => "no object with this number",
    // The manual's text is cut off after "object must not"; read-only is inferred.
    READ_ONLY = 0x0005_0000 => "object must not be written (read-only)",
}

impl ErrorCode {
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
