//! Cuts a byte stream into messages: where the next one ends, or which bytes are noise.
//! It only finds boundaries (control characters and lengths); [`super::Request::decode`]
//! and [`super::Reply::decode`] judge the content. Bounded: a data block is at most 19
//! bytes, so nothing waits for an ETX that never comes. Pure.

use super::control::{ACK, BS, EOT, ETX, NAK, STX};
use super::data_field::MAX_DATA_LEN;

/// Who sent the bytes (the same bytes mean different messages in each direction).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sender {
    Master,
    Drive,
}

/// What the start of a buffer holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Split {
    /// More bytes are needed.
    Incomplete,
    /// The first `n` bytes are one message (possibly malformed: decode it to know).
    Message(usize),
    /// The first `n` bytes are noise or an aborted message: drop them.
    Noise(usize),
}

/// STX, four parameter digits, the data field, ETX.
const LAST_ETX: usize = 5 + MAX_DATA_LEN;

pub fn split(buf: &[u8], sender: Sender) -> Split {
    let starts: &[u8] = match sender {
        Sender::Master => &[EOT, STX, NAK, ACK, BS],
        Sender::Drive => &[STX, ACK, NAK, EOT],
    };
    match buf.iter().position(|b| starts.contains(b)) {
        None if buf.is_empty() => return Split::Incomplete,
        None => return Split::Noise(buf.len()),
        Some(0) => {}
        Some(n) => return Split::Noise(n),
    }
    match (buf[0], sender) {
        (STX, _) => data_block(buf, 0),
        (EOT, Sender::Master) => addressed(buf),
        _ => Split::Message(1),
    }
}

/// `EOT G G U U` followed by `M M P P ENQ` or a data block.
fn addressed(buf: &[u8]) -> Split {
    for i in 1..=5 {
        match buf.get(i) {
            None => return Split::Incomplete,
            Some(&STX) if i == 5 => return data_block(buf, 5),
            // A control character aborts the message and may start the next one.
            Some(&b) if b < 0x20 => return Split::Noise(i),
            Some(_) => {}
        }
    }
    for i in 6..=9 {
        match buf.get(i) {
            None => return Split::Incomplete,
            Some(&b) if b < 0x20 && i < 9 => return Split::Noise(i),
            Some(_) => {}
        }
    }
    Split::Message(10)
}

/// A data block starting at `start` (STX): up to ETX and the check byte after it.
fn data_block(buf: &[u8], start: usize) -> Split {
    for i in start + 1..=start + LAST_ETX {
        match buf.get(i) {
            None => return Split::Incomplete,
            Some(&ETX) => {
                return if buf.len() > i + 1 {
                    Split::Message(i + 2)
                } else {
                    Split::Incomplete
                }
            }
            Some(&b) if b < 0x20 => return Split::Message(i),
            Some(_) => {}
        }
    }
    // No ETX where it must be: hand over what is there so the decoder says why.
    Split::Message(start + LAST_ETX + 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family::ct_ansi::codec::{DataValue, NodeAddress, Parameter, Reply, Request};

    #[test]
    fn messages_are_found_in_a_stream() {
        let read = Request::Read {
            address: NodeAddress::new(1, 2).unwrap(),
            parameter: Parameter::new(1, 21).unwrap(),
        }
        .encode()
        .unwrap();
        assert_eq!(split(&read, Sender::Master), Split::Message(10));
        assert_eq!(split(&read[..6], Sender::Master), Split::Incomplete);
        let reply = Reply::Value {
            parameter: Parameter::new(1, 21).unwrap(),
            value: DataValue::new(15005, 1),
        }
        .encode()
        .unwrap();
        assert_eq!(split(&reply, Sender::Drive), Split::Message(reply.len()));
        assert_eq!(split(&reply[..reply.len() - 1], Sender::Drive), Split::Incomplete);
        assert_eq!(split(&[ACK], Sender::Drive), Split::Message(1));
        assert_eq!(split(b"xy\x06", Sender::Drive), Split::Noise(2));
        assert_eq!(split(&[EOT, EOT], Sender::Master), Split::Noise(1));
        assert_eq!(split(&[], Sender::Drive), Split::Incomplete);
        // A block without ETX is handed over once it is too long to be one.
        let long = [&[STX][..], &[b'1'; 30][..]].concat();
        assert_eq!(split(&long, Sender::Drive), Split::Message(18));
    }
}
