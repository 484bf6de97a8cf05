//! One SD2 block as a typed value, and the exact bytes for it, both ways. Pure.

use super::{
    checksum, Cyclic, Data, DecodeError, EncodeError, ErrorCode, ServiceChannel, WriteLength, CMD_CYCLIC,
    CMD_READ_WIDE, CMD_WRITE_WIDE, MAX_DATA, MAX_LENGTH_FIELD, MIN_LENGTH_FIELD, REPLY_BIT,
};

/// A decoded block: addresses plus what it says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Telegram {
    pub dest: u8,
    pub source: u8,
    pub body: Body,
}

/// What a block says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Body {
    ReadRequest { index: u16, subindex: u32 },
    ReadReply { error: ErrorCode, data: Data },
    WriteRequest { index: u16, subindex: u32, data: Data },
    WriteReply { error: ErrorCode },
    CyclicRequest(Cyclic),
    CyclicReply(Cyclic),
}

/// Layout sizes: zero, len, dest, source, cmd = 5 header bytes; 1 check byte.
const HEADER: usize = 5;
const READ_REQUEST_LEN: u8 = 9;
const WRITE_REPLY_LEN: u8 = 4;
const CYCLIC_LEN: u8 = 0x0D;
const CYCLIC_SERVICE_LEN: u8 = 0x15;
/// Offset of the count byte in a Write Wide Object command.
const WRITE_COUNT_OFFSET: usize = 11;

/// Bytes appended with their running sum for the check byte: the sum is taken from the
/// values being written, not read back from the buffer just written byte by byte (a read
/// that waits for those writes to land, in each of a long run's millions of telegrams).
struct Summed<'a> {
    out: &'a mut Vec<u8>,
    sum: u8,
}

impl Summed<'_> {
    fn put(&mut self, bytes: &[u8]) {
        self.sum = bytes.iter().fold(self.sum, |sum, b| sum.wrapping_add(*b));
        self.out.extend_from_slice(bytes);
    }
}

impl Telegram {
    pub fn read_request(dest: u8, source: u8, index: u16, subindex: u32) -> Telegram {
        Telegram {
            dest,
            source,
            body: Body::ReadRequest { index, subindex },
        }
    }

    /// A write of 1..=48 bytes.
    pub fn write_request(
        dest: u8,
        source: u8,
        index: u16,
        subindex: u32,
        data: &[u8],
    ) -> Result<Telegram, EncodeError> {
        match Data::new(data) {
            Some(d) if !d.is_empty() => Ok(Telegram {
                dest,
                source,
                body: Body::WriteRequest {
                    index,
                    subindex,
                    data: d,
                },
            }),
            _ => Err(EncodeError::WriteCount { count: data.len() }),
        }
    }

    /// The command byte: request number, or with bit 7 set for replies.
    pub fn command(&self) -> u8 {
        match self.body {
            Body::ReadRequest { .. } => CMD_READ_WIDE,
            Body::ReadReply { .. } => CMD_READ_WIDE | REPLY_BIT,
            Body::WriteRequest { .. } => CMD_WRITE_WIDE,
            Body::WriteReply { .. } => CMD_WRITE_WIDE | REPLY_BIT,
            Body::CyclicRequest(_) => CMD_CYCLIC,
            Body::CyclicReply(_) => CMD_CYCLIC | REPLY_BIT,
        }
    }

    pub fn is_reply(&self) -> bool {
        self.command() & REPLY_BIT != 0
    }

    /// The object index a request addresses, where it has one.
    pub fn index(&self) -> Option<u16> {
        match self.body {
            Body::ReadRequest { index, .. } | Body::WriteRequest { index, .. } => Some(index),
            Body::CyclicRequest(c) | Body::CyclicReply(c) => c.service.map(|s| s.index),
            _ => None,
        }
    }

