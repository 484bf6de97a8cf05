//! CANopen (CiA 301) on the wire, pure: the SDO frames both ways, the abort codes, the
//! client state machine of one transfer, NMT commands, heartbeats and EMCY frames. No I/O, no clock, no vendor's notation.

mod abort_code;
mod emcy;
mod nmt;
mod sdo_client;
mod sdo_frame;

pub use abort_code::AbortCode;
pub use emcy::{emcy_id, error_code_text, Emcy};
pub use nmt::{heartbeat_id, NmtCommand, NmtState, NMT_ID};
pub use sdo_client::{SdoClient, SdoStep, Uploaded, MAX_TRANSFER};
pub use sdo_frame::{SdoDecodeError, SdoRequest, SdoResponse, Segment, SDO_LEN};

/// The identifier of SDO requests to `node`: 0x600 + node.
pub fn request_id(node: u8) -> u32 {
    0x600 + u32::from(node)
}

/// The identifier of SDO responses from `node`: 0x580 + node.
pub fn response_id(node: u8) -> u32 {
    0x580 + u32::from(node)
}
