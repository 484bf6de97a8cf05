//! What Control Techniques messages mean, for `decode`, `-v` and traces: control
//! characters by name, the drive address, the parameter with its dictionary name, the
//! value exactly as sent (with its unit, and the state for the status word). The same byte
//! means different things from the master and from the drive, so a message of unknown
//! direction says both. Formatting only.

use super::codec::{
    show_bytes, DataValue, NodeAddress, Parameter, Reply, Request, ACK, BS, EOT, ETX, NAK, STX,
};
use crate::dictionary::{Dictionary, Role};
use crate::link::{Direction, ExplainError, TelegramExplainer};
use serde_json::{json, Value};
use std::sync::Arc;

pub struct CtExplainer {
    dictionary: Arc<Dictionary>,
}

impl CtExplainer {
    pub fn new(dictionary: Arc<Dictionary>) -> Self {
        CtExplainer { dictionary }
    }

    /// `#1.21 speed_setpoint`, or `#1.21` for a parameter the dictionary lacks.
    fn name(&self, p: Parameter) -> String {
        match self.dictionary.by_address(u16::from(p.menu), u32::from(p.param)) {
            Some(o) => format!("{p} {}", o.name),
            None => p.to_string(),
        }
    }

    /// `1500.5 rpm`; for the status word also its bits and the state it shows.
    fn value(&self, p: Parameter, v: DataValue) -> String {
        let object = self.dictionary.by_address(u16::from(p.menu), u32::from(p.param));
        let unit = object
            .and_then(|o| o.unit)
            .map(|u| format!(" {u}"))
            .unwrap_or_default();
        let mut text = format!("{v}{unit}");
        let is_status = object.is_some_and(|o| {
            self.dictionary
                .role(Role::StatusWord)
                .is_some_and(|s| s.name == o.name)
        });
        if let (true, Ok(word), 0) = (is_status, u16::try_from(v.digits), v.places) {
            let state = self
                .dictionary
                .profile()
                .and_then(|pr| pr.state_of(word))
                .map_or_else(|| "no state of the profile".to_string(), |s| s.to_string());
            text = format!("{text} (0x{word:04x}: {state})");
        }
        text
    }

    fn request(&self, r: &Request) -> String {
        match *r {
            Request::Read { address, parameter } => {
                format!("read {} of {}", self.name(parameter), address.describe())
            }
            Request::Write {
                address,
                parameter,
                value,
            } => {
                let to = match address {
                    Some(a) if a.is_broadcast() => format!("{} (no reply)", a.describe()),
                    Some(a) => a.describe(),
                    None => "the drive addressed last (rewrite)".to_string(),
                };
                format!(
                    "write {} = {} to {to}",
                    self.name(parameter),
                    self.value(parameter, value)
                )
            }
            Request::ReadAgain => "NAK: read the same parameter again".into(),
            Request::ReadNext => "ACK: read the next parameter".into(),
            Request::ReadPrevious => "BS: read the previous parameter".into(),
        }
    }

    fn reply(&self, r: &Reply) -> String {
        match *r {
            Reply::Value { parameter, value } => {
                format!("{} = {}", self.name(parameter), self.value(parameter, value))
            }
            Reply::Accepted => "ACK: write accepted".into(),
            Reply::Refused => {
                "NAK: write refused (out of range, invalid, read-only, unknown parameter or damaged message)"
                    .into()
            }
            Reply::NoSuchParameter => "EOT: no such parameter".into(),
        }
    }
}

/// Which way to read bytes whose direction is not known: requests start with EOT and an
/// address (or are BS); a single ACK, NAK or EOT and data blocks are read as replies.
fn looks_like_request(bytes: &[u8]) -> bool {
    matches!(bytes, [EOT, _, ..] | [BS])
}

/// A line saying the value was written in hex (`X83`), for a well-formed message whose
/// data field is `X` + hex digits; empty otherwise.
fn hex_note(bytes: &[u8]) -> String {
    let Some(stx) = bytes.iter().position(|b| *b == STX) else {
        return String::new();
    };
    let field = bytes.get(stx + 5..).unwrap_or_default();
    let field = &field[..field.iter().position(|b| *b == ETX).unwrap_or(field.len())];
    let text = String::from_utf8_lossy(field);
    if text.trim_start().starts_with('X') {
        format!(
            "  data      `{}`: hexadecimal (older drives accept it in writes; drivescript writes decimal)\n",
            text.trim_start()
        )
    } else {
        String::new()
    }
}

fn address_json(a: NodeAddress) -> String {
    a.to_string()
}

impl TelegramExplainer for CtExplainer {
    fn summary(&mut self, direction: Direction, bytes: &[u8]) -> String {
        let text = match direction {
            Direction::Sent => Request::decode(bytes).map(|r| self.request(&r)),
            Direction::Received => Reply::decode(bytes).map(|r| match r {
                Reply::Value { .. } => format!("reply {}", self.reply(&r)),
                _ => self.reply(&r),
            }),
        };
        text.unwrap_or_else(|e| format!("rejected: {e}"))
    }

    fn explain(&mut self, bytes: &[u8]) -> Result<String, ExplainError> {
        let shown = show_bytes(bytes);
        let rejected = |e: super::codec::DecodeError| format!("{e}, in `{shown}`");
        let mut out = format!("  message   {shown}\n");
        if looks_like_request(bytes) {
            let r = Request::decode(bytes).map_err(rejected)?;
            out.push_str(&format!("  request   {}\n", self.request(&r)));
            out.push_str(&hex_note(bytes));
            return Ok(out);
        }
        let r = Reply::decode(bytes).map_err(rejected)?;
        out.push_str(&format!("  reply     {}\n", self.reply(&r)));
        out.push_str(&hex_note(bytes));
        let master = match bytes.first() {
            Some(&ACK) => Some("from the master: read the next parameter"),
            Some(&NAK) => Some("from the master: read the same parameter again"),
            Some(&EOT) => Some("from the master: restart (abort the message under way)"),
            Some(&STX) => Some("from the master: the same write without address (rewrite)"),
            _ => None,
        };
        if let Some(m) = master {
            out.push_str(&format!("  or        {m}\n"));
        }
        Ok(out)
    }

    fn json(&mut self, bytes: &[u8]) -> (Value, bool) {
        let frame = if looks_like_request(bytes) {
            Request::decode(bytes).map(|r| match r {
                Request::Read { address, parameter } => json!({
                    "request": "read", "address": address_json(address), "parameter": parameter.dotted()
                }),
                Request::Write {
                    address,
                    parameter,
                    value,
                } => {
                    let mut v = json!({
                        "request": "write", "parameter": parameter.dotted(), "value": value.to_string()
                    });
                    if let Some(a) = address {
                        v["address"] = json!(address_json(a));
                    }
                    v
                }
                Request::ReadAgain => json!({ "request": "read_again" }),
                Request::ReadNext => json!({ "request": "read_next" }),
                Request::ReadPrevious => json!({ "request": "read_previous" }),
            })
        } else {
            Reply::decode(bytes).map(|r| match r {
                Reply::Value { parameter, value } => json!({
                    "reply": "read", "parameter": parameter.dotted(), "value": value.to_string()
                }),
                Reply::Accepted => json!({ "reply": "ack" }),
                Reply::Refused => json!({ "reply": "nak" }),
                Reply::NoSuchParameter => json!({ "reply": "eot" }),
            })
        };
        match frame {
            Ok(v) => (v, true),
            Err(e) => (json!({ "reject": e.reason() }), false),
        }
    }
}
