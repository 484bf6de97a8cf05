//! A telegram as one JSON object with the keys of `shared/vectors/sd2-dnc.yaml` (`frame`).
//! Pure formatting; a rejected telegram is `{"reject": reason}`.

use super::{Body, Cyclic, DecodeError, Telegram};
use crate::hex::to_hex;
use serde_json::{json, Map, Value};

/// The vector-file form of a decode result.
pub fn to_json(result: &Result<Telegram, DecodeError>) -> Value {
    match result {
        Err(e) => json!({ "reject": e.reason() }),
        Ok(t) => telegram_json(t),
    }
}

fn telegram_json(t: &Telegram) -> Value {
    let mut m = Map::new();
    let (direction, kind) = match t.body {
        Body::ReadRequest { .. } => ("request", "read_wide_object"),
        Body::ReadReply { .. } => ("reply", "read_wide_object"),
        Body::WriteRequest { .. } => ("request", "write_wide_object"),
        Body::WriteReply { .. } => ("reply", "write_wide_object"),
        Body::CyclicRequest(_) => ("request", "cyclic"),
        Body::CyclicReply(_) => ("reply", "cyclic"),
    };
    m.insert(direction.into(), kind.into());
    m.insert("dest".into(), t.dest.into());
    m.insert("source".into(), t.source.into());
    match &t.body {
        Body::ReadRequest { index, subindex } => {
            m.insert("index".into(), (*index).into());
            m.insert("subindex".into(), (*subindex).into());
        }
        Body::ReadReply { error, data } => {
            m.insert("error".into(), error.0.into());
            m.insert("data".into(), to_hex(data.as_slice()).into());
        }
        Body::WriteRequest {
            index,
            subindex,
            data,
        } => {
            m.insert("index".into(), (*index).into());
            m.insert("subindex".into(), (*subindex).into());
            m.insert("data".into(), to_hex(data.as_slice()).into());
        }
        Body::WriteReply { error } => {
            m.insert("error".into(), error.0.into());
        }
        Body::CyclicRequest(c) => {
            m.insert("header".into(), to_hex(&c.header).into());
            m.insert("control_word".into(), c.word().into());
            m.insert("speed".into(), c.speed().into());
            service_json(&mut m, c, "ctrl");
        }
        Body::CyclicReply(c) => {
            m.insert("header".into(), to_hex(&c.header).into());
            m.insert("status_word".into(), c.word().into());
            m.insert("speed".into(), c.speed().into());
            m.insert("drive_error".into(), c.drive_error().into());
            m.insert("current".into(), c.current().into());
            service_json(&mut m, c, "state");
        }
    }
    Value::Object(m)
}

/// In a reply the byte in the ctrl position is the drive's state byte, so it is named so.
fn service_json(m: &mut Map<String, Value>, c: &Cyclic, ctrl_key: &str) {
    if let Some(s) = &c.service {
        let mut sm = Map::new();
        sm.insert(ctrl_key.into(), s.ctrl.into());
        if ctrl_key == "ctrl" {
            sm.insert("function".into(), s.function().id().into());
        }
        sm.insert("index".into(), s.index.into());
        sm.insert("data".into(), to_hex(&s.data).into());
        m.insert("service".into(), Value::Object(sm));
    }
}
