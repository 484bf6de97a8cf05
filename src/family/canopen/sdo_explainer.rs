//! Explains CANopen frames for `decode`, `-v` and traces: SDO (0x600 + node requests,
//! 0x580 + node responses: the command, the object in the family's notation and its
//! dictionary name, the value with the object's unit and scaling when the dictionary has
//! it, or the abort code's meaning), NMT commands (0x000), heartbeats and boot-up messages
//! (0x700 + node) and EMCY frames (0x80 + node, with the error code's text). It remembers
//! each node's last initiate request so that segments and responses are read as the
//! object they belong to, and the transfer's bytes so that its last segment shows the
//! whole value of an object of a number type (a 64-bit count, a REAL64). Frames arrive as
//! [`CanFrame::to_bytes`].

use super::codec::{
    error_code_text, AbortCode, Emcy, NmtCommand, NmtState, SdoRequest, SdoResponse, Segment, Uploaded,
    NMT_ID,
};
use super::transfer_bytes::TransferBytes;
use crate::bus::CanFrame;
use crate::dictionary::Dictionary;
use crate::hex::to_hex;
use crate::link::{Direction, ExplainError, TelegramExplainer};
use serde_json::{json, Map, Value};
use std::collections::HashMap;
use std::sync::Arc;

pub struct SdoExplainer {
    names: Arc<Dictionary>,
    /// The object of each node's transfer under way.
    current: HashMap<u8, (u16, u8)>,
    /// The bytes of each node's segmented transfer under way.
    transfers: TransferBytes,
    /// The whole transfer the frame just read ended, if its last segment it was.
    completed: Option<(u8, Vec<u8>)>,
    notation: ExplainNotation,
}

/// A family's notation for objects in explanations.
#[derive(Debug, Clone, Copy)]
pub struct ExplainNotation {
    /// The vendor's name of an object (`C00099`), if it has one.
    pub code: fn(u16, u8) -> Option<String>,
    /// How the index follows from it, for `explain`: ` = 0x5FFF − code`.
    pub index_rule: &'static str,
}

/// CiA 301's notation: objects by index alone.
pub const INDEX_NOTATION: ExplainNotation = ExplainNotation {
    code: |_, _| None,
    index_rule: "",
};

/// A frame of another CANopen service than SDO.
enum Service {
    Nmt { command: u8, node: u8 },
    Heartbeat { node: u8, state: u8 },
    Emcy { node: u8, emcy: Option<Emcy> },
}

impl Service {
    fn of(frame: &CanFrame) -> Option<Service> {
        if frame.extended {
            return None;
        }
        let d = frame.data();
        Some(match frame.id {
            NMT_ID => Service::Nmt {
                command: *d.first()?,
                node: *d.get(1)?,
            },
            0x701..=0x77F => Service::Heartbeat {
                node: (frame.id - 0x700) as u8,
                state: *d.first()?,
            },
            0x081..=0x0FF => Service::Emcy {
                node: (frame.id - 0x80) as u8,
                emcy: Emcy::decode(d),
            },
            _ => return None,
        })
    }

    fn one_line(&self) -> String {
        match *self {
            Service::Nmt { command, node } => {
                let what = NmtCommand::from_byte(command).map_or("unknown NMT command", NmtCommand::name);
                let to = if node == 0 {
                    "every node".to_string()
                } else {
                    format!("node {node}")
                };
                format!("NMT {what} → {to}")
            }
            Service::Heartbeat { node, state } => match NmtState::from_byte(state) {
                Some(NmtState::BootUp) => format!("boot-up ← node {node}"),
                Some(s) => format!("heartbeat {} ← node {node}", s.name()),
                None => format!("heartbeat with unknown state 0x{state:02X} ← node {node}"),
            },
            Service::Emcy { node, emcy: Some(e) } if e.is_reset() => {
                format!("EMCY error reset ← node {node}")
            }
            Service::Emcy { node, emcy: Some(e) } => format!(
                "EMCY 0x{:04X} {}, error register 0x{:02X} ← node {node}",
                e.code,
                error_code_text(e.code),
                e.register
            ),
            Service::Emcy { node, emcy: None } => {
                format!("EMCY frame of the wrong length (CiA 301 sends 8 bytes) ← node {node}")
            }
        }
    }