    /// The bytes of this telegram. Write commands get the length field `write_length` asks for.
    pub fn encode(&self, write_length: WriteLength) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEADER + 14);
        self.encode_into(&mut out, write_length);
        out
    }

    /// Appends the bytes of this telegram to `out`.
    pub fn encode_into(&self, out: &mut Vec<u8>, write_length: WriteLength) {
        let start = out.len();
        out.extend_from_slice(&[0x00, 0x00]);
        let mut w = Summed { out, sum: 0 };
        w.put(&[self.dest, self.source, self.command()]);
        match &self.body {
            Body::ReadRequest { index, subindex } => {
                w.put(&index.to_le_bytes());
                w.put(&subindex.to_le_bytes());
            }
            Body::ReadReply { error, data } => {
                w.put(&[data.len() as u8, error.0]);
                w.put(data.as_slice());
            }
            Body::WriteRequest {
                index,
                subindex,
                data,
            } => {
                w.put(&index.to_le_bytes());
                w.put(&subindex.to_le_bytes());
                w.put(&[data.len() as u8]);
                w.put(data.as_slice());
            }
            Body::WriteReply { error } => w.put(&[error.0]),
            Body::CyclicRequest(c) | Body::CyclicReply(c) => {
                w.put(&c.header);
                w.put(&c.pdo);
                if let Some(s) = &c.service {
                    w.put(&[s.reserved, s.ctrl]);
                    w.put(&s.index.to_le_bytes());
                    w.put(&s.data);
                }
            }
        }
        let sum = w.sum;
        let length = match &self.body {
            Body::WriteRequest { data, .. } => write_length.field(data.len()),
            // Bytes after the length field up to the check byte: dest..data.
            _ => (out.len() - start - 2) as u8,
        };
        out[start + 1] = length;
        // The check byte of the length field and what follows (see [`checksum`]).
        out.push(0xFF - sum.wrapping_add(length));
    }

    /// Decodes exactly one complete block. Write commands are framed by their count byte,
    /// so both length-field forms decode (see [`WriteLength`]).
    pub fn decode(bytes: &[u8]) -> Result<Telegram, DecodeError> {
        let total = match frame_length(bytes)? {
            Some(total) => total,
            None => {
                return Err(DecodeError::Truncated {
                    needed: minimum_needed(bytes),
                    have: bytes.len(),
                    why: "the header is incomplete".into(),
                })
            }
        };
        if bytes.len() < total {
            return Err(DecodeError::Truncated {
                needed: total,
                have: bytes.len(),
                why: length_reason(bytes),
            });
        }
        if bytes.len() > total {
            return Err(DecodeError::TrailingBytes {
                expected: total,
                have: bytes.len(),
                extra: bytes.len() - total,
            });
        }
        decode_frame(bytes)
    }
}

/// How many bytes the block starting at `bytes[0]` has, or `None` when more bytes are
/// needed to tell. Errors for a prefix that can never start a valid block.
pub(super) fn frame_length(bytes: &[u8]) -> Result<Option<usize>, DecodeError> {
    let Some(&first) = bytes.first() else {
        return Err(DecodeError::Empty);
    };
    if first != 0 {
        return Err(DecodeError::BadStart { actual: first });
    }
    let Some(&len) = bytes.get(1) else {
        return Ok(None);
    };
    if !(MIN_LENGTH_FIELD..=MAX_LENGTH_FIELD).contains(&len) {
        return Err(DecodeError::LengthOutOfRange {
            actual: len,
            min: MIN_LENGTH_FIELD,
            max: MAX_LENGTH_FIELD,
        });
    }
    let Some(&cmd) = bytes.get(4) else {
        return Ok(None);
    };
    if cmd != CMD_WRITE_WIDE {
        return Ok(Some(usize::from(len) + 3));
    }
    let Some(&count) = bytes.get(WRITE_COUNT_OFFSET) else {
        return Ok(None);
    };
    if count == 0 || usize::from(count) > MAX_DATA {
        return Err(DecodeError::CountOutOfRange {
            count,
            min: 1,
            max: MAX_DATA as u8,
            offset: WRITE_COUNT_OFFSET,
        });
    }
    Ok(Some(WRITE_COUNT_OFFSET + 1 + usize::from(count) + 1))
}

fn minimum_needed(bytes: &[u8]) -> usize {
    match bytes.get(4) {
        Some(&CMD_WRITE_WIDE) => WRITE_COUNT_OFFSET + 1,
        _ if bytes.len() < 2 => 2,
        _ => HEADER,
    }
}

fn length_reason(bytes: &[u8]) -> String {
    match (bytes.get(1), bytes.get(4)) {
        (_, Some(&CMD_WRITE_WIDE)) => format!(
            "write command with count {}",
            bytes.get(WRITE_COUNT_OFFSET).copied().unwrap_or(0)
        ),
        (Some(len), _) => format!("length field 0x{len:02x}"),
        _ => "header".into(),
    }
}

