//! The explainer on frames of the Lenze 9400 and of a CiA 402 node from its EDS: segments
//! read as their transfer's object, the whole value on the last one, the other services.

use super::sdo_explainer::*;
use crate::bus::CanFrame;
use crate::dictionary::Dictionary;
use crate::family::lenze_9400::Lenze9400Family;
use crate::family::Family;
use crate::link::{Direction, TelegramExplainer};
use serde_json::json;
use std::sync::Arc;

fn explainer() -> SdoExplainer {
    let text = Lenze9400Family.dictionaries()[0].text;
    let d = Dictionary::from_yaml_for(
        "dictionary/lenze-9400.yaml",
        text,
        Lenze9400Family.address_parser(),
    )
    .unwrap();
    SdoExplainer::new(Arc::new(d), crate::family::lenze_9400::LENZE_EXPLAIN)
}

fn bytes(text: &str) -> Vec<u8> {
    CanFrame::parse_text(text).unwrap().to_bytes()
}

#[test]
fn segments_are_read_as_the_object_of_their_transfer() {
    let mut e = explainer();
    let s = |e: &mut SdoExplainer, t: &str| e.summary(Direction::Received, &bytes(t));
    assert_eq!(s(&mut e, "60C#409C5F0000000000"), "read C00099 ident → node 12");
    assert_eq!(
        s(&mut e, "58C#419C5F000B000000"),
        "reply C00099 ident: segmented, 11 bytes ← node 12"
    );
    assert_eq!(
        s(&mut e, "58C#17322E3037000000"),
        "upload segment, toggle 1, 4 byte(s), last of C00099 ident \"2.07\" ← node 12"
    );
    assert_eq!(
        s(&mut e, "585#43C25F002B000000"),
        "reply C00061 heatsink_temperature = 43 ← node 5"
    );
    assert_eq!(
        s(&mut e, "582#80A75F0031000906"),
        "abort C00088 rated_motor_current ← node 2: 0x06090031 value of parameter written too high"
    );
    assert!(s(&mut e, "700#05").starts_with("rejected: identifier 0x700"));
    assert_eq!(s(&mut e, "000#0105"), "NMT start (enter operational) → node 5");
    assert_eq!(s(&mut e, "000#8000"), "NMT enter pre-operational → every node");
    assert_eq!(s(&mut e, "705#7F"), "heartbeat pre-operational ← node 5");
    assert_eq!(s(&mut e, "705#00"), "boot-up ← node 5");
    assert_eq!(
        s(&mut e, "085#1032010000000000"),
        "EMCY 0x3210 DC link over-voltage, error register 0x01 ← node 5"
    );
    assert_eq!(s(&mut e, "085#0000000000000000"), "EMCY error reset ← node 5");
    assert_eq!(
        e.json(&bytes("085#1032010000000000")).0,
        json!({"emcy": 0x3210, "register": 1, "node": 5})
    );
    assert!(e.explain(&[1, 2]).is_err());
}

/// The CiA 402 node's dictionary from its own EDS.
fn node_explainer() -> SdoExplainer {
    use crate::family::{canopen::CanopenFamily, Family};
    let text = CanopenFamily.dictionaries()[0].text;
    let mut d =
        Dictionary::from_yaml_for("dictionary/canopen.yaml", text, CanopenFamily.address_parser()).unwrap();
    d.extend_from(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/family/canopen/sim/cia402_node.eds"),
    )
    .unwrap();
    SdoExplainer::new(Arc::new(d), INDEX_NOTATION)
}

/// A 64-bit count comes in two segments: the last one shows the whole value, exactly; the
/// segments of a number are no text.
#[test]
fn the_last_segment_shows_the_whole_number() {
    let mut e = node_explainer();
    let mut s = |t: &str| e.summary(Direction::Sent, &bytes(t));
    assert_eq!(
        s("601#2107210008000000"),
        "segmented write request, 8 byte(s) of index 0x2107/0 lifetime_revolutions → node 1"
    );
    assert_eq!(
        s("601#00FFFFFFFFFFFFFF"),
        "download segment, toggle 0, 7 byte(s) of index 0x2107/0 lifetime_revolutions → node 1"
    );
    assert_eq!(
        s("601#1D7F000000000000"),
        "download segment, toggle 1, 1 byte(s), last of index 0x2107/0 lifetime_revolutions = 9223372036854775807 → node 1"
    );
    s("601#4008210000000000");
    s("581#4108210008000000");
    assert_eq!(
        s("581#0001000000000020"),
        "upload segment, toggle 0, 7 byte(s) of index 0x2108/0 position_counter ← node 1"
    );
    assert_eq!(
        s("581#1D00000000000000"),
        "upload segment, toggle 1, 1 byte(s), last of index 0x2108/0 position_counter = 9007199254740993 ← node 1"
    );
    // A lone last segment, its transfer's start unseen: no value is made up.
    assert_eq!(
        s("581#1D00000000000000"),
        "upload segment, toggle 1, 1 byte(s), last of index 0x2108/0 position_counter ← node 1"
    );
    // Text is still shown segment by segment.
    s("601#4008100000000000");
    s("581#4108100018000000");
    assert_eq!(
        s("581#0064726976657363"),
        "upload segment, toggle 0, 7 byte(s) of index 0x1008/0 ident \"drivesc\" ← node 1"
    );
}
