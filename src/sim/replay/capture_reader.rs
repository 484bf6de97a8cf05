//! Reads a capture line by line, streaming (a 24 h capture is never held whole): a
//! drivescript `--trace` of a byte family (`  0.012345 TX 00 09 ..  # meaning`) or a CAN
//! log in candump's format (`(1700000000.123456) can0 601#4000100000000000`, as `candump
//! -l` and drivescript's CAN traces write it; a trailing `T`/`R` of `candump -x` gives the
//! direction). Comments, link events (`--`) and blank lines are skipped; anything else is a
//! [`CaptureError`] naming file and line. Must not interpret the telegrams.

use super::capture_error::LineProblem;
use super::CaptureError;
use crate::bus::CanFrame;
use crate::link::Direction;
use std::io::BufRead;
use std::path::PathBuf;
use std::time::Duration;

/// A line longer than this is not a telegram of any family (and must not fill memory).
const MAX_LINE: u64 = 64 * 1024;

/// One telegram of a capture.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CaptureRecord {
    /// 1-based line number in the capture file.
    pub line: u64,
    /// The capture's own clock (seconds since the run started, or since the epoch).
    pub at: Duration,
    /// `None` for a candump line without `T`/`R`: the family tells a request from a reply.
    pub direction: Option<Direction>,
    /// The telegram's bytes; for a CAN frame [`CanFrame::to_bytes`].
    pub bytes: Vec<u8>,
    /// Whether the bytes are a CAN frame.
    pub frame: bool,
}

pub struct CaptureReader<R: BufRead> {
    input: R,
    file: PathBuf,
    line: u64,
    buf: Vec<u8>,
}

impl<R: BufRead> CaptureReader<R> {
    /// `file` names the capture in errors.
    pub fn new(input: R, file: impl Into<PathBuf>) -> Self {
        CaptureReader {
            input,
            file: file.into(),
            line: 0,
            buf: Vec::new(),
        }
    }

    /// The next telegram; `Ok(None)` at the end of the capture.
    pub fn next_record(&mut self) -> Result<Option<CaptureRecord>, CaptureError> {
        loop {
            self.buf.clear();
            let read = std::io::Read::take(self.input.by_ref(), MAX_LINE + 1)
                .read_until(b'\n', &mut self.buf)
                .map_err(|e| CaptureError::Unreadable {
                    file: self.file.clone(),
                    detail: e.to_string(),
                })?;
            if read == 0 {
                return Ok(None);
            }
            self.line += 1;
            if self.buf.len() as u64 > MAX_LINE {
                return Err(self.error(LineProblem::TooLong { max: MAX_LINE }));
            }
            // Comments may hold any bytes; telegrams are ASCII.
            let text = String::from_utf8_lossy(&self.buf).into_owned();
            match parse_line(&text) {
                Ok(Some((at, direction, bytes, frame))) => {
                    return Ok(Some(CaptureRecord {
                        line: self.line,
                        at,
                        direction,
                        bytes,
                        frame,
                    }))
                }
                Ok(None) => continue,
                Err(what) => return Err(self.error(what)),
            }
        }
    }

    fn error(&self, what: LineProblem) -> CaptureError {
        CaptureError::Line {
            file: self.file.clone(),
            line: self.line,
            what,
        }
    }
}

pub(super) type Parsed = Option<(Duration, Option<Direction>, Vec<u8>, bool)>;

/// One line: a telegram, `None` for what carries none, or what is wrong with it.
pub(super) fn parse_line(text: &str) -> Result<Parsed, LineProblem> {
    // A `-v` trace line carries the meaning after `  # `; it is not read.
    let body = text.split_once(" #").map_or(text, |(b, _)| b).trim();
    if body.is_empty() || body.starts_with('#') {
        return Ok(None);
    }
    if let Some(rest) = body.strip_prefix('(') {
        return candump_line(rest);
    }
    let mut tokens = body.splitn(3, char::is_whitespace);
    let (Some(time), Some(tag)) = (tokens.next(), tokens.next()) else {
        return Err(not_a_telegram(body));
    };
    let direction = match tag {
        "TX" => Direction::Sent,
        "RX" => Direction::Received,
        "--" => return seconds(time).map(|_| None),
        _ => return Err(not_a_telegram(body)),
    };
    let at = seconds(time)?;
    let hex = tokens.next().unwrap_or("").trim();
    if hex.starts_with('(') {
        // `RX (no bytes)`: an empty reply, nothing to answer with.
        return Ok(None);
    }
    let bytes = crate::hex::parse_hex(hex).map_err(|problem| LineProblem::Telegram {
        hex: hex.to_string(),
        problem,
    })?;
    Ok(Some((at, Some(direction), bytes, false)))
}

