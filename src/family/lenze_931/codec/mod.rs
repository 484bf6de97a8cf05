//! The Lenze 931E/K serial ASCII protocol as pure functions: request lines (object
//! commands `OW`/`OR`/`OI`/`ON`/`OX`, the identification and service commands, the
//! SDO-simulation commands), reply lines and their check against the request, the drive's
//! error codes, and CR framing that tolerates stray LF and an echo. No I/O, no clock.
//!
//! Choices the sources leave open, made here and nowhere else:
//! - Values travel as 8 hex digits, two's complement for signed types [I].
//! - The SDO-simulation data `dd..` is read as hex bytes in the order written (the
//!   sources give no length rule), at most [`MAX_SDO_BYTES`] of them.
//! - An error reply is accepted with or without the space the manual prints in the middle
//!   (`OR:FFFFFFFF` and `OR:FFFF FFFF`); hex digits in either case.

mod decode_error;
mod error_code;
mod line_extractor;
mod reply;
mod request;

pub use decode_error::DecodeError;
pub use error_code::ErrorCode;
pub use line_extractor::{Line, LineExtractor, MAX_LINE};
pub use reply::{check_reply, BootState, Reply};
pub use request::{ObjectCommand, Request, MAX_SDO_BYTES};

/// Every command and reply ends with CR.
pub const CR: u8 = 0x0D;
