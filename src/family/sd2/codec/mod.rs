//! The SD2 DNC codec: blocks of object access (Read/Write Wide Object) and the DNC 8-byte
//! cyclic telegram with its acyclic service channel, as typed values and exact bytes.
//! Facts and quirks: `shared/protocols/sd2-dnc.md`. Pure: no I/O, no time.

mod checksum;
mod cyclic;
mod data;
mod decode_error;
mod error_code;
mod frame_extractor;
mod json;
mod reply_check;
mod telegram;
mod write_length;

pub use checksum::checksum;
pub use cyclic::{Cyclic, ServiceChannel, ServiceFunction, SPEED_FULL_SCALE};
pub use data::Data;
pub use decode_error::{DecodeError, EncodeError};
pub use error_code::ErrorCode;
pub use frame_extractor::{Extracted, FrameExtractor, Framing};
pub use json::to_json;
pub use reply_check::check_reply;
pub use telegram::{Body, Telegram};
pub use write_length::WriteLength;

/// Command numbers; a reply carries the command with bit 7 set.
pub const CMD_READ_WIDE: u8 = 0x0D;
pub const CMD_WRITE_WIDE: u8 = 0x0E;
pub const CMD_CYCLIC: u8 = 0x10;
pub const REPLY_BIT: u8 = 0x80;

/// The PC's (master's) DNC address.
pub const MASTER_ADDRESS: u8 = 1;
/// Most user-data bytes one block carries.
pub const MAX_DATA: usize = 48;
/// Largest length field any block can carry: a write of 48 bytes under the manual's formula.
pub const MAX_LENGTH_FIELD: u8 = 10 + MAX_DATA as u8;
/// Smallest length field: dest, source, cmd.
pub const MIN_LENGTH_FIELD: u8 = 3;

/// DNC address of drive A (`drive_b` false) or B on a device whose address switch is at
/// `switch`: A = switch × 2 + 2, B = switch × 2 + 3. `None` when the result exceeds a byte.
pub fn dnc_address(switch: u8, drive_b: bool) -> Option<u8> {
    let a = u16::from(switch) * 2 + 2 + u16::from(drive_b);
    u8::try_from(a).ok()
}

/// The address switch and drive letter behind a DNC address; `None` for the master's 0 and 1.
pub fn switch_of(address: u8) -> Option<(u8, char)> {
    if address < 2 {
        return None;
    }
    let rel = address - 2;
    Some((rel / 2, if rel.is_multiple_of(2) { 'A' } else { 'B' }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_follow_the_switch() {
        assert_eq!(dnc_address(0, false), Some(2));
        assert_eq!(dnc_address(0, true), Some(3));
        assert_eq!(dnc_address(5, false), Some(12));
        assert_eq!(dnc_address(126, true), Some(255));
        assert_eq!(dnc_address(127, true), None);
        assert_eq!(dnc_address(200, false), None);
        assert_eq!(switch_of(12), Some((5, 'A')));
        assert_eq!(switch_of(3), Some((0, 'B')));
        assert_eq!(switch_of(1), None);
    }
}
