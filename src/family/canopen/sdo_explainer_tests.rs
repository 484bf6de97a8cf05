//! The explainer on frames of the Lenze 9400 and of a CiA 402 node from its EDS: segments
//! read as their transfer's object, the whole value on the last one, the other services;
//! any frames without panic.

use super::sdo_explainer::*;
use crate::bus::CanFrame;
use crate::dictionary::Dictionary;
use crate::family::lenze_9400::LENZE_9400_FAMILY;
use crate::family::Family;
use crate::link::{Direction, TelegramExplainer};
use proptest::prelude::Strategy as _;
use serde_json::json;
use std::sync::Arc;

fn explainer() -> SdoExplainer {
    let text = LENZE_9400_FAMILY.dictionaries()[0].text;
    let d = Dictionary::from_yaml_for(
        "dictionary/lenze-9400.yaml",
        text,
        LENZE_9400_FAMILY.address_parser(),
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
    #[rustfmt::skip]
    let summaries = [
        ("60C#409C5F0000000000", "read C00099 ident → node 12"),
        ("58C#419C5F000B000000", "reply C00099 ident: segmented, 11 bytes ← node 12"),
        ("58C#17322E3037000000", "upload segment, toggle 1, 4 byte(s), last of C00099 ident \"2.07\" ← node 12"),
        ("585#43C25F002B000000", "reply C00061 heatsink_temperature = 43 ← node 5"),
        ("582#80A75F0031000906", "abort C00088 rated_motor_current ← node 2: 0x06090031 value of parameter written too high"),
        ("000#0105", "NMT start (enter operational) → node 5"),
        ("000#8000", "NMT enter pre-operational → every node"),
        ("705#7F", "heartbeat pre-operational ← node 5"),
        ("705#00", "boot-up ← node 5"),
        ("085#1032010000000000", "EMCY 0x3210 DC link over-voltage, error register 0x01 ← node 5"),
        ("085#0000000000000000", "EMCY error reset ← node 5"),
    ];
    for (frame, said) in summaries {
        assert_eq!(s(&mut e, frame), said, "{frame}");
    }
    assert!(s(&mut e, "700#05").starts_with("rejected: identifier 0x700"));
    assert_eq!(
        e.json(&bytes("085#1032010000000000")).0,
        json!({"emcy": 0x3210, "register": 1, "node": 5})
    );
    assert!(e.explain(&[1, 2]).is_err());
}

/// The CiA 402 node's dictionary from its own EDS.
fn node_explainer() -> SdoExplainer {
    use crate::family::{canopen::CANOPEN_FAMILY, Family};
    let text = CANOPEN_FAMILY.dictionaries()[0].text;
    let mut d =
        Dictionary::from_yaml_for("dictionary/canopen.yaml", text, CANOPEN_FAMILY.address_parser()).unwrap();
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

proptest::proptest! {
    /// Whatever frames a capture holds, in any order and for any node (transfers started,
    /// broken off, segments without a start, any bytes), the explainer reads each without
    /// panic, and the bytes it keeps of a transfer stay bounded.
    #[test]
    fn any_frames_are_explained_without_panic(frames in proptest::collection::vec(
        (
            proptest::prop_oneof![
                0x580u32..0x590, 0x600u32..0x610, 0x80u32..0x90, 0x700u32..0x710, 0u32..2, 0u32..0x800,
            ],
            proptest::prop_oneof![
                proptest::collection::vec(proptest::prelude::any::<u8>(), 0..=8),
                // Initiates and segments of the node's objects: a 64-bit count, text, a block.
                (
                    proptest::sample::select(vec![0x40u8, 0x41, 0x21, 0x00, 0x10, 0x1D, 0x17, 0x60, 0x23, 0x43, 0x80]),
                    proptest::sample::select(vec![[0x07u8, 0x21], [0x08, 0x21], [0x08, 0x10], [0x06, 0x21], [0x00, 0x2F]]),
                    proptest::collection::vec(proptest::prelude::any::<u8>(), 5),
                )
                    .prop_map(|(command, index, rest)| [&[command][..], &index, &rest].concat()),
            ],
        ),
        0..120,
    )) {
        let mut e = node_explainer();
        for (id, data) in frames {
            let Some(frame) = CanFrame::new(id, &data) else { continue };
            let raw = frame.to_bytes();
            let _ = e.summary(Direction::Received, &raw);
            let _ = e.explain(&raw);
            let _ = e.json(&raw);
        }
    }
}