    fn to_json(&self) -> Value {
        match *self {
            Service::Nmt { command, node } => json!({ "nmt": command, "node": node }),
            Service::Heartbeat { node, state } => json!({ "heartbeat": state, "node": node }),
            Service::Emcy { node, emcy } => match emcy {
                Some(e) => json!({ "emcy": e.code, "register": e.register, "node": node }),
                None => json!({ "emcy": null, "node": node }),
            },
        }
    }
}

/// One frame read as SDO.
enum Sdo {
    Request { node: u8, body: SdoRequest },
    Response { node: u8, body: SdoResponse },
}

impl SdoExplainer {
    pub fn new(names: Arc<Dictionary>, notation: ExplainNotation) -> Self {
        SdoExplainer {
            names,
            current: HashMap::new(),
            transfers: TransferBytes::default(),
            completed: None,
            notation,
        }
    }

    /// The frame of another service than SDO, if `bytes` is one.
    fn service(bytes: &[u8]) -> Option<Service> {
        Service::of(&CanFrame::from_bytes(bytes)?)
    }

    fn read(&mut self, bytes: &[u8]) -> Result<(CanFrame, Sdo), ExplainError> {
        let frame = CanFrame::from_bytes(bytes).ok_or_else(|| {
            "not a CAN frame; give it as ID#DATA (e.g. 60C#409C5F0000000000) or ID and data bytes".to_string()
        })?;
        if frame.extended {
            return Err(format!(
                "{:08X} is an extended (29-bit) identifier; SDO uses 11-bit identifiers 0x581..0x5FF and 0x601..0x67F",
                frame.id
            )
            .into());
        }
        let sdo = match frame.id {
            0x601..=0x67F => Sdo::Request {
                node: (frame.id - 0x600) as u8,
                body: SdoRequest::decode(frame.data()).map_err(|e| e.to_string())?,
            },
            0x581..=0x5FF => Sdo::Response {
                node: (frame.id - 0x580) as u8,
                body: SdoResponse::decode(frame.data()).map_err(|e| e.to_string())?,
            },
            id => {
                return Err(format!(
                    "identifier 0x{id:03X} is not an SDO channel nor another CANopen service drivescript reads (NMT 0x000, EMCY 0x80 + node, SDO requests 0x600 + node and responses 0x580 + node, heartbeat 0x700 + node, node 1..127)"
                )
                .into())
            }
        };
        // Remember the object each transfer is about, and its segments' bytes.
        let (node, object, segment) = match &sdo {
            Sdo::Request { node, body } => match body {
                SdoRequest::DownloadSegment(s) => (*node, None, Some(s)),
                _ => (*node, body.object(), None),
            },
            Sdo::Response { node, body } => match body {
                SdoResponse::UploadSegment(s) => (*node, None, Some(s)),
                _ => (*node, body.object(), None),
            },
        };
        if let Some(object) = object {
            self.current.insert(node, object);
            self.transfers.start(node);
        }
        self.completed = segment
            .and_then(|s| self.transfers.segment(node, &s.data, s.last))
            .map(|bytes| (node, bytes));
        Ok((frame, sdo))
    }

    /// `C00099 ident` or `C00061` or `index 0x1000/0`.
    fn object(&self, index: u16, subindex: u8) -> String {
        let code = match (self.notation.code)(index, subindex) {
            Some(c) => c,
            None => format!("index 0x{index:04X}/{subindex}"),
        };
        match self.names.by_address(index, u32::from(subindex)) {
            Some(def) if def.name != code => format!("{code} {}", def.name),
            _ => code,
        }
    }

