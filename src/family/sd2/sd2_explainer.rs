//! The SD2 family's [`TelegramExplainer`]: one line per telegram for traces and `-v`
//! (`read object 67 status_word`, `reply status_word = 0x0237 operation enabled`), and the
//! full explanation ([`explain`]: direction, addresses, command, object, data as numbers,
//! error text, control and status word bits) and vector JSON for `decode`. Objects are
//! named, values shown with units and states read with the dictionary's profile.
//! Formatting only; object names come from whoever implements [`ObjectNames`].

use super::codec::{switch_of, to_json, Body, Cyclic, Data, Telegram, WriteLength, MASTER_ADDRESS};
use super::object_names::ObjectNames;
use crate::drive::device_control::{control_word_bits, control_word_meaning, status_word_bits, DeviceState};
use crate::hex::to_hex;
use crate::link::{Direction, ExplainError, TelegramExplainer};
use std::fmt::Write as _;
use std::sync::Arc;

/// The names the explainer uses; a `crate::dictionary::Dictionary` in practice.
pub type Names = Arc<dyn ObjectNames + Send + Sync>;

pub struct Sd2Explainer {
    names: Names,
    /// The last request seen, so its reply can be read as the object it returns.
    last_request: Option<Telegram>,
}

impl Sd2Explainer {
    pub fn new(names: Names) -> Self {
        Sd2Explainer {
            names,
            last_request: None,
        }
    }

    /// The request `t` answers, if it is a reply; remembers `t` if it is a request.
    fn context(&mut self, t: &Telegram) -> Option<Telegram> {
        if t.is_reply() {
            self.last_request
        } else {
            self.last_request = Some(*t);
            None
        }
    }
}

impl TelegramExplainer for Sd2Explainer {
    fn summary(&mut self, _direction: Direction, bytes: &[u8]) -> String {
        match Telegram::decode(bytes) {
            Ok(t) => {
                let request = self.context(&t);
                summary(&t, request.as_ref(), self.names.as_ref())
            }
            Err(e) => format!("rejected: {}", e.reason()),
        }
    }

    fn explain(&mut self, bytes: &[u8]) -> Result<String, ExplainError> {
        let t = Telegram::decode(bytes).map_err(|e| e.to_string())?;
        let request = self.context(&t);
        Ok(explain(&t, bytes, request.as_ref(), self.names.as_ref()))
    }

    fn json(&mut self, bytes: &[u8]) -> (serde_json::Value, bool) {
        let decoded = Telegram::decode(bytes);
        let ok = decoded.is_ok();
        if let Ok(t) = &decoded {
            self.context(t);
        }
        (to_json(&decoded), ok)
    }
}

/// One line saying what a telegram means: `read object 67 status_word`,
/// `reply status_word = 0x0237 operation enabled`, `write reply ok`. `request` is the
/// request a reply answers, when known.
fn summary(t: &Telegram, request: Option<&Telegram>, names: &dyn ObjectNames) -> String {
    match &t.body {
        Body::ReadRequest { index, subindex } => {
            format!("read object {}", object(names, *index, *subindex))
        }
        Body::WriteRequest {
            index,
            subindex,
            data,
        } => format!(
            "write object {} = {}",
            object(names, *index, *subindex),
            value(names, Some((*index, *subindex)), data)
        ),
        Body::ReadReply { error, data } => {
            if !error.is_ok() {
                return format!("read reply {error}");
            }
            match request.map(|r| r.body) {
                Some(Body::ReadRequest { index, subindex }) => format!(
                    "reply {} = {}",
                    short_name(names, index, subindex).unwrap_or_else(|| format!("object {index}")),
                    value(names, Some((index, subindex)), data)
                ),
                _ => format!("reply {} (request not seen)", value(names, None, data)),
            }
        }
        Body::WriteReply { error } if error.is_ok() => "write reply ok".into(),
        Body::WriteReply { error } => format!("write reply {error}"),
        Body::CyclicRequest(c) => cyclic(c, false, names),
        Body::CyclicReply(c) => cyclic(c, true, names),
    }
}

/// `67 status_word`, `67/1 name`, `9999 (not in the dictionary)`.
fn object(names: &dyn ObjectNames, index: u16, subindex: u32) -> String {
    let address = if subindex == 0 {
        index.to_string()
    } else {
        format!("{index}/{subindex}")
    };
    match short_name(names, index, subindex) {
        Some(name) => format!("{address} {name}"),
        None => format!("{address} (not in the dictionary)"),
    }
}

/// The object's name without its alias: `speed_actual`.
fn short_name(names: &dyn ObjectNames, index: u16, subindex: u32) -> Option<String> {
    let full = names.object_name(index, subindex)?;
    Some(full.split(" (").next().unwrap_or(&full).to_string())
}

