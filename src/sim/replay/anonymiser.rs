//! A copy of a capture to share: every string the drive gave in a reply (its ident,
//! serial number, product name: what the family's explainer quotes) is masked, letters
//! as `X` and digits as `0`, keeping its length, and the telegram's check bytes are
//! recomputed by the family, so the copy still replays. Requests stay as they are (a
//! replay matches them byte for byte); comments get the same masks. Streams line by line.

use super::capture_reader::parse_line;
use super::{CaptureError, Classifier};
use crate::bus::CanFrame;
use crate::link::{Direction, TelegramExplainer};
use std::io::{BufRead, Write};
use std::path::Path;

/// How many distinct strings are remembered for masking comments.
const REMEMBERED: usize = 1024;

/// Recomputes a telegram's check bytes after its data changed.
pub type Resealer = Box<dyn Fn(&mut [u8]) + Send>;

pub struct Anonymiser {
    explainer: Box<dyn TelegramExplainer>,
    reseal: Resealer,
    classify: Classifier,
    /// Each string masked and its mask, for the comments and notes.
    masks: Vec<(String, String)>,
}

/// Why a copy stopped: the capture could not be read, or the copy could not be written
/// (the caller knows where the copy goes and names it).
#[derive(Debug, thiserror::Error)]
pub enum CopyError {
    #[error(transparent)]
    Capture(#[from] CaptureError),
    #[error("{0}")]
    Write(std::io::Error),
}

/// What an anonymised copy holds.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Anonymised {
    pub telegrams: u64,
    pub masked: u64,
}

impl Anonymiser {
    pub fn new(explainer: Box<dyn TelegramExplainer>, reseal: Resealer, classify: Classifier) -> Self {
        Anonymiser {
            explainer,
            reseal,
            classify,
            masks: Vec::new(),
        }
    }

    /// Copies the capture `input` (named `file` in errors) to `out`, masked.
    pub fn copy(
        &mut self,
        input: impl BufRead,
        file: &Path,
        out: &mut dyn Write,
    ) -> Result<Anonymised, CopyError> {
        let mut done = Anonymised::default();
        for (number, line) in input.split(b'\n').enumerate() {
            let line = line.map_err(|e| CaptureError::Unreadable {
                file: file.to_path_buf(),
                detail: e.to_string(),
            })?;
            let text = String::from_utf8_lossy(&line);
            let text = text.trim_end_matches('\r');
            let parsed = parse_line(text).map_err(|what| CaptureError::Line {
                file: file.to_path_buf(),
                line: number as u64 + 1,
                what,
            })?;
            let copied = match parsed {
                Some((_, direction, bytes, frame)) => {
                    done.telegrams += 1;
                    let reply = direction.or_else(|| (self.classify)(&bytes)) == Some(Direction::Received);
                    match self.masked(&bytes, frame).filter(|_| reply) {
                        Some(masked) => {
                            done.masked += 1;
                            self.rewritten(text, &masked, frame)
                        }
                        None => text.to_string(),
                    }
                }
                None => self.mask_text(text),
            };
            writeln!(out, "{copied}").map_err(CopyError::Write)?;
        }
        out.flush().map_err(CopyError::Write)?;
        Ok(done)
    }

    /// `text` with every string masked so far replaced by its mask.
    pub fn mask_text(&self, text: &str) -> String {
        self.masks
            .iter()
            .fold(text.to_string(), |t, (from, to)| t.replace(from.as_str(), to))
    }

    /// The telegram with the strings its meaning quotes masked; `None` when it has none.
    fn masked(&mut self, bytes: &[u8], frame: bool) -> Option<Vec<u8>> {
        let meaning = self.explainer.summary(Direction::Received, bytes);
        // A frame's data follows its 4 bytes of identifier.
        let data_from = if frame { 4 } else { 0 };
        let mut out = bytes.to_vec();
        let mut changed = false;
        for quoted in meaning.split('"').skip(1).step_by(2).filter(|q| !q.is_empty()) {
            let Some(at) = find(&out[data_from..], quoted.as_bytes()) else {
                continue;
            };
            let mask = mask(quoted);
            out[data_from + at..data_from + at + quoted.len()].copy_from_slice(mask.as_bytes());
            changed |= mask != quoted;
            if self.masks.len() < REMEMBERED
                && quoted.trim().len() >= 4
                && !self.masks.iter().any(|(f, _)| f == quoted)
            {
                self.masks.push((quoted.to_string(), mask));
            }
        }
        if !changed {
            return None;
        }
        (self.reseal)(&mut out[data_from..]);
        Some(out)
    }

