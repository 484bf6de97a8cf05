//! The MBAP header of Modbus TCP (TCP/IP Implementation Guide V1.0b, 3.1.3): transaction
//! id (2 bytes), protocol id 0 (2), the length of what follows (2: unit id and PDU), unit
//! id (1), then the PDU; no CRC.

use super::CodecError;

pub const HEADER: usize = 7;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame<'a> {
    pub transaction: u16,
    pub unit: u8,
    pub pdu: &'a [u8],
}

pub fn encode(transaction: u16, unit: u8, pdu: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER + pdu.len());
    out.extend_from_slice(&transaction.to_be_bytes());
    out.extend_from_slice(&[0, 0]);
    out.extend_from_slice(&((pdu.len() + 1) as u16).to_be_bytes());
    out.push(unit);
    out.extend_from_slice(pdu);
    out
}

/// The whole frame's length from its first six bytes; `None` until they have come.
pub fn frame_len(prefix: &[u8]) -> Option<usize> {
    let field = prefix.get(4..6)?;
    Some(6 + usize::from(u16::from_be_bytes([field[0], field[1]])))
}

pub fn decode(frame: &[u8]) -> Result<Frame<'_>, CodecError> {
    if frame.len() < HEADER + 1 {
        return Err(CodecError::Length {
            what: "an MBAP frame",
            len: frame.len(),
            expected: "at least 8 (header and function)".into(),
        });
    }
    let protocol = u16::from_be_bytes([frame[2], frame[3]]);
    if protocol != 0 {
        return Err(CodecError::Protocol(protocol));
    }
    let field = usize::from(u16::from_be_bytes([frame[4], frame[5]]));
    if field != frame.len() - 6 {
        return Err(CodecError::MbapLength {
            field,
            actual: frame.len() - 6,
        });
    }
    Ok(Frame {
        transaction: u16::from_be_bytes([frame[0], frame[1]]),
        unit: frame[6],
        pdu: &frame[HEADER..],
    })
}