    /// `43`, `102 = 10.2 A`, from the value bytes and the object's definition if known.
    /// `C00011 speed_setpoint = 1500`: an expedited transfer's object and value, in the
    /// size it indicates (all four bytes when it does not).
    fn assignment(&self, index: u16, subindex: u8, data: &[u8; 4], size: Option<u8>) -> String {
        let n = usize::from(size.unwrap_or(4));
        format!(
            "{} = {}",
            self.object(index, subindex),
            self.value(index, subindex, &data[..n], size.is_some())
        )
    }

    /// The bytes as the object's type holds them (the node's own decoding, so a REAL32 is
    /// its float and a 24-bit integer sign-extended); as an unsigned number for an object
    /// the dictionary does not know, or whose type the bytes do not fit.
    fn value(&self, index: u16, subindex: u8, data: &[u8], size_indicated: bool) -> String {
        let mut buf = [0u8; 8];
        let n = data.len().min(8);
        buf[..n].copy_from_slice(&data[..n]);
        let unsigned = u64::from_le_bytes(buf).to_string();
        let Some(def) = self.names.by_address(index, u32::from(subindex)) else {
            return unsigned;
        };
        let uploaded = Uploaded {
            data: data.to_vec(),
            size_indicated,
            segmented: false,
        };
        let Ok(raw) = super::sdo_value::decode(&uploaded, def.data_type) else {
            return unsigned;
        };
        match def.value_of(raw.clone()) {
            Ok(v) if def.unit.is_some() && def.scale != 1.0 => format!("{raw} = {v}"),
            Ok(v) => v.to_string(),
            Err(_) => raw.to_string(),
        }
    }

    fn segment_of(&self, node: u8) -> String {
        match self.current.get(&node) {
            Some(&(i, s)) => format!(" of {}", self.object(i, s)),
            None => String::new(),
        }
    }

    /// The object of `node`'s transfer under way when the dictionary gives it a number
    /// type, whose segments are no text.
    fn number_object(&self, node: u8) -> Option<(u16, u8)> {
        let &(index, subindex) = self.current.get(&node)?;
        let def = self.names.by_address(index, u32::from(subindex))?;
        def.data_type.is_number().then_some((index, subindex))
    }

    /// An upload segment's bytes as text (` "2.07"`), unless they are part of a number.
    fn segment_text(&self, node: u8, data: &[u8]) -> String {
        match self.number_object(node) {
            Some(_) => String::new(),
            None => format!(" {:?}", String::from_utf8_lossy(data)),
        }
    }

    /// ` = 9223372036854775807`: the whole value of a number the last segment just read
    /// ended; empty for anything else.
    fn whole_value(&self, node: u8) -> String {
        match (&self.completed, self.number_object(node)) {
            (Some((n, bytes)), Some((index, subindex))) if *n == node => {
                format!(" = {}", self.value(index, subindex, bytes, true))
            }
            _ => String::new(),
        }
    }

    /// An abort, either way: `abort <object> <arrow and node>: <code and meaning>`.
    fn abort_line(&self, index: u16, subindex: u8, code: AbortCode, way: &str) -> String {
        format!("abort {} {way}: {code}", self.object(index, subindex))
    }

