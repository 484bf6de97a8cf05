//! RTU framing (Serial Line V1.02, 2.5.1): slave address, PDU, CRC-16 low byte first; at
//! most 256 bytes. A frame has no length field, so a stream is cut by the PDU's own
//! length rules; frames are told apart on the wire by a silence of 3.5 characters
//! (2.5.1.1), fixed at 1.75 ms above 19 200 bit/s.

use super::{crc16, CodecError, Request, Response};
use std::time::Duration;

/// Slave 0 is broadcast: writes only, and no slave answers it.
pub const BROADCAST: u8 = 0;
/// The highest individual slave address.
pub const MAX_SLAVE: u8 = 247;
pub const MAX_FRAME: usize = 256;

pub fn encode(slave: u8, pdu: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(pdu.len() + 3);
    out.push(slave);
    out.extend_from_slice(pdu);
    let crc = crc16(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// The slave address and the PDU of a whole frame whose CRC is right.
pub fn decode(frame: &[u8]) -> Result<(u8, &[u8]), CodecError> {
    if frame.len() < 4 || frame.len() > MAX_FRAME {
        return Err(CodecError::Length {
            what: "an RTU frame",
            len: frame.len(),
            expected: "4..=256 (address, function, CRC at least)".into(),
        });
    }
    let (body, tail) = frame.split_at(frame.len() - 2);
    let carried = u16::from_le_bytes([tail[0], tail[1]]);
    let computed = crc16(body);
    if carried != computed {
        return Err(CodecError::Crc { carried, computed });
    }
    Ok((body[0], &body[1..]))
}

/// Who sent the bytes being cut: a master sends requests, a slave replies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sender {
    Master,
    Slave,
}

/// Where the next frame in a stream ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Split {
    /// Not enough bytes yet.
    Incomplete,
    /// A frame of this many bytes (its CRC still to be checked).
    Frame(usize),
    /// This many bytes are no frame start (an unknown function code): drop them.
    Noise(usize),
}

pub fn split(buf: &[u8], sender: Sender) -> Split {
    let Some(pdu) = buf.get(1..) else {
        return Split::Incomplete;
    };
    let len = match sender {
        Sender::Master => Request::length_from(pdu),
        Sender::Slave => Response::length_from(pdu),
    };
    match len {
        None => Split::Incomplete,
        Some(Err(_)) => Split::Noise(1),
        Some(Ok(n)) if 3 + n > MAX_FRAME => Split::Noise(1),
        Some(Ok(n)) if buf.len() >= 3 + n => Split::Frame(3 + n),
        Some(Ok(_)) => Split::Incomplete,
    }
}

/// The silence that ends a frame at `baud` with `bits_per_char` bits per character
/// (start, data, parity, stops): 3.5 characters up to 19 200 bit/s, 1.75 ms above.
pub fn frame_silence(baud: u32, bits_per_char: u32) -> Duration {
    if baud > 19_200 || baud == 0 {
        Duration::from_micros(1750)
    } else {
        Duration::from_nanos(3_500_000_000 * u64::from(bits_per_char) / 1_000 / u64::from(baud) * 1_000)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_silence_is_three_and_a_half_characters_up_to_19200_and_fixed_above() {
        // 11 bits a character at 19 200 bit/s: 3.5 × 11 / 19 200 s = 2.005 ms.
        assert_eq!(frame_silence(19_200, 11), Duration::from_nanos(2_005_000));
        // 9600 bit/s: 3.5 × 11 / 9600 s = 4.010 ms.
        assert_eq!(frame_silence(9_600, 11), Duration::from_nanos(4_010_000));
        assert_eq!(frame_silence(38_400, 11), Duration::from_micros(1750));
        assert_eq!(frame_silence(115_200, 10), Duration::from_micros(1750));
    }

    #[test]
    fn a_stream_is_cut_by_the_pdu_lengths() {
        let request = encode(0x11, &[0x03, 0x00, 0x6B, 0x00, 0x03]);
        assert_eq!(split(&request[..5], Sender::Master), Split::Incomplete);
        assert_eq!(split(&request, Sender::Master), Split::Frame(8));
        let reply = encode(0x11, &[0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64]);
        assert_eq!(split(&reply, Sender::Slave), Split::Frame(11));
        assert_eq!(split(&[0x11, 0x83, 0x02, 0, 0], Sender::Slave), Split::Frame(5));
        assert_eq!(split(&[0x11, 0x42, 0, 0], Sender::Slave), Split::Noise(1));
    }
}