    /// The capture line `text` carrying `bytes` instead, its meaning read anew.
    fn rewritten(&mut self, text: &str, bytes: &[u8], frame: bool) -> String {
        let body = text.split_once(" #").map_or(text, |(b, _)| b);
        let meaning = text.contains(" #").then(|| {
            self.explainer
                .summary(Direction::Received, bytes)
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
        });
        let mut line = if frame {
            // `(TIME) IF ID#DATA [T|R]`: only the frame changes.
            let mut tokens: Vec<String> = body.split_whitespace().map(str::to_string).collect();
            if let (Some(slot), Some(f)) = (tokens.get_mut(2), CanFrame::from_bytes(bytes)) {
                *slot = f.to_candump();
            }
            tokens.join(" ")
        } else {
            // `  SECONDS RX HEX`: the time as it was written.
            let indent = &body[..body.len() - body.trim_start().len()];
            let time = body.split_whitespace().next().unwrap_or("");
            format!("{indent}{time} RX {}", crate::hex::to_hex(bytes))
        };
        if let Some(m) = meaning {
            line.push_str(&format!("  # {m}"));
        }
        line
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// Letters become `X`, digits `0`; the rest stays, so the shape and length are kept.
fn mask(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            c if c.is_ascii_alphabetic() => 'X',
            c if c.is_ascii_digit() => '0',
            c => c,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quotes the printable bytes after the first two, as an explainer quotes a string.
    struct Quoting;
    impl TelegramExplainer for Quoting {
        fn summary(&mut self, _: Direction, bytes: &[u8]) -> String {
            format!(
                "reply ident = \"{}\"",
                String::from_utf8_lossy(&bytes[2..bytes.len() - 1])
            )
        }
        fn explain(&mut self, _: &[u8]) -> Result<String, crate::link::ExplainError> {
            Err(String::from("not used").into())
        }
        fn json(&mut self, _: &[u8]) -> (serde_json::Value, bool) {
            (serde_json::Value::Null, false)
        }
    }

    #[test]
    fn replies_quoting_a_string_are_masked_and_resealed_requests_and_the_rest_kept() {
        // Telegrams: 2 header bytes, the string, a sum check byte.
        let reseal: Resealer = Box::new(|t: &mut [u8]| {
            let last = t.len() - 1;
            t[last] = t[..last].iter().fold(0u8, |s, b| s.wrapping_add(*b));
        });
        let mut a = Anonymiser::new(Box::new(Quoting), reseal, Box::new(|_| None));
        let hex = crate::hex::to_hex;
        let reply = [&[0xAA, 0x01][..], b"SN-42x", &[0x00]].concat();
        let text = format!(
            "# drive: sd2\n    0.000000 TX {}  # read\n    0.000100 RX {}  # reply ident = \"SN-42x\"\n    0.2 -- drive SN-42x answered\n",
            hex(&reply),
            hex(&reply)
        );
        let mut out = Vec::new();
        let done = a.copy(text.as_bytes(), Path::new("c"), &mut out).unwrap();
        assert_eq!(
            done,
            Anonymised {
                telegrams: 2,
                masked: 1
            }
        );
        let out = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[1], format!("    0.000000 TX {}  # read", hex(&reply)));
        let mut masked = [&[0xAA, 0x01][..], b"XX-00X", &[0]].concat();
        let last = masked.len() - 1;
        masked[last] = masked[..last].iter().fold(0u8, |s, b| s.wrapping_add(*b));
        assert_eq!(
            lines[2],
            format!("    0.000100 RX {}  # reply ident = \"XX-00X\"", hex(&masked))
        );
        assert_eq!(lines[3], "    0.2 -- drive XX-00X answered");
    }

    #[test]
    fn a_bad_line_is_named() {
        let mut a = Anonymiser::new(Box::new(Quoting), Box::new(|_| {}), Box::new(|_| None));
        let e = a
            .copy(&b"# x\nnonsense\n"[..], Path::new("c.trace"), &mut Vec::new())
            .unwrap_err();
        assert!(e.to_string().starts_with("c.trace:2: "), "{e}");
    }
}
