//! What Modbus frames mean, for `decode`, `-v` and traces: the slave (or unit and
//! transaction), the function, the registers in both notations with their dictionary
//! names, the values through the dictionary (unit, scale, the state a status register
//! shows), exceptions with the specification's text, and a bad CRC. A frame of unknown
//! direction is read as a request when it is one, else as a reply to the last request.
//! Formatting only.

use super::codec::{mbap, rtu, Request, Response};
use super::register_address::{Register, Table};
use super::register_value;
use super::Framing;
use crate::dictionary::{Dictionary, Role};
use crate::link::{Direction, ExplainError, TelegramExplainer};
use serde_json::{json, Value};
use std::sync::Arc;

pub struct ModbusExplainer {
    dictionary: Arc<Dictionary>,
    framing: Framing,
    last: Option<Request>,
}

/// One frame, unwrapped: who it is for, its transaction (TCP), its PDU.
struct Unwrapped {
    unit: u8,
    transaction: Option<u16>,
    pdu: Vec<u8>,
}

enum Read {
    Request(Request),
    Response(Response),
}

impl ModbusExplainer {
    pub fn new(dictionary: Arc<Dictionary>, framing: Framing) -> Self {
        ModbusExplainer {
            dictionary,
            framing,
            last: None,
        }
    }

    fn unwrap(&self, bytes: &[u8]) -> Result<Unwrapped, ExplainError> {
        match self.framing {
            Framing::Rtu => rtu::decode(bytes)
                .map(|(unit, pdu)| Unwrapped {
                    unit,
                    transaction: None,
                    pdu: pdu.to_vec(),
                })
                .map_err(|e| ExplainError::from(format!("no Modbus RTU frame: {e}"))),
            Framing::Tcp => mbap::decode(bytes)
                .map(|f| Unwrapped {
                    unit: f.unit,
                    transaction: Some(f.transaction),
                    pdu: f.pdu.to_vec(),
                })
                .map_err(|e| ExplainError::from(format!("no Modbus TCP frame: {e}"))),
        }
    }

    fn read(&mut self, direction: Option<Direction>, pdu: &[u8]) -> Result<Read, ExplainError> {
        let as_request = || Request::decode(pdu).map(Read::Request);
        let as_reply = || Response::decode(pdu).map(Read::Response);
        let read = match direction {
            Some(Direction::Sent) => as_request(),
            Some(Direction::Received) => as_reply(),
            // An echo-shaped write reply reads as a request too: after that request it is the reply.
            None => match (&self.last, as_request()) {
                (Some(last), Ok(Read::Request(r))) if *last == r && r.writes() => as_reply(),
                (_, Ok(r)) => Ok(r),
                (_, Err(_)) => as_reply(),
            },
        }
        .map_err(|e| ExplainError::from(e.to_string()))?;
        if let Read::Request(r) = &read {
            self.last = Some(r.clone());
        }
        Ok(read)
    }

    fn who(&self, f: &Unwrapped) -> String {
        match (self.framing, f.transaction) {
            (Framing::Tcp, Some(t)) => format!("unit {} transaction {t}", f.unit),
            _ if f.unit == rtu::BROADCAST => "broadcast (slave 0, no reply)".into(),
            _ => format!("slave {}", f.unit),
        }
    }

    /// `holding 0x2000 (402001) inverter_status`.
    fn register(&self, table: Table, address: u16) -> String {
        let register = Register {
            table,
            address,
            low_word_first: false,
        };
        let name = self
            .dictionary
            .objects()
            .find(|o| Register::of(&o.address).is_some_and(|r| r.table == table && r.address == address))
            .map(|o| format!(" {}", o.name))
            .unwrap_or_default();
        format!("{}{name}", register.notation())
    }