fn value(names: &dyn ObjectNames, addr: Option<(u16, u32)>, data: &Data) -> String {
    let bytes = data.as_slice();
    let word = match bytes {
        [lo, hi] => Some(u16::from_le_bytes([*lo, *hi])),
        _ => None,
    };
    let mut text = addr
        .and_then(|(i, sub)| names.object_value(i, sub, bytes))
        .unwrap_or_else(|| raw_value(bytes));
    if let (Some((index, _)), Some(w)) = (addr, word) {
        if names.is_status_word(index) {
            let _ = write!(text, " {}", state_text(names, w));
        } else if names.is_control_word(index) {
            let _ = write!(text, " {}", control_word_meaning(w));
        }
    }
    text
}

fn raw_value(bytes: &[u8]) -> String {
    match bytes {
        [] => "no data".into(),
        [b] => format!("{b}"),
        [a, b] => format!("{}", u16::from_le_bytes([*a, *b])),
        [a, b, c, d] => format!("{}", i32::from_le_bytes([*a, *b, *c, *d])),
        _ => format!("{} bytes", bytes.len()),
    }
}

fn state_text(names: &dyn ObjectNames, status: u16) -> String {
    names
        .state_of(status)
        .unwrap_or_else(|| "(no state matches)".into())
}

fn cyclic(c: &Cyclic, reply: bool, names: &dyn ObjectNames) -> String {
    let w = c.word();
    let mut s = if reply {
        format!(
            "cyclic reply status 0x{w:04x} {}, speed {:.1} %, drive error {}, current {}",
            state_text(names, w),
            c.speed_percent(),
            c.drive_error(),
            c.current()
        )
    } else {
        format!(
            "cyclic control 0x{w:04x} {}, speed {:.1} %",
            control_word_meaning(w),
            c.speed_percent()
        )
    };
    if let Some(svc) = &c.service {
        let what = if reply {
            "service reply".to_string()
        } else {
            format!("service {}", svc.function().id().replace('_', " "))
        };
        let _ = write!(
            s,
            "; {what} object {} = {}",
            object(names, svc.index, 0),
            svc.value()
        );
    }
    s
}

/// Explains `bytes` (already decoded into `telegram`). `request` is the request this
/// telegram answers, when known, so a read reply can be read as the object it returns.
pub fn explain(
    telegram: &Telegram,
    bytes: &[u8],
    request: Option<&Telegram>,
    names: &dyn ObjectNames,
) -> String {
    let mut s = String::new();
    let t = telegram;
    let (direction, what) = match t.body {
        Body::ReadRequest { .. } | Body::ReadReply { .. } => (t.is_reply(), "read wide object"),
        Body::WriteRequest { .. } | Body::WriteReply { .. } => (t.is_reply(), "write wide object"),
        Body::CyclicRequest(_) | Body::CyclicReply(_) => (t.is_reply(), "DNC 8-byte cyclic telegram"),
    };
    let kind = if direction { "reply" } else { "request" };
    line(
        &mut s,
        kind,
        format!(
            "{what} (cmd 0x{:02x}), {} → {}",
            t.command(),
            party(t.source),
            party(t.dest)
        ),
    );

    match &t.body {
        Body::ReadRequest { index, subindex } => {
            line(&mut s, "object", object_full(names, *index, *subindex));
        }
        Body::WriteRequest {
            index,
            subindex,
            data,
        } => {
            line(&mut s, "object", object_full(names, *index, *subindex));
            line(&mut s, "data", data_text(names, Some((*index, *subindex)), data));
            if names.is_control_word(*index) {
                if let Some(cw) = word(data) {
                    line(&mut s, "control", control_text(cw));
                }
            }
            if let Some(&len) = bytes.get(1) {
                let formula = WriteLength::Formula.field(data.len());
                let how = if len == WriteLength::Captured.field(data.len()) && len != formula {
                    format!("as captured from real drives (the manual's formula gives 0x{formula:02x})")
                } else {
                    "the manual's formula, 10 + count".to_string()
                };
                line(&mut s, "length", format!("0x{len:02x} {how}"));
            }
        }
        Body::ReadReply { error, data } => {
            line(&mut s, "error", error.to_string());
            let addr = match request.map(|r| r.body) {
                Some(Body::ReadRequest { index, subindex }) => Some((index, subindex)),
                _ => None,
            };
            if let Some((index, subindex)) = addr {
                line(&mut s, "object", object_full(names, index, subindex));
            }
            if !data.is_empty() {
                line(&mut s, "data", data_text(names, addr, data));
                if let (Some((index, _)), Some(sw)) = (addr, word(data)) {
                    if names.is_status_word(index) {
                        line(&mut s, "status", status_text(sw));
                    }
                }
            }
        }
        Body::WriteReply { error } => line(&mut s, "error", error.to_string()),
        Body::CyclicRequest(c) => cyclic_text(&mut s, c, false, names),
        Body::CyclicReply(c) => cyclic_text(&mut s, c, true, names),
    }
    if let Some(&check) = bytes.last() {
        line(&mut s, "check", format!("0x{check:02x} ok"));
    }
    s
}

fn line(s: &mut String, label: &str, text: String) {
    let _ = writeln!(s, "  {label:<9} {text}");
}