/// Decodes a block whose extent is already known to be exactly `bytes`.
fn decode_frame(bytes: &[u8]) -> Result<Telegram, DecodeError> {
    let last = bytes.len() - 1;
    let expected = checksum(&bytes[1..last]);
    if bytes[last] != expected {
        return Err(DecodeError::BadChecksum {
            expected,
            actual: bytes[last],
            offset: last,
        });
    }
    let len = bytes[1];
    let (dest, source, cmd) = (bytes[2], bytes[3], bytes[4]);
    let payload = &bytes[HEADER..last];
    // `what` is only written out for a mismatch: this runs for every telegram of a run.
    let need_len = |expected: u8, what: &dyn Fn() -> String| -> Result<(), DecodeError> {
        if len == expected {
            Ok(())
        } else {
            Err(DecodeError::LengthMismatch {
                actual: len,
                expected: format!("0x{expected:02x}"),
                what: what(),
            })
        }
    };
    let body = match cmd {
        CMD_READ_WIDE => {
            need_len(READ_REQUEST_LEN, &|| "a read request".into())?;
            Body::ReadRequest {
                index: u16::from_le_bytes([payload[0], payload[1]]),
                subindex: u32::from_le_bytes([payload[2], payload[3], payload[4], payload[5]]),
            }
        }
        c if c == CMD_READ_WIDE | REPLY_BIT => {
            let Some(&count) = payload.first() else {
                return Err(DecodeError::LengthMismatch {
                    actual: len,
                    expected: "0x05 or more".into(),
                    what: "a read reply".into(),
                });
            };
            if usize::from(count) > MAX_DATA {
                return Err(DecodeError::CountOutOfRange {
                    count,
                    min: 0,
                    max: MAX_DATA as u8,
                    offset: HEADER,
                });
            }
            need_len(5 + count, &|| format!("a read reply with {count} data bytes"))?;
            Body::ReadReply {
                error: ErrorCode(payload[1]),
                data: Data::new(&payload[2..]).unwrap_or_default(),
            }
        }
        CMD_WRITE_WIDE => {
            let count = payload[6];
            let formula = 10 + count;
            if len != WriteLength::Captured.field(usize::from(count)) && len != formula {
                return Err(DecodeError::LengthMismatch {
                    actual: len,
                    expected: format!("0x0b (as captured) or 0x{formula:02x} (manual formula)"),
                    what: format!("a write command with {count} data bytes"),
                });
            }
            Body::WriteRequest {
                index: u16::from_le_bytes([payload[0], payload[1]]),
                subindex: u32::from_le_bytes([payload[2], payload[3], payload[4], payload[5]]),
                data: Data::new(&payload[7..]).unwrap_or_default(),
            }
        }
        c if c == CMD_WRITE_WIDE | REPLY_BIT => {
            need_len(WRITE_REPLY_LEN, &|| "a write reply".into())?;
            Body::WriteReply {
                error: ErrorCode(payload[0]),
            }
        }
        c if c & !REPLY_BIT == CMD_CYCLIC => {
            let cyclic = decode_cyclic(len, payload)?;
            if c & REPLY_BIT != 0 {
                Body::CyclicReply(cyclic)
            } else {
                Body::CyclicRequest(cyclic)
            }
        }
        other => return Err(DecodeError::UnknownCommand { cmd: other }),
    };
    Ok(Telegram { dest, source, body })
}

