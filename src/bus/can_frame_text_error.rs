//! Why a CAN frame written as text (`60C#409C…`, a candump log line, `60C 40 9C …`) is not
//! one: what is wrong and where, in the words the user wrote. Plain data.

use crate::hex::HexError;

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CanFrameTextError {
    #[error("`{line}`: a candump log line is `(TIME) INTERFACE ID#DATA`")]
    LogLine { line: String },
    #[error("`{frame}`: remote and CAN FD frames carry no SDO data; give a data frame `ID#DATA`")]
    NoData { frame: String },
    #[error("`{id}` is not a CAN identifier: write 3 hex digits (11-bit, e.g. 60C) or 8 (29-bit), then `#` and the data")]
    Identifier { id: String },
    #[error("`{id}`: {source}")]
    IdentifierValue {
        id: String,
        source: std::num::ParseIntError,
    },
    #[error("the data `{data}`: {source}")]
    Data { data: String, source: HexError },
    #[error("a CAN frame carries at most 8 data bytes, got {0}")]
    TooLong(usize),
    #[error("identifier 0x{0:X} does not fit 11 bits; write 8 hex digits for an extended frame")]
    Not11Bits(u32),
}
