//! What a `--trace` records about the run it traces — the drive (built-in dictionary) and
//! dictionary files its telegrams are explained with, the address and the line — as `#`
//! lines `decode` reads back, so a trace explains itself without flags. Holds text only:
//! must not load dictionaries or name a family.

use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TraceHeader {
    /// The built-in dictionary, as `--drive` takes it (`ct-unidrive-sp`).
    pub drive: String,
    /// The `--dictionary` files merged into it.
    pub dictionaries: Vec<PathBuf>,
    /// The drive's address as the family shows it (for the reader; `decode` needs none).
    pub address: String,
    /// The line: port and its settings, CAN bus, or the simulated drive; timeouts, options.
    pub line: String,
    /// The motor's pole pairs an inverter's rpm were shown for, so `decode` shows the
    /// same rpm; `None` for a dictionary without them.
    pub pole_pairs: Option<u32>,
}

const DRIVE: &str = "drive: ";
const DICTIONARY: &str = "dictionary: ";
const ADDRESS: &str = "address: ";
const LINE: &str = "line: ";
const POLE_PAIRS: &str = "pole pairs: ";

/// The file next to a CAN trace that holds its header and link events: a candump log
/// must hold frames only, or python-can's reader stops at the first other line.
pub fn trace_notes_path(trace: &Path) -> PathBuf {
    let mut name = trace.as_os_str().to_os_string();
    name.push(".meta");
    PathBuf::from(name)
}

impl TraceHeader {
    /// The header's lines, without their `# `.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![format!("{DRIVE}{}", self.drive)];
        lines.extend(
            self.dictionaries
                .iter()
                .map(|d| format!("{DICTIONARY}{}", d.display())),
        );
        lines.push(format!("{ADDRESS}{}", self.address));
        lines.push(format!("{LINE}{}", self.line));
        lines.extend(self.pole_pairs.map(|n| format!("{POLE_PAIRS}{n}")));
        lines
    }

    /// The header at the top of a trace (its leading `#` lines), when it has one.
    pub fn read<'a>(lines: impl IntoIterator<Item = &'a str>) -> Option<TraceHeader> {
        let mut header = TraceHeader::default();
        for line in lines {
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            let Some(comment) = line.strip_prefix('#') else {
                break;
            };
            let comment = comment.trim();
            if let Some(drive) = comment.strip_prefix(DRIVE) {
                header.drive = drive.trim().to_string();
            } else if let Some(path) = comment.strip_prefix(DICTIONARY) {
                header.dictionaries.push(PathBuf::from(path.trim()));
            } else if let Some(address) = comment.strip_prefix(ADDRESS) {
                header.address = address.trim().to_string();
            } else if let Some(text) = comment.strip_prefix(LINE) {
                header.line = text.trim().to_string();
            } else if let Some(n) = comment.strip_prefix(POLE_PAIRS) {
                header.pole_pairs = n.trim().parse().ok();
            }
        }
        (!header.drive.is_empty()).then_some(header)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_reads_back_what_it_wrote_and_stops_at_the_first_telegram() {
        let header = TraceHeader {
            drive: "ct-unidrive-sp".into(),
            dictionaries: vec![PathBuf::from("/bench/extra.yaml")],
            address: "1.1".into(),
            line: "serial /dev/ttyUSB0, 4800 7E1".into(),
            pole_pairs: Some(2),
        };
        let mut text: Vec<String> = vec!["# drivescript telegram trace".into()];
        text.extend(header.lines().iter().map(|l| format!("# {l}")));
        text.push("    0.000100 TX 04 31  # read".into());
        text.push("# drive: sd2".into());
        assert_eq!(TraceHeader::read(text.iter().map(String::as_str)), Some(header));
        assert_eq!(TraceHeader::read(["# a comment", "00 0b 02"]), None);
        assert_eq!(
            trace_notes_path(Path::new("out/run.log")),
            PathBuf::from("out/run.log.meta")
        );
    }
}
