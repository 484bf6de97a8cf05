//! Cuts a byte stream into CR-terminated lines. LF is never part of a line (a stray LF
//! before or after the CR is dropped), empty lines are skipped, and memory is bounded:
//! a run of more than [`MAX_LINE`] bytes without a CR is reported once as too long and
//! thrown away up to the next CR.

use super::decode_error::DecodeError;
use super::CR;

/// The longest line kept. The longest line the protocol defines is an SDO write with
/// 8 data bytes (24 characters); the switch-on message has no documented length, so there
/// is room to spare.
pub const MAX_LINE: usize = 128;

const LF: u8 = 0x0A;

/// One line cut from the stream.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Line {
    /// The bytes as received, without CR and LF (for traces).
    pub bytes: Vec<u8>,
    /// The text, or why these bytes are no line of the protocol.
    pub text: Result<String, DecodeError>,
}

#[derive(Debug, Default)]
pub struct LineExtractor {
    pending: Vec<u8>,
    /// Bytes of an over-long line dropped so far; its end (the next CR) is still to come.
    overflow: usize,
}

impl LineExtractor {
    pub fn new() -> Self {
        Self::default()
    }

    /// Bytes received but not yet part of a complete line.
    pub fn pending(&self) -> usize {
        self.pending.len() + self.overflow
    }

    pub fn clear(&mut self) {
        self.pending.clear();
        self.overflow = 0;
    }

    /// Adds received bytes; complete lines are taken with [`Self::next_line`].
    pub fn push(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if b == LF {
                continue;
            }
            if self.overflow > 0 {
                if b == CR {
                    // The over-long line ended; it was reported when it overflowed.
                    self.overflow = 0;
                    self.pending.push(CR);
                } else {
                    self.overflow += 1;
                }
                continue;
            }
            self.pending.push(b);
        }
    }

    /// The next complete line, or an over-long one as an error (once), or `None`.
    pub fn next_line(&mut self) -> Option<Line> {
        loop {
            match self.pending.iter().position(|&b| b == CR) {
                Some(end) if end > MAX_LINE => {
                    // Only reachable for bytes pushed while a CR was already pending.
                    let len = end;
                    self.pending.drain(..=end);
                    return Some(too_long(len));
                }
                Some(end) => {
                    let bytes: Vec<u8> = self.pending.drain(..=end).take(end).collect();
                    if bytes.iter().all(|b| *b == b' ') {
                        continue;
                    }
                    let text = match std::str::from_utf8(&bytes) {
                        Ok(t) => super::request::check_ascii(t).map(str::to_string),
                        Err(_) => {
                            let offset = bytes.iter().position(|b| !b.is_ascii()).unwrap_or(0);
                            Err(DecodeError::NotAscii {
                                offset,
                                found: char::from(bytes[offset]),
                            })
                        }
                    };
                    return Some(Line { bytes, text });
                }
                None if self.pending.len() > MAX_LINE => {
                    let len = self.pending.len();
                    self.pending.clear();
                    self.overflow = len;
                    return Some(too_long(len));
                }
                None => return None,
            }
        }
    }
}

fn too_long(len: usize) -> Line {
    Line {
        bytes: Vec::new(),
        text: Err(DecodeError::TooLong { len, max: MAX_LINE }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn lines(input: &[u8]) -> Vec<Result<String, DecodeError>> {
        let mut x = LineExtractor::new();
        x.push(input);
        std::iter::from_fn(|| x.next_line()).map(|l| l.text).collect()
    }

    #[test]
    fn cr_ends_a_line_and_stray_lf_is_dropped() {
        assert_eq!(lines(b"OK!\r"), vec![Ok("OK!".into())]);
        assert_eq!(
            lines(b"\nOK!\r\n0011:00000BB8\r"),
            vec![Ok("OK!".into()), Ok("0011:00000BB8".into())]
        );
        assert_eq!(lines(b"OK\n!\r"), vec![Ok("OK!".into())]);
        assert_eq!(lines(b"\r\r\n \rDONE\r"), vec![Ok("DONE".into())]);
        assert_eq!(lines(b"DONE"), vec![]);
    }

    #[test]
    fn a_line_split_over_reads_is_joined() {
        let mut x = LineExtractor::new();
        x.push(b"00");
        assert!(x.next_line().is_none());
        x.push(b"11:000\n00BB8\r");
        assert_eq!(x.next_line().unwrap().text, Ok("0011:00000BB8".into()));
        assert_eq!(x.pending(), 0);
    }

    #[test]
    fn an_over_long_line_is_reported_once_and_dropped_to_its_cr() {
        let mut x = LineExtractor::new();
        x.push(&[b'A'; 200]);
        let first = x.next_line().unwrap();
        assert!(
            matches!(first.text, Err(DecodeError::TooLong { max: MAX_LINE, .. })),
            "{first:?}"
        );
        assert!(x.next_line().is_none());
        x.push(&[b'B'; 1000]);
        assert!(x.next_line().is_none());
        assert!(
            x.pending() > 1000,
            "the count of dropped bytes, not the bytes, is kept"
        );
        x.push(b"C\rOK!\r");
        assert_eq!(x.next_line().unwrap().text, Ok("OK!".into()));
        assert!(x.next_line().is_none());
    }

    #[test]
    fn garbage_bytes_are_a_line_with_the_reason() {
        let got = lines(b"\xff\xfeOK\r");
        assert!(
            matches!(got[0], Err(DecodeError::NotAscii { offset: 0, .. })),
            "{got:?}"
        );
        let got = lines(b"OK\x07!\r");
        assert!(
            matches!(got[0], Err(DecodeError::NotAscii { offset: 2, .. })),
            "{got:?}"
        );
    }

    proptest! {
        #[test]
        fn memory_stays_bounded_and_nothing_panics(chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..300), 0..20)) {
            let mut x = LineExtractor::new();
            for c in chunks {
                x.push(&c);
                while let Some(line) = x.next_line() {
                    prop_assert!(line.bytes.len() <= MAX_LINE);
                }
                prop_assert!(x.pending.len() <= MAX_LINE);
            }
        }
    }
}
