//! A telegram explained as a commissioning engineer reads it: direction, addresses,
//! command, object, data as numbers, error text, control and status word bits.
//! Pure text formatting; object names come from whoever implements [`ObjectNames`].

use super::codec::{switch_of, Body, Cyclic, Data, Telegram, WriteLength, MASTER_ADDRESS};
use crate::drive::device_control::{control_word_bits, control_word_meaning, status_word_bits, DeviceState};
use crate::hex::to_hex;
use std::fmt::Write as _;

/// What the explainer needs to know about objects (a dictionary, or nothing).
pub trait ObjectNames {
    /// A readable name for the object, e.g. `control_word (DEV_CTRL_CONTROL_WORD)`.
    fn object_name(&self, index: u16, subindex: u32) -> Option<String>;
    /// The object's value with its unit, e.g. `1003.647 rpm`, from its raw bytes.
    fn object_value(&self, index: u16, subindex: u32, data: &[u8]) -> Option<String>;
    /// True for the device-control control word.
    fn is_control_word(&self, index: u16) -> bool;
    /// True for the device-control status word.
    fn is_status_word(&self, index: u16) -> bool;
    /// The state a status word shows under the dictionary's profile.
    fn state_of(&self, status: u16) -> Option<String>;
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
            line(&mut s, "object", object(names, *index, *subindex));
        }
        Body::WriteRequest {
            index,
            subindex,
            data,
        } => {
            line(&mut s, "object", object(names, *index, *subindex));
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
                line(&mut s, "object", object(names, index, subindex));
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

fn object(names: &dyn ObjectNames, index: u16, subindex: u32) -> String {
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
        line(s, "object", object(names, svc.index, 0));
        line(s, "data", format!("{} = {}", to_hex(&svc.data), svc.value()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoNames;
    impl ObjectNames for NoNames {
        fn object_name(&self, _: u16, _: u32) -> Option<String> {
            None
        }
        fn object_value(&self, _: u16, _: u32, _: &[u8]) -> Option<String> {
            None
        }
        fn is_control_word(&self, index: u16) -> bool {
            index == 68
        }
        fn is_status_word(&self, index: u16) -> bool {
            index == 67
        }
        fn state_of(&self, status: u16) -> Option<String> {
            crate::drive::DeviceState::from_status_word(status).map(|s| s.to_string())
        }
    }

    fn explain_hex(hex: &str, request: Option<&Telegram>) -> String {
        let bytes = crate::hex::parse_hex(hex).unwrap();
        let t = Telegram::decode(&bytes).unwrap();
        explain(&t, &bytes, request, &NoNames)
    }

    #[test]
    fn write_of_the_control_word() {
        let text = explain_hex("00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 97", None);
        assert!(
            text.contains("request   write wide object (cmd 0x0e), PC (1) → drive 2 (switch 0, drive A)"),
            "{text}"
        );
        assert!(text.contains("68 (0x0044)"));
        assert!(text.contains("06 00 (2 bytes) = 6 (u16)"));
        assert!(text.contains("control   6: shutdown (bits set: 1 enable voltage, 2 quick stop off)"));
        assert!(text.contains("0x0b as captured from real drives (the manual's formula gives 0x0c)"));
        assert!(text.contains("check     0x97 ok"));
    }

    #[test]
    fn read_reply_in_the_context_of_its_request() {
        let req = Telegram::read_request(2, 1, 67, 0);
        let bytes = Telegram {
            dest: 1,
            source: 2,
            body: Body::ReadReply {
                error: super::super::codec::ErrorCode::OK,
                data: Data::new(&[0x37, 0x02]).unwrap(),
            },
        }
        .encode(WriteLength::Captured);
        let text = explain_hex(&to_hex(&bytes), Some(&req));
        assert!(text.contains("status    0x0237: operation enabled"), "{text}");
        let text = explain_hex("00 09 01 02 8d 04 00 7f 50 0f 00 84", None);
        assert!(text.contains("= 1003647 (i32)"), "{text}");
        assert!(text.contains("error     0x00 no error"));
    }

    #[test]
    fn cyclic_with_service_channel() {
        let text = explain_hex(
            "00 15 02 01 10 05 00 06 00 ff 0f 00 00 00 00 00 0d 60 01 01 00 00 00 4f",
            None,
        );
        assert!(text.contains("heartbeat toggle set"), "{text}");
        assert!(
            text.contains("ctrl 0x0d: write object, toggle 1, 2 valid bytes"),
            "{text}"
        );
        assert!(text.contains("352 (0x0160)"));
        assert!(text.contains("4095 = 25.0 %"));
    }

    #[test]
    fn strings_are_recognised() {
        assert_eq!(as_string(b"\x20Test Motor\0\0"), Some("Test Motor".into()));
        assert_eq!(as_string(&[0x04, 0x40, 0x42, 0x0f]), None);
        assert_eq!(as_string(&[2]), None);
    }
}