    fn one_line(&self, sdo: &Sdo) -> String {
        match sdo {
            Sdo::Request { node, body } => {
                let to = format!("→ node {node}");
                match body {
                    SdoRequest::UploadInitiate { index, subindex } => {
                        format!("read {} {to}", self.object(*index, *subindex))
                    }
                    SdoRequest::DownloadExpedited {
                        index,
                        subindex,
                        data,
                        size,
                    } => {
                        format!("write {} {to}", self.assignment(*index, *subindex, data, *size))
                    }
                    SdoRequest::Abort {
                        index,
                        subindex,
                        code,
                    } => self.abort_line(*index, *subindex, *code, &to),
                    other => format!(
                        "{other}{}{} {to}",
                        self.segment_of(*node),
                        self.whole_value(*node)
                    ),
                }
            }
            Sdo::Response { node, body } => {
                let from = format!("← node {node}");
                match body {
                    SdoResponse::UploadExpedited {
                        index,
                        subindex,
                        data,
                        size,
                    } => {
                        format!("reply {} {from}", self.assignment(*index, *subindex, data, *size))
                    }
                    SdoResponse::UploadInitiate {
                        index,
                        subindex,
                        size,
                    } => format!(
                        "reply {}: segmented{} {from}",
                        self.object(*index, *subindex),
                        size.map(|s| format!(", {s} bytes")).unwrap_or_default()
                    ),
                    SdoResponse::UploadSegment(segment) => format!(
                        "{body}{}{}{} {from}",
                        self.segment_of(*node),
                        self.segment_text(*node, &segment.data),
                        self.whole_value(*node)
                    ),
                    SdoResponse::DownloadInitiate { index, subindex } => {
                        format!("write {} accepted {from}", self.object(*index, *subindex))
                    }
                    SdoResponse::Abort {
                        index,
                        subindex,
                        code,
                    } => self.abort_line(*index, *subindex, *code, &from),
                    other => format!("{other}{} {from}", self.segment_of(*node)),
                }
            }
        }
    }
}

fn request_kind(body: &SdoRequest) -> &'static str {
    match body {
        SdoRequest::UploadInitiate { .. } => "upload",
        SdoRequest::UploadSegment { .. } => "upload_segment",
        SdoRequest::DownloadExpedited { .. } => "download_expedited",
        SdoRequest::DownloadInitiate { .. } => "download_segmented",
        SdoRequest::DownloadSegment { .. } => "download_segment",
        SdoRequest::Abort { .. } => "abort",
    }
}

fn response_kind(body: &SdoResponse) -> &'static str {
    match body {
        SdoResponse::UploadExpedited { .. } => "upload_expedited",
        SdoResponse::UploadInitiate { .. } => "upload_segmented",
        SdoResponse::UploadSegment { .. } => "upload_segment",
        SdoResponse::DownloadInitiate { .. } => "download",
        SdoResponse::DownloadSegment { .. } => "download_segment",
        SdoResponse::Abort { .. } => "abort",
    }
}

/// The keys of the golden vectors (`shared/vectors/lenze-9400-sdo.yaml`).
fn to_json(sdo: &Sdo, notation: ExplainNotation) -> Value {
    let mut m = Map::new();
    let (node, object) = match sdo {
        Sdo::Request { node, body } => {
            m.insert("request".into(), json!(request_kind(body)));
            (*node, body.object())
        }
        Sdo::Response { node, body } => {
            m.insert("reply".into(), json!(response_kind(body)));
            (*node, body.object())
        }
    };
    m.insert("node".into(), json!(node));
    if let Some((index, subindex)) = object {
        if let Some(code) = (notation.code)(index, subindex) {
            m.insert("code".into(), json!(code));
        }
    }
    // As the golden vectors: the index only on the read request that opens a transfer.
    let with_index = matches!(
        sdo,
        Sdo::Request {
            body: SdoRequest::UploadInitiate { .. },
            ..
        }
    );
    if let (true, Some((index, subindex))) = (with_index, object) {
        m.insert("index".into(), json!(index));
        m.insert("subindex".into(), json!(subindex));
    }
    let value4 = |data: &[u8; 4], size: Option<u8>, m: &mut Map<String, Value>| {
        let n = usize::from(size.unwrap_or(4));
        m.insert("data".into(), json!(to_hex(&data[..n])));
        let mut buf = [0u8; 4];
        buf[..n].copy_from_slice(&data[..n]);
        m.insert("value".into(), json!(u32::from_le_bytes(buf)));
    };
    match sdo {
        Sdo::Request {
            body: SdoRequest::DownloadExpedited { data, size, .. },
            ..
        }
        | Sdo::Response {
            body: SdoResponse::UploadExpedited { data, size, .. },
            ..
        } => value4(data, *size, &mut m),
        Sdo::Response {
            body: SdoResponse::UploadInitiate { size: Some(size), .. },
            ..
        }
        | Sdo::Request {
            body: SdoRequest::DownloadInitiate { size: Some(size), .. },
            ..
        } => {
            m.insert("size".into(), json!(size));
        }
        Sdo::Request {
            body: SdoRequest::Abort { code, .. },
            ..
        }
        | Sdo::Response {
            body: SdoResponse::Abort { code, .. },
            ..
        } => {
            m.insert("abort".into(), json!(code.0));
        }
        Sdo::Request {
            body: SdoRequest::DownloadSegment(Segment { data, last, toggle }),
            ..
        }
        | Sdo::Response {
            body: SdoResponse::UploadSegment(Segment { data, last, toggle }),
            ..
        } => {
            m.insert("toggle".into(), json!(u8::from(*toggle)));
            m.insert("data".into(), json!(to_hex(data)));
            m.insert("last".into(), json!(last));
        }
        Sdo::Request {
            body: SdoRequest::UploadSegment { toggle },
            ..
        }
        | Sdo::Response {
            body: SdoResponse::DownloadSegment { toggle },
            ..
        } => {
            m.insert("toggle".into(), json!(u8::from(*toggle)));
        }
        _ => {}
    }
    Value::Object(m)
}

