//! The SLCAN (Lawicel) ASCII protocol of USB-serial CAN adapters, pure: bit-rate commands
//! (`S0`..`S8`), frames as text (`tIIILDD…` standard, `TIIIIIIIILDD…` extended, `r`/`R`
//! remote, each ended by CR, received ones optionally followed by a 4-hex-digit timestamp,
//! which is ignored), and [`SlcanReader`], which cuts the adapter's byte stream into
//! events: a frame, an acknowledgement (CR alone, or `z`/`Z` + CR after a transmit), a
//! refusal (BELL, 0x07), or a line that is none of these. Bounded: a line longer than any
//! SLCAN line is dropped, never buffered without end. No I/O.

use super::CanFrame;

const CR: u8 = b'\r';
const BELL: u8 = 0x07;
/// Longest SLCAN line: `T`, 8 id digits, length, 16 data digits, 4 timestamp digits.
const MAX_LINE: usize = 1 + 8 + 1 + 16 + 4;

/// The `S` command for a bit rate in bit/s (`S6` for 500 kbit/s); `None` for a rate
/// SLCAN has no command for.
pub fn bitrate_command(bitrate: u32) -> Option<&'static str> {
    Some(match bitrate {
        10_000 => "S0",
        20_000 => "S1",
        50_000 => "S2",
        100_000 => "S3",
        125_000 => "S4",
        250_000 => "S5",
        500_000 => "S6",
        800_000 => "S7",
        1_000_000 => "S8",
        _ => return None,
    })
}

/// The rates `S0`..`S8` stand for, for messages.
pub const BITRATES: &str = "10k, 20k, 50k, 100k, 125k, 250k, 500k, 800k or 1M";

/// A frame as the transmit command: `t60C8409C5F0000000000` + CR.
pub fn encode_frame(frame: &CanFrame) -> Vec<u8> {
    let mut text = if frame.extended {
        format!("T{:08X}{}", frame.id, frame.data().len())
    } else {
        format!("t{:03X}{}", frame.id, frame.data().len())
    };
    for b in frame.data() {
        text.push_str(&format!("{b:02X}"));
    }
    let mut bytes = text.into_bytes();
    bytes.push(CR);
    bytes
}

/// One thing the adapter said.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SlcanEvent {
    /// A data frame received from the bus.
    Frame(CanFrame),
    /// A remote frame (no data; SDO does not use them).
    Remote,
    /// A command succeeded: CR, or `z`/`Z` CR after a transmit.
    Ack,
    /// A command failed: BELL.
    Refused,
    /// A line that is none of the above (a version reply `V1013`, noise), as text.
    Other(String),
}

/// Reads one line (without its CR) as an event.
pub fn parse_line(line: &[u8]) -> SlcanEvent {
    match line.first() {
        None => SlcanEvent::Ack,
        Some(b'z' | b'Z') if line.len() == 1 => SlcanEvent::Ack,
        Some(b't') => parse_frame(&line[1..], 3, false),
        Some(b'T') => parse_frame(&line[1..], 8, true),
        Some(b'r' | b'R') => SlcanEvent::Remote,
        _ => SlcanEvent::Other(String::from_utf8_lossy(line).into_owned()),
    }
}

fn hex_value(digits: &[u8]) -> Option<u32> {
    if digits.is_empty() || digits.len() > 8 {
        return None;
    }
    let text = std::str::from_utf8(digits).ok()?;
    if !text.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(text, 16).ok()
}

/// `IIIL DD… [TTTT]` after the `t` (or `T` with 8 id digits).
fn parse_frame(rest: &[u8], id_digits: usize, extended: bool) -> SlcanEvent {
    let other = || {
        SlcanEvent::Other(format!(
            "{}{}",
            if extended { 'T' } else { 't' },
            String::from_utf8_lossy(rest)
        ))
    };
    let Some(id) = rest.get(..id_digits).and_then(hex_value) else {
        return other();
    };
    let Some(len) = rest.get(id_digits).and_then(|&d| (d as char).to_digit(10)) else {
        return other();
    };
    let len = len as usize;
    let start = id_digits + 1;
    let end = start + 2 * len;
    // After the data only a 4-digit timestamp may follow.
    let tail = rest.len().saturating_sub(end);
    if len > 8 || rest.len() < end || !(tail == 0 || (tail == 4 && hex_value(&rest[end..]).is_some())) {
        return other();
    }
    let mut data = Vec::with_capacity(len);
    for pair in rest[start..end].chunks(2) {
        match hex_value(pair) {
            Some(b) => data.push(b as u8),
            None => return other(),
        }
    }
    let frame = if extended {
        CanFrame::extended(id, &data)
    } else {
        CanFrame::new(id, &data)
    };
    frame.map_or_else(other, SlcanEvent::Frame)
}

