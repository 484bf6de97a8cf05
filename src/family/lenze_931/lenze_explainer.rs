//! Explains 931 lines for `decode`, `-v` and traces: the command or reply, the object
//! with its dictionary name, the value as signed 32-bit and hex, the error code's text,
//! and the status-word bits of `rs232_stat_sum`. A reply is read as an answer to the last
//! request seen.

use super::codec::{ErrorCode, ObjectCommand, Reply, Request};
use super::object_address::LenzeObject;
use crate::dictionary::Dictionary;
use crate::link::{Direction, ExplainError, TelegramExplainer};
use serde_json::json;
use std::sync::Arc;

/// The bits of the status word `rs232_stat_sum` (manual, p. 171).
pub const STATUS_BITS: &[(u32, &str)] = &[
    (0, "homing active"),
    (1, "home switch"),
    (2, "negative limit switch"),
    (3, "positive limit switch"),
    (4, "positioning completed"),
    (5, "target reached"),
    (6, "remaining path reached"),
    (8, "speed = message speed ± hysteresis"),
    (9, "speed = setpoint ± hysteresis"),
    (10, "positioning started"),
    (11, "i²t limiting"),
    (12, "SinCos encoder active"),
    (13, "speed = 0 ± hysteresis"),
    (14, "power stage switched on"),
    (15, "ready for operation"),
    (16, "warning"),
    (17, "group error"),
    (18, "negative direction inhibited"),
    (19, "positive direction inhibited"),
    (20, "homing completed"),
    (21, "automatic encoder adjustment"),
    (24, "internal enable of controller and power stage"),
    (27, "MOTID operation"),
];

/// `5 target reached, 14 power stage switched on`.
pub fn status_bits(word: u32) -> String {
    let set: Vec<String> = STATUS_BITS
        .iter()
        .filter(|(bit, _)| word & (1 << bit) != 0)
        .map(|(bit, name)| format!("{bit} {name}"))
        .collect();
    if set.is_empty() {
        "none of the documented bits".into()
    } else {
        set.join(", ")
    }
}

pub struct LenzeExplainer {
    dictionary: Arc<Dictionary>,
    last_request: Option<Request>,
}

impl LenzeExplainer {
    pub fn new(dictionary: Arc<Dictionary>) -> Self {
        LenzeExplainer {
            dictionary,
            last_request: None,
        }
    }

    fn name_of(&self, object: LenzeObject) -> Option<String> {
        let crate::dictionary::Address::Indexed { index, subindex } = object.address();
        let def = self.dictionary.by_address(index, subindex)?;
        Some(def.name.clone())
    }

    fn object_text(&self, number: u16) -> String {
        match self.name_of(LenzeObject::Communication(number)) {
            Some(name) => format!("0x{number:04X} {name}"),
            None => format!("0x{number:04X}"),
        }
    }

    fn is_status_word(&self, number: u16) -> bool {
        self.name_of(LenzeObject::Communication(number))
            .is_some_and(|n| n == "rs232_stat_sum")
    }

    /// Lines of the full explanation; the first is the summary.
    fn lines(&mut self, bytes: &[u8]) -> Result<Vec<String>, ExplainError> {
        let text = std::str::from_utf8(bytes)
            .map_err(|_| "not ASCII text: a 931 line is printable ASCII ended by CR".to_string())?;
        let line = text.trim_matches(|c| c == '\r' || c == '\n');
        if let Ok(request) = Request::parse(line) {
            let out = self.request_lines(&request);
            self.last_request = Some(request);
            return Ok(out);
        }
        let reply = match &self.last_request {
            Some(r) => Reply::parse_for(r, line),
            None => Reply::parse(line),
        }
        .map_err(|e| e.to_string())?;
        Ok(self.reply_lines(&reply))
    }

    fn request_lines(&self, request: &Request) -> Vec<String> {
        let mut out = vec![format!("request   {}", request.describe())];
        match *request {
            Request::Write { object, value } => {
                out[0] = format!("request   write object {}", self.object_text(object));
                out.push(format!("value     {} (0x{value:08X})", value as i32));
            }
            Request::Read { command, object } => {
                out[0] = format!(
                    "request   {} object {}",
                    command.describe(),
                    self.object_text(object)
                );
            }
            _ => {}
        }
        out
    }

    fn reply_lines(&self, reply: &Reply) -> Vec<String> {
        let asked = self.last_request.as_ref().and_then(Request::object_command);
        match reply {
            Reply::Ok => vec!["reply     OK!: written".into()],
            Reply::Value { object, value } => {
                let what = match asked {
                    Some((ObjectCommand::Internal, _)) => "internal value",
                    Some((ObjectCommand::Min, _)) => "minimum",
                    Some((ObjectCommand::Max, _)) => "maximum",
                    _ => "value",
                };
                let mut out = vec![
                    format!("reply     {what} of object {}", self.object_text(*object)),
                    format!("value     {} (0x{value:08X})", *value as i32),
                ];
                if self.is_status_word(*object) {
                    out.push(format!("status    {}", status_bits(*value)));
                }
                out
            }
            Reply::Error { command, code } => {
                let object = asked
                    .filter(|(c, _)| c == command)
                    .map(|(_, n)| format!(" object {}", self.object_text(n)))
                    .unwrap_or_default();
                let kind = if code.is_limited() {
                    "written but limited"
                } else {
                    "refused"
                };
                vec![
                    format!("reply     {} {kind}{object}", command.prefix()),
                    format!("error     {code}"),
                ]
            }
            Reply::Done => vec!["reply     DONE".into()],
            Reply::Type(t) => vec![format!("reply     device type {t}")],
            Reply::Version { status, version } => {
                vec![format!("reply     firmware version {version} (status {status})")]
            }
            Reply::Bus {
                status,
                node,
                baud,
                mode,
            } => vec![format!(
                "reply     CAN bus status {status}: node {node}, baud {baud}, mode {mode}"
            )],
            Reply::Boot(_) => vec![format!(
                "reply     {} (boot loader {})",
                reply.text(),
                if reply.text() == "SERVICE" {
                    "active"
                } else {
                    "not active"
                }
            )],
            Reply::Sdo {
                index,
                subindex,
                data,
            } => vec![format!(
                "reply     CANopen object 0x{index:04X} subindex {subindex} = {}",
                crate::hex::to_hex(data)
            )],
            Reply::UnknownCommand => vec!["reply     ERROR!: the drive does not know the command".into()],
            Reply::SwitchOn(t) => vec![format!("reply     switch-on message {t:?}")],
        }
    }
}