fn decode_cyclic(len: u8, p: &[u8]) -> Result<Cyclic, DecodeError> {
    if len != CYCLIC_LEN && len != CYCLIC_SERVICE_LEN {
        return Err(DecodeError::LengthMismatch {
            actual: len,
            expected: "0x0d (without) or 0x15 (with the service channel)".into(),
            what: "a cyclic telegram".into(),
        });
    }
    let mut pdo = [0u8; 8];
    pdo.copy_from_slice(&p[2..10]);
    let service = (len == CYCLIC_SERVICE_LEN).then(|| ServiceChannel {
        reserved: p[10],
        ctrl: p[11],
        index: u16::from_le_bytes([p[12], p[13]]),
        data: [p[14], p[15], p[16], p[17]],
    });
    Ok(Cyclic {
        header: [p[0], p[1]],
        pdo,
        service,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hex::parse_hex;
    use proptest::prelude::*;

    fn dec(hex: &str) -> Result<Telegram, DecodeError> {
        Telegram::decode(&parse_hex(hex).unwrap())
    }

    #[test]
    fn write_is_framed_by_count_and_accepts_both_length_forms() {
        let t = Telegram::write_request(2, 1, 395, 0, &1_000_000i32.to_le_bytes()).unwrap();
        let captured = t.encode(WriteLength::Captured);
        let formula = t.encode(WriteLength::Formula);
        assert_eq!(captured[1], 0x0B);
        assert_eq!(formula[1], 0x0E);
        assert_eq!(captured.len(), formula.len());
        assert_eq!(Telegram::decode(&captured).unwrap(), t);
        assert_eq!(Telegram::decode(&formula).unwrap(), t);
    }

    #[test]
    fn empty_and_bad_start() {
        assert_eq!(Telegram::decode(&[]), Err(DecodeError::Empty));
        assert_eq!(dec("01 09"), Err(DecodeError::BadStart { actual: 1 }));
    }

    #[test]
    fn truncated_says_how_many_bytes() {
        let e = dec("00 09 01 02 8d 02 00 37 66 84").unwrap_err();
        assert!(
            matches!(
                e,
                DecodeError::Truncated {
                    needed: 12,
                    have: 10,
                    ..
                }
            ),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            "truncated: needed 12 bytes (length field 0x09), have 10"
        );
        assert!(matches!(
            dec("00"),
            Err(DecodeError::Truncated {
                needed: 2,
                have: 1,
                ..
            })
        ));
        assert!(matches!(
            dec("00 0b 02 01 0e 44"),
            Err(DecodeError::Truncated { needed: 12, .. })
        ));
    }

    #[test]
    fn trailing_bytes_are_refused() {
        let e = dec("00 04 01 02 8e 00 6a ff").unwrap_err();
        assert_eq!(
            e,
            DecodeError::TrailingBytes {
                expected: 7,
                have: 8,
                extra: 1
            }
        );
    }

    #[test]
    fn bad_checksum_gives_expected_and_actual() {
        let e = dec("00 0d 02 01 10 05 00 07 00 ff 1f 00 00 00 00 05").unwrap_err();
        assert_eq!(
            e,
            DecodeError::BadChecksum {
                expected: 0xb5,
                actual: 0x05,
                offset: 15
            }
        );
        assert_eq!(e.to_string(), "bad checksum at byte 15: expected 0xb5, got 0x05");
    }

    #[test]
    fn length_field_out_of_range() {
        assert!(matches!(
            dec("00 02 01 02 8e"),
            Err(DecodeError::LengthOutOfRange { actual: 2, .. })
        ));
        assert!(matches!(
            dec("00 ff"),
            Err(DecodeError::LengthOutOfRange { actual: 0xff, .. })
        ));
    }

    fn with_check(mut bytes: Vec<u8>) -> Vec<u8> {
        let c = checksum(&bytes[1..]);
        bytes.push(c);
        bytes
    }

    #[test]
    fn length_mismatch_names_the_content() {
        // A read reply saying 2 data bytes inside a block of 4.
        let b = with_check(vec![0, 9, 1, 2, 0x8d, 2, 0, 1, 2, 3, 4]);
        let e = Telegram::decode(&b).unwrap_err();
        assert!(
            matches!(e, DecodeError::LengthMismatch { actual: 9, .. }),
            "{e:?}"
        );
        assert!(e
            .to_string()
            .contains("a read reply with 2 data bytes has length 0x07"));
        // A write with length neither 0x0b nor 10+count.
        let b = with_check(vec![0, 0x10, 2, 1, 0x0e, 0x44, 0, 0, 0, 0, 0, 2, 6, 0]);
        let e = Telegram::decode(&b).unwrap_err();
        assert!(
            e.to_string()
                .contains("0x0b (as captured) or 0x0c (manual formula)"),
            "{e}"
        );
        // Sizes that do not fit the command.
        for bytes in [
            // A read request of the wrong size.
            vec![0, 7, 2, 1, 0x0d, 0x44, 0, 0, 0],
            // Cyclic telegram of an unknown size.
            vec![0, 5, 2, 1, 0x10, 1, 0],
            // Read reply with no count byte at all.
            vec![0, 3, 1, 2, 0x8d],
            // Write reply of the wrong size.
            vec![0, 5, 1, 2, 0x8e, 0, 0],
        ] {
            let b = with_check(bytes);
            let decoded = Telegram::decode(&b);
            assert!(
                matches!(decoded, Err(DecodeError::LengthMismatch { .. })),
                "{b:02x?}"
            );
        }
    }

    #[test]
    fn unknown_command() {
        let b = with_check(vec![0, 4, 2, 1, 0x22, 0]);
        assert_eq!(
            Telegram::decode(&b),
            Err(DecodeError::UnknownCommand { cmd: 0x22 })
        );
    }

    #[test]
    fn count_out_of_range() {
        let b = with_check(vec![0, 0x0b, 2, 1, 0x0e, 0x44, 0, 0, 0, 0, 0, 0]);
        assert!(matches!(
            Telegram::decode(&b),
            Err(DecodeError::CountOutOfRange {
                count: 0,
                offset: 11,
                ..
            })
        ));
        let b = with_check(vec![0, 0x0b, 2, 1, 0x0e, 0x44, 0, 0, 0, 0, 0, 49]);
        assert!(matches!(
            Telegram::decode(&b),
            Err(DecodeError::CountOutOfRange { count: 49, .. })
        ));
        let mut reply = vec![0, 5 + 49, 1, 2, 0x8d, 49, 0];
        reply.extend([0u8; 49]);
        // Length 54 is within range; the count is not.
        let b = with_check(reply);
        assert!(matches!(
            Telegram::decode(&b),
            Err(DecodeError::CountOutOfRange {
                count: 49,
                offset: 5,
                ..
            })
        ));
        assert!(Telegram::write_request(2, 1, 1, 0, &[]).is_err());
        assert!(Telegram::write_request(2, 1, 1, 0, &[0; 49]).is_err());
    }

    fn arb_data(min: usize) -> impl Strategy<Value = Data> {
        proptest::collection::vec(any::<u8>(), min..=MAX_DATA).prop_map(|v| Data::new(&v).unwrap_or_default())
    }

    fn arb_cyclic() -> impl Strategy<Value = Cyclic> {
        (
            any::<[u8; 2]>(),
            any::<[u8; 8]>(),
            proptest::option::of((any::<u8>(), any::<u8>(), any::<u16>(), any::<[u8; 4]>())),
        )
            .prop_map(|(header, pdo, s)| Cyclic {
                header,
                pdo,
                service: s.map(|(reserved, ctrl, index, data)| ServiceChannel {
                    reserved,
                    ctrl,
                    index,
                    data,
                }),
            })
    }

    fn arb_telegram() -> impl Strategy<Value = Telegram> {
        let body = prop_oneof![
            (any::<u16>(), any::<u32>()).prop_map(|(index, subindex)| Body::ReadRequest { index, subindex }),
            (any::<u8>(), arb_data(0)).prop_map(|(e, data)| Body::ReadReply {
                error: ErrorCode(e),
                data
            }),
            (any::<u16>(), any::<u32>(), arb_data(1)).prop_map(|(index, subindex, data)| {
                Body::WriteRequest {
                    index,
                    subindex,
                    data,
                }
            }),
            any::<u8>().prop_map(|e| Body::WriteReply { error: ErrorCode(e) }),
            arb_cyclic().prop_map(Body::CyclicRequest),
            arb_cyclic().prop_map(Body::CyclicReply),
        ];
        (any::<u8>(), any::<u8>(), body).prop_map(|(dest, source, body)| Telegram { dest, source, body })
    }

    proptest! {
        #[test]
        fn round_trip(t in arb_telegram(), formula in any::<bool>()) {
            let wl = if formula { WriteLength::Formula } else { WriteLength::Captured };
            let bytes = t.encode(wl);
            prop_assert_eq!(Telegram::decode(&bytes), Ok(t));
        }

        #[test]
        fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..80)) {
            let _ = Telegram::decode(&bytes);
        }

        #[test]
        fn plausible_headers_never_panic(len in 0u8..70, cmd in prop_oneof![Just(0x0du8), Just(0x8d), Just(0x0e), Just(0x8e), Just(0x10), Just(0x90), any::<u8>()],
                                         rest in proptest::collection::vec(any::<u8>(), 0..70)) {
            let mut b = vec![0, len, 2, 1, cmd];
            b.extend(rest);
            let _ = Telegram::decode(&b);
        }

        #[test]
        fn a_flipped_bit_is_never_silently_accepted(t in arb_telegram(), pos in any::<prop::sample::Index>(), bit in 0u8..8) {
            let mut bytes = t.encode(WriteLength::Captured);
            let i = pos.index(bytes.len());
            bytes[i] ^= 1 << bit;
            // A single flipped bit always changes the checksum or the framing; it must never
            // decode to a different telegram without an error.
            if let Ok(other) = Telegram::decode(&bytes) {
                prop_assert_eq!(other, t);
            }
        }
    }
}
