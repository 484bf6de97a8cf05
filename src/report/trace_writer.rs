//! The telegram trace (`--trace FILE`, and `-v` on stderr): one line per telegram as the
//! run goes, flushed at once, so a trace of an aborted run is complete up to the abort:
//!
//! ```text
//!     0.012345 TX 00 09 02 01 0d 43 00 00 00 00 00 a3  # read object 67 status_word
//!     0.013901 RX 00 09 01 02 8d 02 00 37 02 ..        # reply status_word = 0x0237 operation enabled
//!     0.114000 -- no reply within 100 ms
//! ```
//!
//! The hex between the TX/RX tag and `#` is what `drivescript decode` reads back
//! ([`hex_of_trace_line`]), with the [`TraceHeader`] at the top saying which drive's
//! telegrams they are. A CAN trace file holds frames only, as a candump log (python-can's
//! reader accepts nothing else); its header and link events go to the notes file next to
//! it ([`trace_notes_path`]). It must not block or fail the link: write errors are kept, not
//! raised, and the rest of the run goes on without the trace.

use super::trace_header::{trace_notes_path, TraceHeader};
use crate::bus::CanFrame;
use crate::hex::to_hex;
use crate::link::{Direction, TelegramExplainer, TelegramObserver};
use crate::output_file_error::{create_output_file, OutputFileError};
use std::io::Write;
use std::path::Path;
use std::time::Duration;

pub struct TraceWriter<W: Write + Send> {
    out: W,
    /// The family's reading of its telegrams, for the text after `#`.
    explainer: Box<dyn TelegramExplainer>,
    /// The first write error; after it the trace stays silent.
    error: Option<String>,
    /// CAN frames went by: the trace is in candump's log format, events become comments.
    candump: bool,
    /// Whether CAN frame lines carry their meaning after `#` (on a terminal, `-v`); a
    /// file keeps them exactly as candump writes them so CAN tools can read it.
    frame_meanings: bool,
    /// Where comments and link events go when they must not go into `out` (a CAN trace
    /// file: its notes file).
    notes: Option<W>,
}

/// The interface name CAN frame lines carry (candump's log names one; `canplayer
/// vcan0=can0 -I FILE` replays such a trace on another interface).
pub const TRACE_CAN_INTERFACE: &str = "can0";

impl<W: Write + Send> TraceWriter<W> {
    /// A trace onto `out` (a file, or `std::io::stderr()` for `-v`).
    pub fn new(out: W, explainer: Box<dyn TelegramExplainer>) -> Self {
        TraceWriter {
            out,
            explainer,
            error: None,
            candump: false,
            frame_meanings: true,
            notes: None,
        }
    }

    /// Writes `# text` (ignored by `decode` and [`hex_of_trace_line`]).
    pub fn comment(&mut self, text: &str) {
        for line in text.lines() {
            self.note(&format!("# {line}"));
        }
    }

    /// The first write error, if writing ever failed.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    pub fn into_inner(self) -> W {
        self.out
    }

    /// Nothing more is written after the first error: a full or hung disk must not
    /// cost every later telegram (the safe stop's too) another write and flush.
    fn line(&mut self, text: &str) {
        if self.error.is_some() {
            return;
        }
        let result = write_line(&mut self.out, text);
        self.keep_error(result);
    }

    /// A comment or link event: into the notes file when there is one.
    fn note(&mut self, text: &str) {
        if self.error.is_some() {
            return;
        }
        let result = match &mut self.notes {
            Some(notes) => write_line(notes, text),
            None => write_line(&mut self.out, text),
        };
        self.keep_error(result);
    }

    fn keep_error(&mut self, result: std::io::Result<()>) {
        if let (Err(e), None) = (result, &self.error) {
            self.error = Some(e.to_string());
        }
    }
}

fn write_line(out: &mut impl Write, text: &str) -> std::io::Result<()> {
    out.write_all(format!("{text}\n").as_bytes())
        .and_then(|()| out.flush())
}

impl TraceWriter<std::fs::File> {
    /// Creates (truncates) the trace file, its directory too, and writes the header
    /// comments: into the file, or for a trace of CAN `frames` into its notes file (also
    /// created). An unwritable path is an error here, before anything is sent.
    pub fn create(
        path: &Path,
        header: &TraceHeader,
        frames: bool,
        explainer: Box<dyn TelegramExplainer>,
    ) -> Result<Self, OutputFileError> {
        let file = create_output_file(path, false)?;
        let mut trace = TraceWriter::new(file, explainer);
        trace.frame_meanings = false;
        let name = path.file_name().map_or(path, Path::new).display();
        if frames {
            trace.notes = Some(create_output_file(&trace_notes_path(path), false)?);
            trace.candump = true;
            trace.comment(&format!(
                "drivescript trace notes: the drive and line of the CAN frames in {name} \
                 (candump's log format), and the link events"
            ));
        } else {
            trace.comment(
                "drivescript telegram trace: clock seconds, TX (sent) or RX (received), the \
                 bytes as in the manual  # meaning",
            );
        }
        trace.comment(&format!(
            "`drivescript decode {name}` explains every telegram in full with the drive below"
        ));
        for line in header.lines() {
            trace.comment(&line);
        }
        match trace.error.take() {
            Some(e) => Err(OutputFileError::file(path, std::io::Error::other(e))),
            None => Ok(trace),
        }
    }
}

