//! Cuts a byte stream that arrives in pieces into SD2 blocks. Leading garbage is skipped;
//! a block is complete only when its length (or, for write commands, its count) says so.
//! Pure buffering: the caller feeds bytes and asks for blocks; no I/O, no time.

use super::telegram::frame_length;
use super::{DecodeError, Telegram, CMD_WRITE_WIDE};

/// Which blocks the stream carries, which decides how they are framed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Framing {
    /// Drive → PC: every block is framed by its length field.
    Replies,
    /// PC → drive (the simulator's side): write commands are framed by their count,
    /// because real masters send length 0x0B whatever the count.
    Requests,
}

/// One block cut from the stream; its bytes stay in the extractor's buffer until the next
/// call (a long run cuts millions of blocks).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Extracted<'a> {
    /// Bytes dropped before this block because no block could start there.
    pub skipped: usize,
    /// The block's bytes as received.
    pub bytes: &'a [u8],
    /// The decoded telegram, or why these bytes are not one (checksum, length, command).
    pub telegram: Result<Telegram, DecodeError>,
}

/// Bounded buffer of bytes not yet cut into blocks.
#[derive(Debug)]
pub struct FrameExtractor {
    framing: Framing,
    buf: Vec<u8>,
    skipped: usize,
    /// Bytes at the front of `buf` already handed out (the last block, or the first byte
    /// of a corrupt one): dropped before anything else is done.
    taken: usize,
}

/// A reasonable stream never holds more than a few blocks; beyond this, the oldest bytes are
/// garbage that will never frame and are dropped so memory stays bounded on a noisy line.
const MAX_BUFFER: usize = 4096;

impl FrameExtractor {
    pub fn new(framing: Framing) -> Self {
        FrameExtractor {
            framing,
            buf: Vec::with_capacity(128),
            skipped: 0,
            taken: 0,
        }
    }

    pub fn push(&mut self, bytes: &[u8]) {
        self.drop_taken();
        self.buf.extend_from_slice(bytes);
        if self.buf.len() > MAX_BUFFER {
            let drop = self.buf.len() - MAX_BUFFER;
            self.buf.drain(..drop);
            self.skipped += drop;
        }
    }

    /// Bytes buffered but not yet part of a complete block.
    pub fn pending(&self) -> &[u8] {
        &self.buf[self.taken..]
    }

    /// Forgets everything buffered (after the link discards input).
    pub fn clear(&mut self) {
        self.buf.clear();
        self.skipped = 0;
        self.taken = 0;
    }

    fn drop_taken(&mut self) {
        if self.taken > 0 {
            self.buf.drain(..self.taken);
            self.taken = 0;
        }
    }

    /// The next complete block, or `None` until more bytes arrive. A candidate whose check
    /// byte is wrong is returned as an error and only its first byte is dropped, so a real
    /// block hidden behind a stray 0x00 is still found on the next call.
    pub fn next_block(&mut self) -> Option<Extracted<'_>> {
        self.drop_taken();
        loop {
            let start = self.buf.iter().position(|&b| b == 0)?;
            self.drop_front(start);
            let length = if self.framing == Framing::Replies && self.buf.get(4) == Some(&CMD_WRITE_WIDE) {
                // A write command never comes from a drive; frame it by the length field
                // as any other block so the checksum decides.
                frame_length_by_field(&self.buf)
            } else {
                frame_length(&self.buf)
            };
            match length {
                Ok(None) => return None,
                Err(_) => {
                    self.drop_front(1);
                    continue;
                }
                Ok(Some(total)) if self.buf.len() < total => return None,
                Ok(Some(total)) => {
                    let bytes = &self.buf[..total];
                    let telegram = Telegram::decode(bytes);
                    let skipped = std::mem::take(&mut self.skipped);
                    if telegram.is_ok() {
                        self.taken = total;
                    } else {
                        self.taken = 1;
                        self.skipped = 1;
                    }
                    return Some(Extracted {
                        skipped,
                        bytes,
                        telegram,
                    });
                }
            }
        }
    }

    fn drop_front(&mut self, n: usize) {
        self.buf.drain(..n);
        self.skipped += n;
    }
}