/// `1700000000.123456) can0 601#40001000 [T|R]`, after the opening parenthesis. Remote
/// frames (`701#R`, node guarding) and CAN FD frames (`##`) are real traffic no drive
/// family here answers with data: they are left out.
fn candump_line(rest: &str) -> Result<Parsed, LineProblem> {
    let (time, rest) = rest.split_once(')').ok_or(LineProblem::CandumpTime)?;
    let at = seconds(time.trim())?;
    let mut tokens = rest.split_whitespace();
    let (Some(_interface), Some(frame)) = (tokens.next(), tokens.next()) else {
        return Err(LineProblem::CandumpShape);
    };
    let direction = match tokens.next() {
        None => None,
        Some("T") => Some(Direction::Sent),
        Some("R") => Some(Direction::Received),
        Some(other) => {
            return Err(LineProblem::AfterFrame {
                after: other.to_string(),
            })
        }
    };
    if frame
        .split_once('#')
        .is_some_and(|(_, data)| data.starts_with('R') || data.starts_with('#'))
    {
        return Ok(None);
    }
    let frame = CanFrame::parse_text(frame)?;
    Ok(Some((at, direction, frame.to_bytes(), true)))
}

/// `0.012345` or `1700000000.123456`: seconds, at most nanosecond precision.
fn seconds(text: &str) -> Result<Duration, LineProblem> {
    let bad = || LineProblem::NotATime {
        text: text.to_string(),
    };
    let (whole, fraction) = text.split_once('.').unwrap_or((text, ""));
    if whole.is_empty()
        || !whole.bytes().all(|b| b.is_ascii_digit())
        || fraction.len() > 9
        || !fraction.bytes().all(|b| b.is_ascii_digit())
    {
        return Err(bad());
    }
    let secs: u64 = whole.parse().map_err(|_| bad())?;
    let nanos: u32 = if fraction.is_empty() {
        0
    } else {
        format!("{fraction:0<9}").parse().map_err(|_| bad())?
    };
    Ok(Duration::new(secs, nanos))
}

fn not_a_telegram(line: &str) -> LineProblem {
    LineProblem::NotATelegram {
        shown: line.chars().take(60).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn all(text: &str) -> Result<Vec<CaptureRecord>, CaptureError> {
        let mut reader = CaptureReader::new(text.as_bytes(), "cap.trace");
        let mut out = Vec::new();
        while let Some(r) = reader.next_record()? {
            out.push(r);
        }
        Ok(out)
    }

    #[test]
    fn a_trace_gives_its_telegrams_with_time_direction_and_line() {
        let text = "# drive: sd2\n    0.000000 TX 00 09 02  # read\n\n    0.000100 RX 00 11 01  # reply\n    0.114000 -- no reply within 100 ms\n    0.2 RX (no bytes)  # empty\n";
        let records = all(text).unwrap();
        assert_eq!(records.len(), 2);
        assert_eq!(records[0].line, 2);
        assert_eq!(records[0].direction, Some(Direction::Sent));
        assert_eq!(records[0].bytes, vec![0x00, 0x09, 0x02]);
        assert_eq!(records[1].at, Duration::from_micros(100));
        assert_eq!(records[1].line, 4);
        assert!(!records[1].frame);
    }

    #[test]
    fn candump_lines_in_can_utils_format_with_and_without_direction() {
        let text = "(1700000000.123456) can0 601#4000100000000000\n(1700000000.123500) can0 701#R\n(1700000000.123600) can0 123##1112233\n(1700000000.124000) can0 581#4B00100092010000 R\n";
        let records = all(text).unwrap();
        assert_eq!(records[0].at, Duration::new(1_700_000_000, 123_456_000));
        assert_eq!(records[0].direction, None);
        assert_eq!(
            records[0].bytes,
            CanFrame::parse_text("601#4000100000000000").unwrap().to_bytes()
        );
        assert_eq!(records.len(), 2, "remote and CAN FD frames are left out");
        assert_eq!(
            (records[1].line, records[1].direction),
            (4, Some(Direction::Received))
        );
        assert!(records[1].frame);
    }

    #[test]
    fn a_bad_line_is_named_with_file_and_line() {
        let e = all("# x\n    0.1 TX 00 09\nhello world\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("cap.trace:3: `hello world` is neither a trace line"),
            "{e}"
        );
        let e = all("    0.1 TX 0g\n").unwrap_err().to_string();
        assert!(e.starts_with("cap.trace:1: the telegram `0g`"), "{e}");
        let e = all("(17x.1) can0 601#00\n").unwrap_err().to_string();
        assert!(e.starts_with("cap.trace:1: `17x.1` is not a time"), "{e}");
        let e = all("(1.1) can0 601#00 X\n").unwrap_err().to_string();
        assert!(e.contains("only T or R"), "{e}");
    }

    proptest! {
        #[test]
        fn no_panic_on_any_text(text in "\\PC{0,200}(\n\\PC{0,80}){0,6}") {
            let _ = all(&text);
        }

        #[test]
        fn no_panic_on_any_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
            let mut reader = CaptureReader::new(&bytes[..], "x");
            while let Ok(Some(_)) = reader.next_record() {}
        }
    }
}