impl<W: Write + Send> TelegramObserver for TraceWriter<W> {
    fn telegram(&mut self, at: Duration, direction: Direction, bytes: &[u8]) {
        let meaning = self.explainer.summary(direction, bytes);
        let hex = if bytes.is_empty() {
            "(no bytes)".to_string()
        } else {
            to_hex(bytes)
        };
        self.line(&format!(
            "{:>12.6} {} {hex}  # {}",
            at.as_secs_f64(),
            direction.tag(),
            one_line(&meaning)
        ));
    }

    fn event(&mut self, at: Duration, text: &str) {
        let comment = if self.candump && self.notes.is_none() {
            "# "
        } else {
            ""
        };
        self.note(&format!(
            "{comment}{:>12.6} -- {}",
            at.as_secs_f64(),
            one_line(text)
        ));
    }

    /// candump's log format, `(0000000000.012345) can0 60C#409C5F0000000000`, with the
    /// meaning after `  # ` only on a terminal.
    fn frame(&mut self, at: Duration, direction: Direction, frame: &CanFrame) {
        if !self.candump && !self.frame_meanings {
            self.comment(
                "CAN frames follow in candump's log format; `drivescript decode` on this \
                 file explains them with the drive its header names",
            );
        }
        self.candump = true;
        let mut line = format!(
            "({:010}.{:06}) {TRACE_CAN_INTERFACE} {}",
            at.as_secs(),
            at.subsec_micros(),
            frame.to_candump()
        );
        if self.frame_meanings {
            let meaning = self.explainer.summary(direction, &frame.to_bytes());
            line.push_str(&format!("  # {}", one_line(&meaning)));
        }
        self.line(&line);
    }
}

/// The hex bytes of a trace line (`    0.012345 TX 00 09 ..  # meaning` gives `00 09 ..`);
/// `None` for link events (`--`), comments and lines that are not trace lines.
pub fn hex_of_trace_line(line: &str) -> Option<&str> {
    let line = line.trim_start();
    let (seconds, rest) = line.split_once(' ')?;
    seconds.parse::<f64>().ok()?;
    let rest = rest.trim_start();
    let rest = rest.strip_prefix("TX").or_else(|| rest.strip_prefix("RX"))?;
    if !rest.starts_with(' ') {
        return None;
    }
    let hex = rest.split_once('#').map_or(rest, |(hex, _)| hex).trim();
    if hex.is_empty() || hex.starts_with('(') {
        None
    } else {
        Some(hex)
    }
}

/// True for every line a trace of a byte family holds: telegram lines, link events (`--`)
/// and comments (`#`). (CAN traces are candump logs, which `decode` reads as frames.)
/// `decode` reads a trace line's hex with [`hex_of_trace_line`] and skips the others, and
/// takes any other line as hex itself.
pub fn is_trace_line(line: &str) -> bool {
    let line = line.trim_start();
    if line.starts_with('#') {
        return true;
    }
    let mut tokens = line.split_whitespace();
    let seconds = tokens
        .next()
        .is_some_and(|t| t.contains('.') && t.parse::<f64>().is_ok());
    seconds && matches!(tokens.next(), Some("TX" | "RX" | "--"))
}