fn frame_length_by_field(buf: &[u8]) -> Result<Option<usize>, DecodeError> {
    match buf.get(1) {
        None => Ok(None),
        Some(&len) if (super::MIN_LENGTH_FIELD..=super::MAX_LENGTH_FIELD).contains(&len) => {
            Ok(Some(usize::from(len) + 3))
        }
        Some(&len) => Err(DecodeError::LengthOutOfRange {
            actual: len,
            min: super::MIN_LENGTH_FIELD,
            max: super::MAX_LENGTH_FIELD,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family::sd2::codec::{Body, WriteLength};
    use crate::hex::parse_hex;
    use proptest::prelude::*;

    const READ_REPLY: &str = "00 09 01 02 8d 04 00 7f 50 0f 00 84";
    const WRITE_REPLY: &str = "00 04 01 02 8e 00 6a";

    #[test]
    fn block_arriving_byte_by_byte() {
        let bytes = parse_hex(READ_REPLY).unwrap();
        let mut x = FrameExtractor::new(Framing::Replies);
        for (i, b) in bytes.iter().enumerate() {
            x.push(&[*b]);
            let got = x.next_block();
            if i + 1 < bytes.len() {
                assert!(got.is_none(), "complete after {} of {} bytes", i + 1, bytes.len());
            } else {
                let got = got.unwrap();
                assert_eq!(got.skipped, 0);
                assert!(matches!(got.telegram.unwrap().body, Body::ReadReply { .. }));
            }
        }
        assert!(x.pending().is_empty());
    }

    #[test]
    fn leading_garbage_is_skipped() {
        let mut x = FrameExtractor::new(Framing::Replies);
        x.push(&[0xff, 0x13, 0x00, 0xee]); // 0x00 0xee: length out of range, not a start
        x.push(&parse_hex(WRITE_REPLY).unwrap());
        let got = x.next_block().unwrap();
        assert_eq!(got.skipped, 4);
        assert!(got.telegram.is_ok());
        assert!(x.next_block().is_none());
    }

    #[test]
    fn two_blocks_in_one_piece() {
        let mut x = FrameExtractor::new(Framing::Replies);
        let mut bytes = parse_hex(WRITE_REPLY).unwrap();
        bytes.extend(parse_hex(READ_REPLY).unwrap());
        x.push(&bytes);
        assert!(x.next_block().unwrap().telegram.is_ok());
        assert!(x.next_block().unwrap().telegram.is_ok());
        assert!(x.next_block().is_none());
    }

    #[test]
    fn corrupt_block_is_reported_then_resynchronised() {
        let mut x = FrameExtractor::new(Framing::Replies);
        let mut bad = parse_hex(WRITE_REPLY).unwrap();
        bad[6] ^= 0xff;
        x.push(&bad);
        x.push(&parse_hex(READ_REPLY).unwrap());
        let first = x.next_block().unwrap();
        assert!(matches!(first.telegram, Err(DecodeError::BadChecksum { .. })));
        let second = x.next_block().unwrap();
        assert!(second.telegram.is_ok(), "{second:?}");
        assert!(second.skipped > 0);
    }

    #[test]
    fn requests_frame_writes_by_count() {
        // Length 0x0b with 4 data bytes: 17 bytes, not 14.
        let write = parse_hex("00 0b 02 01 0e 8b 01 00 00 00 00 04 80 8d 5b 00 eb").unwrap();
        let mut x = FrameExtractor::new(Framing::Requests);
        x.push(&write[..14]);
        assert!(x.next_block().is_none());
        x.push(&write[14..]);
        let got = x.next_block().unwrap();
        assert_eq!(got.bytes, write);
        assert!(got.telegram.is_ok());
    }

    #[test]
    fn buffer_stays_bounded() {
        let mut x = FrameExtractor::new(Framing::Replies);
        for _ in 0..100 {
            x.push(&[0x00, 0x3a]); // plausible length, never completes
            x.push(&[0x55; 100]);
        }
        assert!(x.pending().len() <= MAX_BUFFER);
    }

    proptest! {
        #[test]
        fn any_split_yields_the_same_blocks(cut in 0usize..19) {
            let mut bytes = parse_hex(WRITE_REPLY).unwrap();
            bytes.extend(parse_hex(READ_REPLY).unwrap());
            let mut x = FrameExtractor::new(Framing::Replies);
            x.push(&bytes[..cut]);
            let mut got = Vec::new();
            while let Some(b) = x.next_block() { got.push(b.telegram); }
            x.push(&bytes[cut..]);
            while let Some(b) = x.next_block() { got.push(b.telegram); }
            prop_assert_eq!(got.len(), 2);
            prop_assert!(got.iter().all(Result::is_ok));
        }

        #[test]
        fn noise_never_panics(chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..40), 0..10), framing in any::<bool>()) {
            let mut x = FrameExtractor::new(if framing { Framing::Requests } else { Framing::Replies });
            for c in chunks {
                x.push(&c);
                while x.next_block().is_some() {}
            }
        }

        #[test]
        fn garbage_without_zero_bytes_then_a_block(garbage in proptest::collection::vec(1u8..=255, 0..30)) {
            let t = crate::family::sd2::codec::Telegram::write_request(2, 1, 68, 0, &[6, 0]).unwrap();
            let mut x = FrameExtractor::new(Framing::Requests);
            x.push(&garbage);
            x.push(&t.encode(WriteLength::Captured));
            let got = x.next_block().unwrap();
            prop_assert_eq!(got.skipped, garbage.len());
            prop_assert_eq!(got.telegram, Ok(t));
        }
    }
}
