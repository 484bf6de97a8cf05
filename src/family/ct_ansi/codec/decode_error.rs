//! Why bytes are not a valid ANSI x3.28 message. Every variant says what was expected,
//! what arrived (control characters by name) and where (byte offset).

use super::control::show_byte;

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    #[error("no bytes: a message is at least one control character (ACK, NAK, EOT, BS) long")]
    Empty,

    #[error("byte {offset}: expected {expected}, got {}", show_byte(*actual))]
    Unexpected {
        offset: usize,
        expected: &'static str,
        actual: u8,
    },

    #[error("truncated after {have} byte(s): expected {expected}")]
    Truncated { have: usize, expected: &'static str },

    #[error("address digits not doubled ({} {}) at byte {offset}: each digit is sent twice, e.g. drive 1.2 as `1122`", *first as char, *second as char)]
    AddressNotDoubled { offset: usize, first: u8, second: u8 },

    #[error("block check: expected 0x{expected:02x} ({}), got 0x{actual:02x} ({}) at byte {offset}", show_byte(*expected).trim_matches('\''), show_byte(*actual).trim_matches('\''))]
    BadBcc { expected: u8, actual: u8, offset: usize },

    #[error("data field of {len} characters at byte {offset}: at most 12 (sign and decimal point included)")]
    DataTooLong { len: usize, offset: usize },

    #[error("data field `{text}` at byte {offset}: {why}")]
    BadData {
        text: String,
        offset: usize,
        why: &'static str,
    },

    #[error("{extra} byte(s) after the end of the message at byte {offset}")]
    TrailingBytes { extra: usize, offset: usize },
}

impl DecodeError {
    /// A short form for `{"reject": ...}` and trace lines: the message itself.
    pub fn reason(&self) -> String {
        self.to_string()
    }
}