fn party(address: u8) -> String {
    if address <= MASTER_ADDRESS {
        return format!("PC ({address})");
    }
    match switch_of(address) {
        Some((switch, letter)) => format!("drive {address} (switch {switch}, drive {letter})"),
        None => format!("drive {address}"),
    }
}

fn object_full(names: &dyn ObjectNames, index: u16, subindex: u32) -> String {
    let name = names
        .object_name(index, subindex)
        .map(|n| format!(" {n}"))
        .unwrap_or_else(|| " (not in the dictionary)".into());
    format!("{index} (0x{index:04x}){name}, subindex {subindex}")
}

fn word(data: &Data) -> Option<u16> {
    match data.as_slice() {
        [lo, hi] => Some(u16::from_le_bytes([*lo, *hi])),
        _ => None,
    }
}

fn data_text(names: &dyn ObjectNames, addr: Option<(u16, u32)>, data: &Data) -> String {
    let bytes = data.as_slice();
    let mut text = format!(
        "{} ({} byte{})",
        to_hex(bytes),
        bytes.len(),
        if bytes.len() == 1 { "" } else { "s" }
    );
    if let Some(value) = addr.and_then(|(i, sub)| names.object_value(i, sub, bytes)) {
        let _ = write!(text, " = {value}");
        return text;
    }
    match bytes {
        [b] => {
            let _ = write!(text, " = {b} (u8)");
        }
        [a, b] => {
            let u = u16::from_le_bytes([*a, *b]);
            let _ = write!(text, " = {u} (u16), {} (i16)", u as i16);
        }
        [a, b, c, d] => {
            let u = u32::from_le_bytes([*a, *b, *c, *d]);
            let _ = write!(text, " = {} (i32), {u} (u32)", u as i32);
        }
        _ => {}
    }
    if let Some(string) = as_string(bytes) {
        let _ = write!(text, " = \"{string}\" (string)");
    }
    text
}

/// SD2 strings: data[0] is the maximum length, then the characters, NUL-terminated when
/// shorter than the maximum.
pub(crate) fn as_string(bytes: &[u8]) -> Option<String> {
    let (&max, rest) = bytes.split_first()?;
    if rest.is_empty() || usize::from(max) < rest.iter().take_while(|&&b| b != 0).count() {
        return None;
    }
    let text: Vec<u8> = rest.iter().copied().take_while(|&b| b != 0).collect();
    if text.is_empty() || !text.iter().all(|b| b.is_ascii_graphic() || *b == b' ') {
        return None;
    }
    String::from_utf8(text).ok()
}

fn control_text(cw: u16) -> String {
    format!(
        "{cw}: {} (bits set: {})",
        control_word_meaning(cw),
        list(control_word_bits(cw))
    )
}

fn status_text(sw: u16) -> String {
    let state = DeviceState::from_status_word(sw)
        .map(|s| s.to_string())
        .unwrap_or_else(|| "no state of the table matches".into());
    format!("0x{sw:04x}: {state} (bits set: {})", list(status_word_bits(sw)))
}

fn list(items: Vec<String>) -> String {
    if items.is_empty() {
        "none".into()
    } else {
        items.join(", ")
    }
}

fn cyclic_text(s: &mut String, c: &Cyclic, reply: bool, names: &dyn ObjectNames) {
    let toggle = if c.toggle() {
        "heartbeat toggle set"
    } else {
        "heartbeat toggle clear"
    };
    line(s, "header", format!("{} ({toggle})", to_hex(&c.header)));
    if reply {
        line(s, "status", status_text(c.word()));
        line(
            s,
            "speed",
            format!(
                "{} = {:.1} % of the velocity scaling (actual)",
                c.speed(),
                c.speed_percent()
            ),
        );
        line(s, "error", format!("drive error {}", c.drive_error()));
        line(s, "current", format!("{} (drive scaling)", c.current()));
    } else {
        line(s, "control", control_text(c.word()));
        line(
            s,
            "speed",
            format!(
                "{} = {:.1} % of the velocity scaling (reference)",
                c.speed(),
                c.speed_percent()
            ),
        );
    }
    if let Some(svc) = &c.service {
        let head = if reply {
            format!("state 0x{:02x}", svc.ctrl)
        } else {
            format!(
                "ctrl 0x{:02x}: {} object, toggle {}, {} valid byte{}",
                svc.ctrl,
                svc.function().id().replace('_', " "),
                u8::from(svc.toggle()),
                svc.valid_bytes(),
                if svc.valid_bytes() == 1 { "" } else { "s" }
            )
        };
        let reserved = if svc.reserved != 0 {
            format!(" (reserved byte 0x{:02x} is not zero)", svc.reserved)
        } else {
            String::new()
        };
        line(s, "service", format!("{head}{reserved}"));
        line(s, "object", object_full(names, svc.index, 0));
        line(s, "data", format!("{} = {}", to_hex(&svc.data), svc.value()));
    }
}

#[cfg(test)]
#[path = "sd2_explainer_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "sd2_explanation_tests.rs"]
mod explanation_tests;