    /// The values of registers from `start` as the dictionary's objects read them.
    fn values(&self, table: Table, start: u16, words: &[u16]) -> Vec<String> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < words.len() {
            let address = start.wrapping_add(i as u16);
            let object = self
                .dictionary
                .objects()
                .find(|o| Register::of(&o.address).is_some_and(|r| r.table == table && r.address == address));
            let n = object
                .and_then(|o| register_value::count(o.data_type))
                .map_or(1, usize::from)
                .min(words.len() - i);
            let text = object.and_then(|o| {
                let r = Register::of(&o.address)?;
                let raw = register_value::decode(&words[i..i + n], o.data_type, r.low_word_first).ok()?;
                let value = o.value_of(raw).ok()?;
                let mut text = format!("{} = {value}", o.name);
                let is_status = self
                    .dictionary
                    .role(Role::StatusWord)
                    .is_some_and(|s| s.name == o.name);
                if let (true, Some(profile)) = (is_status, self.dictionary.profile()) {
                    let state = profile
                        .state_of(words[i])
                        .map_or_else(|| "no state of the profile".to_string(), |s| s.to_string());
                    text = format!("{text} ({state})");
                }
                Some(text)
            });
            out.push(text.unwrap_or_else(|| format!("0x{address:04X} = {} (0x{:04X})", words[i], words[i])));
            i += n.max(1);
        }
        out
    }

    fn table_of(function: super::codec::Function) -> Table {
        if function == super::codec::Function::ReadInput {
            Table::Input
        } else {
            Table::Holding
        }
    }

    fn request_text(&self, r: &Request) -> String {
        let name = r.function().name();
        match r {
            Request::Read {
                function,
                start,
                count,
            } => {
                format!(
                    "{name}: {} ×{count}",
                    self.register(Self::table_of(*function), *start)
                )
            }
            Request::WriteSingle { address, value } => format!(
                "{name}: {}",
                self.values(Table::Holding, *address, &[*value]).join(", ")
            ),
            Request::WriteMultiple { start, values } => format!(
                "{name} from {}: {}",
                self.register(Table::Holding, *start),
                self.values(Table::Holding, *start, values).join(", ")
            ),
            Request::ReadWrite {
                read_start,
                read_count,
                write_start,
                values,
            } => format!(
                "{name}: read {} ×{read_count}, write {}",
                self.register(Table::Holding, *read_start),
                self.values(Table::Holding, *write_start, values).join(", ")
            ),
        }
    }

    fn reply_text(&self, r: &Response) -> String {
        match r {
            Response::Registers { function, values } => {
                let start = match &self.last {
                    Some(Request::Read { start, .. }) => Some(*start),
                    Some(Request::ReadWrite { read_start, .. }) => Some(*read_start),
                    _ => None,
                };
                match start {
                    Some(start) => format!(
                        "reply to {}: {}",
                        function.name(),
                        self.values(Self::table_of(*function), start, values).join(", ")
                    ),
                    None => format!("reply to {}: {values:?}", function.name()),
                }
            }
            Response::WriteSingle { address, value } => {
                format!(
                    "reply: wrote {}",
                    self.values(Table::Holding, *address, &[*value]).join(", ")
                )
            }
            Response::WriteMultiple { start, count } => {
                format!(
                    "reply: wrote {count} register(s) from {}",
                    self.register(Table::Holding, *start)
                )
            }
            Response::Exception { function, code } => format!("reply to function {function:02X}: {code}"),
        }
    }

    fn line(&mut self, direction: Option<Direction>, bytes: &[u8]) -> Result<String, ExplainError> {
        let f = self.unwrap(bytes)?;
        let who = self.who(&f);
        Ok(match self.read(direction, &f.pdu)? {
            Read::Request(r) => format!("{who} {}", self.request_text(&r)),
            Read::Response(r) => format!("{who} {}", self.reply_text(&r)),
        })
    }
}

impl TelegramExplainer for ModbusExplainer {
    fn summary(&mut self, direction: Direction, bytes: &[u8]) -> String {
        self.line(Some(direction), bytes)
            .unwrap_or_else(|e| format!("rejected: {e}"))
    }

    fn explain(&mut self, bytes: &[u8]) -> Result<String, ExplainError> {
        let line = self.line(None, bytes)?;
        let check = match self.framing {
            Framing::Rtu => format!(
                "\nCRC {:02X} {:02X} correct",
                bytes[bytes.len() - 2],
                bytes[bytes.len() - 1]
            ),
            Framing::Tcp => String::new(),
        };
        Ok(format!("{line}{check}"))
    }

    fn json(&mut self, bytes: &[u8]) -> (Value, bool) {
        let f = match self.unwrap(bytes) {
            Ok(f) => f,
            Err(e) => return (json!({ "reject": e.reason }), false),
        };
        match self.read(None, &f.pdu) {
            Ok(Read::Request(r)) => (
                json!({ "unit": f.unit, "transaction": f.transaction, "function": r.function().code(), "request": self.request_text(&r) }),
                true,
            ),
            Ok(Read::Response(Response::Exception { function, code })) => (
                json!({ "unit": f.unit, "transaction": f.transaction, "function": function | 0x80, "exception": code.0, "text": code.meaning() }),
                true,
            ),
            Ok(Read::Response(r)) => (
                json!({ "unit": f.unit, "transaction": f.transaction, "reply": self.reply_text(&r) }),
                true,
            ),
            Err(e) => (json!({ "reject": e.reason }), false),
        }
    }
}