/// Cuts the adapter's bytes into events.
#[derive(Debug, Default)]
pub struct SlcanReader {
    line: Vec<u8>,
    /// The current line ran past [`MAX_LINE`]: drop it up to its CR.
    overlong: bool,
}

impl SlcanReader {
    pub fn new() -> Self {
        SlcanReader::default()
    }

    /// Feeds bytes; returns the events they complete.
    pub fn push(&mut self, bytes: &[u8]) -> Vec<SlcanEvent> {
        let mut events = Vec::new();
        for &b in bytes {
            match b {
                BELL => {
                    self.line.clear();
                    self.overlong = false;
                    events.push(SlcanEvent::Refused);
                }
                CR => {
                    if self.overlong {
                        events.push(SlcanEvent::Other("an over-long line".into()));
                    } else {
                        events.push(parse_line(&self.line));
                    }
                    self.line.clear();
                    self.overlong = false;
                }
                // Some adapters end lines with CR LF; the LF starts nothing.
                b'\n' if self.line.is_empty() => {}
                _ if self.line.len() >= MAX_LINE => self.overlong = true,
                _ => self.line.push(b),
            }
        }
        events
    }

    /// Forgets a partial line (after the port was reopened).
    pub fn clear(&mut self) {
        self.line.clear();
        self.overlong = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn frames_both_ways_with_and_without_timestamps() {
        let f = CanFrame::new(0x60C, &[0x40, 0x9C, 0x5F, 0, 0, 0, 0, 0]).unwrap();
        assert_eq!(encode_frame(&f), b"t60C8409C5F0000000000\r");
        let mut r = SlcanReader::new();
        let reply = CanFrame::new(0x58C, &[0x41, 0x9C, 0x5F, 0, 0x0B, 0, 0, 0]).unwrap();
        // An acknowledgement of the transmit, the reply with a timestamp, a BELL, a CR.
        let events = r.push(b"z\rt58C8419C5F000B0000001A2F\r\x07\r");
        assert_eq!(
            events,
            [
                SlcanEvent::Ack,
                SlcanEvent::Frame(reply),
                SlcanEvent::Refused,
                SlcanEvent::Ack
            ]
        );
        // Split anywhere, the same events.
        let mut r = SlcanReader::new();
        let mut split = r.push(b"t58C8419C5F00");
        split.extend(r.push(b"0B000000\r"));
        assert_eq!(split, [SlcanEvent::Frame(reply)]);
        let ext = CanFrame::extended(0x18FF_0001, &[1, 2]).unwrap();
        assert_eq!(encode_frame(&ext), b"T18FF000120102\r");
        assert_eq!(
            SlcanReader::new().push(b"T18FF000120102\r"),
            [SlcanEvent::Frame(ext)]
        );
    }

    #[test]
    fn what_is_no_frame_is_said_to_be_so() {
        assert_eq!(parse_line(b"V1013"), SlcanEvent::Other("V1013".into()));
        assert_eq!(parse_line(b"r6000"), SlcanEvent::Remote);
        assert!(matches!(parse_line(b"t60C9"), SlcanEvent::Other(_)), "length 9");
        assert!(
            matches!(parse_line(b"t60C2AB"), SlcanEvent::Other(_)),
            "short data"
        );
        assert!(
            matches!(parse_line(b"t60C1AB12"), SlcanEvent::Other(_)),
            "2-digit tail"
        );
        assert!(
            matches!(parse_line(b"t8001AB"), SlcanEvent::Other(_)),
            "id over 11 bits"
        );
        let mut r = SlcanReader::new();
        let long = [b'7'; 100];
        assert_eq!(r.push(&long), []);
        assert_eq!(r.push(b"\r"), [SlcanEvent::Other("an over-long line".into())]);
    }

    #[test]
    fn bitrates() {
        assert_eq!(bitrate_command(500_000), Some("S6"));
        assert_eq!(bitrate_command(1_000_000), Some("S8"));
        assert_eq!(bitrate_command(83_333), None);
    }

    proptest! {
        #[test]
        fn any_bytes_give_bounded_events_and_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
            let mut r = SlcanReader::new();
            let events = r.push(&bytes);
            prop_assert!(events.len() <= bytes.len());
            prop_assert!(r.line.len() <= MAX_LINE);
        }

        #[test]
        fn every_frame_survives_the_text_form(id in 0u32..0x800, data in proptest::collection::vec(any::<u8>(), 0..=8), stamp in proptest::option::of(0u16..)) {
            let f = CanFrame::new(id, &data).unwrap();
            let mut line = encode_frame(&f);
            line.pop();
            if let Some(s) = stamp {
                line.extend_from_slice(format!("{s:04X}").as_bytes());
            }
            line.push(b'\r');
            prop_assert_eq!(SlcanReader::new().push(&line), vec![SlcanEvent::Frame(f)]);
        }
    }
}
