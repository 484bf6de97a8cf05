//! The Control Techniques ANSI x3.28 codec: drive addresses (`1.2` → `1122`), parameters
//! (`#1.21` → `0121`), the decimal data field kept exact, the block check, requests and
//! replies in both directions, and a framer that cuts a byte stream into messages. Pure:
//! no I/O, no clock. Every decode error says what was expected, what arrived and where.
//!
//! `x328-proto` (Rust, sans-I/O) frames the same messages, but its values are integers
//! only (no decimal point, at most 6 characters), so it cannot read a Unidrive SP reply
//! such as `+1500.5`; this codec is written for the decimal data field instead.

mod bcc;
mod control;
mod data_field;
mod decode_error;
mod framer;
mod message;
mod node_address;
mod parameter;

pub use bcc::bcc;
pub use control::{control_name, show_byte, show_bytes, ACK, BS, ENQ, EOT, ETX, NAK, STX};
pub use data_field::{DataValue, MAX_DATA_LEN};
pub use decode_error::DecodeError;
pub use framer::{split, Sender, Split};
pub use message::{Reply, Request};
pub use node_address::NodeAddress;
pub use parameter::Parameter;

#[cfg(test)]
mod proptests;
