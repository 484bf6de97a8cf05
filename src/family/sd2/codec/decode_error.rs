//! Why bytes are not a valid SD2 block, or why a reply does not answer its request.
//! Every variant carries what was expected, what arrived, and where (byte offset).

/// A telegram that cannot be decoded, with the reason a decoder must give.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    #[error("no bytes: an SD2 block is at least 6 bytes (zero, length, dest, source, cmd, check)")]
    Empty,

    #[error("byte 0 is 0x{actual:02x}; every SD2 block starts with 0x00")]
    BadStart { actual: u8 },

    #[error("length field 0x{actual:02x} at byte 1 is out of range (0x{min:02x}..=0x{max:02x})")]
    LengthOutOfRange { actual: u8, min: u8, max: u8 },

    #[error("truncated: needed {needed} bytes ({why}), have {have}")]
    Truncated { needed: usize, have: usize, why: String },

    #[error("{extra} byte(s) after the end of the block: the block is {expected} bytes, have {have}")]
    TrailingBytes {
        expected: usize,
        have: usize,
        extra: usize,
    },

    #[error("bad checksum at byte {offset}: expected 0x{expected:02x}, got 0x{actual:02x}")]
    BadChecksum { expected: u8, actual: u8, offset: usize },

    #[error(
        "length field 0x{actual:02x} at byte 1 disagrees with the content: {what} has length {expected}"
    )]
    LengthMismatch {
        actual: u8,
        /// The accepted value(s), written out (`0x09`, or `0x0b or 0x0c`).
        expected: String,
        what: String,
    },

    #[error("unknown command 0x{cmd:02x} at byte 4 (known: 0x0d read wide object, 0x0e write wide object, 0x10 cyclic telegram; replies with bit 7 set)")]
    UnknownCommand { cmd: u8 },

    #[error("data count {count} at byte {offset} is out of range {min}..={max}")]
    CountOutOfRange {
        count: u8,
        min: u8,
        max: u8,
        offset: usize,
    },

    #[error("reply does not answer the request: {field} expected {expected}, got {actual}")]
    ReplyMismatch {
        field: &'static str,
        expected: String,
        actual: String,
    },
}

impl DecodeError {
    /// A short form for `{"reject": ...}` and trace lines: the message itself.
    pub fn reason(&self) -> String {
        self.to_string()
    }
}

/// A telegram that cannot be put into bytes.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EncodeError {
    #[error("a write needs 1 to 48 data bytes, this one has {count}")]
    WriteCount { count: usize },
}