impl TelegramExplainer for LenzeExplainer {
    /// The line as text, then what it means: `OR:0011  read object 0x0011 speed_actual`.
    fn summary(&mut self, _direction: Direction, bytes: &[u8]) -> String {
        match self.lines(bytes) {
            Ok(lines) => {
                let meaning = lines
                    .iter()
                    .map(|l| {
                        l.split_once(' ')
                            .map_or(l.as_str(), |(_, rest)| rest.trim_start())
                    })
                    .collect::<Vec<_>>()
                    .join("; ");
                format!("{}  {meaning}", String::from_utf8_lossy(bytes).trim())
            }
            Err(e) => format!("rejected: {e}"),
        }
    }

    fn explain(&mut self, bytes: &[u8]) -> Result<String, ExplainError> {
        let line = String::from_utf8_lossy(bytes).trim().to_string();
        let lines = self.lines(bytes)?;
        let mut out = format!("  line      {line}\n");
        for l in lines {
            out.push_str(&format!("  {l}\n"));
        }
        Ok(out)
    }

    fn json(&mut self, bytes: &[u8]) -> (serde_json::Value, bool) {
        let line = String::from_utf8_lossy(bytes).trim().to_string();
        let request = Request::parse(&line).ok();
        match self.lines(bytes) {
            Err(e) => (json!({ "reject": e.reason }), false),
            Ok(lines) => {
                let mut v = json!({ "line": line, "explain": lines });
                if let Some(r) = request {
                    v["kind"] = json!("request");
                    if let Some((command, object)) = r.object_command() {
                        v["command"] = json!(command.prefix());
                        v["object"] = json!(format!("0x{object:04X}"));
                    }
                    if let Request::Write { value, .. } = r {
                        v["value"] = json!(value as i32);
                    }
                } else if let Ok(reply) = Reply::parse(&line) {
                    v["kind"] = json!("reply");
                    match reply {
                        Reply::Value { object, value } => {
                            v["object"] = json!(format!("0x{object:04X}"));
                            v["value"] = json!(value as i32);
                        }
                        Reply::Error { command, code } => {
                            v["command"] = json!(command.prefix());
                            v["error"] = json!(format!("0x{:08X}", code.0));
                            v["limited"] = json!(ErrorCode(code.0).is_limited());
                        }
                        _ => {}
                    }
                }
                (v, true)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn explainer() -> LenzeExplainer {
        LenzeExplainer::new(Arc::new(
            crate::family::Registry::builtin()
                .load_dictionary("lenze-931")
                .expect("the built-in dictionary"),
        ))
    }

    #[test]
    fn requests_and_replies_are_explained() {
        let mut x = explainer();
        let text = x.explain(b"OW:0010:FFFFF448\r").unwrap();
        assert!(text.contains("request   write object 0x0010"), "{text}");
        assert!(text.contains("value     -3000 (0xFFFFF448)"), "{text}");
        let text = x.explain(b"OW:0000 0005").unwrap();
        assert!(text.contains("OW written but limited object 0x0010"), "{text}");
        x.explain(b"OR:0011").unwrap();
        let text = x.explain(b"OW:00000005").unwrap();
        assert!(
            text.contains("OW written but limited\n"),
            "a write error does not answer a read: {text}"
        );
        assert!(
            text.contains("0x00000005 value too high, written but limited"),
            "{text}"
        );
        x.explain(b"OX:0010\r").unwrap();
        let text = x.explain(b"0010:00001770\r").unwrap();
        assert!(text.contains("maximum of object 0x0010"), "{text}");
        assert!(text.contains("6000 (0x00001770)"), "{text}");
        assert_eq!(
            x.summary(Direction::Received, b"ERROR!\r"),
            "ERROR!  ERROR!: the drive does not know the command"
        );
        assert!(x.explain(b"\xff\r").is_err());
        assert!(x.explain(b"HELLO").unwrap_err().reason.contains("unknown reply"));
    }

    #[test]
    fn json_has_the_fields() {
        let mut x = explainer();
        let (v, ok) = x.json(b"OR:0011");
        assert!(ok);
        assert_eq!(v["command"], "OR");
        assert_eq!(v["object"], "0x0011");
        let (v, _) = x.json(b"OR:0004 0000");
        assert_eq!(v["error"], "0x00040000");
        let (v, ok) = x.json(b"#?");
        assert!(!ok);
        assert!(v["reject"].is_string());
    }

    #[test]
    fn status_bits_are_named() {
        assert_eq!(
            status_bits(1 << 14 | 1 << 15),
            "14 power stage switched on, 15 ready for operation"
        );
        assert_eq!(status_bits(1 << 7), "none of the documented bits");
    }
}
