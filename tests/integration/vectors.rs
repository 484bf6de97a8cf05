//! Every golden telegram of the SD2 sources decodes to exactly its `frame` (or is rejected
//! for the stated reason), and the encoder, fed the frame's fields, reproduces every
//! request byte for byte.

use crate::support::{assert_every_vector_decodes, assert_matches_shared, sd2_vectors};
use drivescript::family::sd2::codec::{to_json, Body, Cyclic, ServiceChannel, Telegram, WriteLength};
use drivescript::hex::parse_hex;
use serde_json::Value;

#[test]
fn the_copy_matches_the_shared_vectors() {
    assert_matches_shared(&sd2_vectors(), "sd2-dnc.yaml");
}

#[test]
fn every_vector_decodes_to_its_frame() {
    assert_every_vector_decodes(&sd2_vectors(), 17, |bytes| {
        let decoded = Telegram::decode(bytes);
        (to_json(&decoded), decoded.is_ok())
    });
}

#[test]
fn rejections_give_the_documented_reason() {
    let vectors = sd2_vectors();
    let reason = |name: &str| {
        let v = vectors.iter().find(|v| v.name.starts_with(name)).unwrap();
        Telegram::decode(&parse_hex(&v.hex).unwrap())
            .unwrap_err()
            .to_string()
    };
    // "10 bytes where the length field says 12"
    assert_eq!(
        reason("printed status-word reply"),
        "truncated: needed 12 bytes (length field 0x09), have 10"
    );
    // "check byte 0x05, sum gives 0xb5"
    assert_eq!(
        reason("hand-typed cyclic"),
        "bad checksum at byte 15: expected 0xb5, got 0x05"
    );
}

fn num(frame: &Value, key: &str) -> u64 {
    frame[key].as_u64().unwrap_or_else(|| panic!("{key} in {frame}"))
}

fn bytes_of(frame: &Value, key: &str) -> Vec<u8> {
    parse_hex(frame[key].as_str().unwrap()).unwrap()
}

/// Builds the telegram from the vector's `frame` fields alone, not from its bytes.
fn telegram_from_frame(f: &Value) -> Option<Telegram> {
    let kind = f.get("request")?.as_str()?;
    let dest = num(f, "dest") as u8;
    let source = num(f, "source") as u8;
    match kind {
        "read_wide_object" => Some(Telegram::read_request(
            dest,
            source,
            num(f, "index") as u16,
            num(f, "subindex") as u32,
        )),
        "write_wide_object" => Telegram::write_request(
            dest,
            source,
            num(f, "index") as u16,
            num(f, "subindex") as u32,
            &bytes_of(f, "data"),
        )
        .ok(),
        "cyclic" => {
            let header = bytes_of(f, "header");
            let mut c = Cyclic::request(num(f, "control_word") as u16, num(f, "speed") as i16, false);
            c.header = [header[0], header[1]];
            if let Some(s) = f.get("service") {
                let data = bytes_of(s, "data");
                c.service = Some(ServiceChannel {
                    reserved: 0,
                    ctrl: num(s, "ctrl") as u8,
                    index: num(s, "index") as u16,
                    data: [data[0], data[1], data[2], data[3]],
                });
                assert_eq!(c.service.map(|s| s.function().id()), s["function"].as_str());
            }
            Some(Telegram {
                dest,
                source,
                body: Body::CyclicRequest(c),
            })
        }
        other => panic!("unknown request kind {other}"),
    }
}

#[test]
fn the_encoder_reproduces_every_request_byte_for_byte() {
    let mut requests = 0;
    for v in sd2_vectors() {
        if let Some(t) = telegram_from_frame(&v.frame) {
            assert_eq!(
                drivescript::hex::to_hex(&t.encode(WriteLength::Captured)),
                v.hex,
                "{}",
                v.name
            );
            requests += 1;
        }
    }
    assert_eq!(requests, 13);
}