impl TelegramExplainer for SdoExplainer {
    fn summary(&mut self, _direction: Direction, bytes: &[u8]) -> String {
        if let Some(service) = Self::service(bytes) {
            return service.one_line();
        }
        match self.read(bytes) {
            Ok((_, sdo)) => self.one_line(&sdo),
            Err(e) => format!("rejected: {e}"),
        }
    }

    fn explain(&mut self, bytes: &[u8]) -> Result<String, ExplainError> {
        if let Some(service) = Self::service(bytes) {
            return Ok(format!("  meaning   {}\n", service.one_line()));
        }
        let (frame, sdo) = self.read(bytes)?;
        let mut out = String::new();
        let (role, node, command) = match &sdo {
            Sdo::Request { node, body } => ("request ", *node, body.to_string()),
            Sdo::Response { node, body } => ("response", *node, body.to_string()),
        };
        let data = frame.data();
        let direction = match &sdo {
            Sdo::Request { .. } => format!("PC → node {node} (0x{:03X} = 0x600 + {node})", frame.id),
            Sdo::Response { .. } => format!("node {node} → PC (0x{:03X} = 0x580 + {node})", frame.id),
        };
        out.push_str(&format!(
            "  {role}  {command} (command 0x{:02x}), {direction}\n",
            data[0]
        ));
        let object = match &sdo {
            Sdo::Request { body, .. } => body.object(),
            Sdo::Response { body, .. } => body.object(),
        };
        if let Some((index, subindex)) = object {
            out.push_str(&format!(
                "  object    {} (index 0x{index:04X}{}, subindex {subindex})\n",
                self.object(index, subindex),
                self.notation.index_rule
            ));
        } else if let Some(&(i, s)) = self.current.get(&node) {
            out.push_str(&format!(
                "  object    {} (from the transfer under way)\n",
                self.object(i, s)
            ));
        }
        let line = self.one_line(&sdo);
        match &sdo {
            Sdo::Request {
                body: SdoRequest::Abort { code, .. },
                ..
            }
            | Sdo::Response {
                body: SdoResponse::Abort { code, .. },
                ..
            } => out.push_str(&format!(
                "  abort     {code} (bytes 5..8 {} little-endian)\n",
                to_hex(&AbortCode(code.0).to_bytes())
            )),
            _ => out.push_str(&format!("  meaning   {line}\n")),
        }
        Ok(out)
    }

    fn json(&mut self, bytes: &[u8]) -> (Value, bool) {
        if let Some(service) = Self::service(bytes) {
            return (service.to_json(), true);
        }
        match self.read(bytes) {
            Ok((_, sdo)) => (to_json(&sdo, self.notation), true),
            Err(e) => (json!({ "reject": e.reason }), false),
        }
    }
}