/// Error texts and events can hold line breaks; a trace line must stay one line.
pub(crate) fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Says how many bytes it was given, so the line format can be checked alone.
    struct Counting;

    impl TelegramExplainer for Counting {
        fn summary(&mut self, direction: Direction, bytes: &[u8]) -> String {
            format!("{} bytes {}\nwrapped", bytes.len(), direction.tag())
        }
        fn explain(&mut self, _bytes: &[u8]) -> Result<String, crate::link::ExplainError> {
            Err(String::from("not used").into())
        }
        fn json(&mut self, _bytes: &[u8]) -> (serde_json::Value, bool) {
            (serde_json::Value::Null, false)
        }
    }

    /// Fails every write and counts how often it was asked.
    struct Failing(std::sync::Arc<std::sync::atomic::AtomicUsize>);

    impl Write for Failing {
        fn write(&mut self, _buf: &[u8]) -> std::io::Result<usize> {
            self.0.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            Err(std::io::Error::other("disk full"))
        }
        fn flush(&mut self) -> std::io::Result<()> {
            self.0.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            Err(std::io::Error::other("disk full"))
        }
    }

    #[test]
    fn after_the_first_write_error_nothing_more_is_written() {
        let calls = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let frame = CanFrame::new(0x60C, &[0x40]).unwrap();
        for notes in [false, true] {
            calls.store(0, std::sync::atomic::Ordering::SeqCst);
            let mut trace = TraceWriter::new(Failing(calls.clone()), Box::new(Counting));
            if notes {
                trace.notes = Some(Failing(calls.clone()));
            }
            trace.telegram(Duration::ZERO, Direction::Sent, &[0x00]);
            assert_eq!(trace.error(), Some("disk full"));
            let after_first = calls.load(std::sync::atomic::Ordering::SeqCst);
            trace.telegram(Duration::ZERO, Direction::Received, &[0x01]);
            trace.event(Duration::ZERO, "no reply");
            trace.comment("a\nb");
            trace.frame(Duration::ZERO, Direction::Sent, &frame);
            assert_eq!(
                calls.load(std::sync::atomic::Ordering::SeqCst),
                after_first,
                "notes file: {notes}"
            );
            assert_eq!(trace.error(), Some("disk full"));
        }
    }

    #[test]
    fn one_line_per_telegram_and_event_with_the_explainers_words() {
        let mut trace = TraceWriter::new(Vec::new(), Box::new(Counting));
        trace.telegram(Duration::from_millis(12), Direction::Sent, &[0x00, 0x09]);
        trace.telegram(Duration::from_millis(14), Direction::Received, &[]);
        trace.event(Duration::from_millis(115), "no reply\nwithin 100 ms");
        trace.comment("a\nb");
        let text = String::from_utf8(trace.into_inner()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "    0.012000 TX 00 09  # 2 bytes TX wrapped");
        assert_eq!(lines[1], "    0.014000 RX (no bytes)  # 0 bytes RX wrapped");
        assert_eq!(lines[2], "    0.115000 -- no reply within 100 ms");
        assert_eq!(lines[3..], ["# a", "# b"]);
        assert_eq!(hex_of_trace_line(lines[0]), Some("00 09"));
        assert_eq!(hex_of_trace_line(lines[1]), None);
        assert_eq!(hex_of_trace_line(lines[2]), None);
        assert!(lines.iter().all(|l| is_trace_line(l)));
        assert!(!is_trace_line("00 09 02"));
    }

    #[test]
    fn can_frames_in_candump_log_format_and_events_as_comments() {
        let frame = CanFrame::new(0x60C, &[0x40, 0x9C, 0x5F, 0, 0, 0, 0, 0]).unwrap();
        let mut file = TraceWriter::new(Vec::new(), Box::new(Counting));
        file.frame_meanings = false;
        file.frame(Duration::from_micros(12_345), Direction::Sent, &frame);
        file.event(Duration::from_millis(115), "no response");
        let text = String::from_utf8(file.into_inner()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("# CAN frames follow in candump's log format"));
        assert!(lines[0].contains("the drive its header names"), "{}", lines[0]);
        assert!(!lines[0].contains("--protocol"), "{}", lines[0]);
        assert_eq!(lines[1], "(0000000000.012345) can0 60C#409C5F0000000000");
        assert_eq!(lines[2], "#     0.115000 -- no response");
        let mut terminal = TraceWriter::new(Vec::new(), Box::new(Counting));
        terminal.frame(Duration::ZERO, Direction::Received, &frame);
        let text = String::from_utf8(terminal.into_inner()).unwrap();
        assert_eq!(
            text,
            "(0000000000.000000) can0 60C#409C5F0000000000  # 12 bytes RX wrapped\n"
        );
        assert!(!is_trace_line(lines[1]) && hex_of_trace_line(lines[1]).is_none());
    }

    #[test]
    fn a_can_trace_file_holds_frames_only_and_its_notes_the_header_and_events() {
        let dir = std::env::temp_dir().join(format!("drivescript-can-trace-{}", std::process::id()));
        let path = dir.join("run.log");
        let header = TraceHeader {
            drive: "lenze-9400".into(),
            address: "CAN node 12".into(),
            ..TraceHeader::default()
        };
        let mut trace = TraceWriter::create(&path, &header, true, Box::new(Counting)).unwrap();
        let frame = CanFrame::new(0x60C, &[0x40, 0x9C, 0x5F, 0, 0, 0, 0, 0]).unwrap();
        trace.event(Duration::ZERO, "drive `left`");
        trace.frame(Duration::from_micros(100), Direction::Sent, &frame);
        trace.event(Duration::from_millis(115), "no response");
        drop(trace);
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, "(0000000000.000100) can0 60C#409C5F0000000000\n");
        let notes = std::fs::read_to_string(trace_notes_path(&path)).unwrap();
        assert_eq!(TraceHeader::read(notes.lines()), Some(header));
        assert!(
            notes.ends_with("    0.000000 -- drive `left`\n    0.115000 -- no response\n"),
            "{notes}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
