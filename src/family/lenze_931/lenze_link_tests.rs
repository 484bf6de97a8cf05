//! The link against a scripted peer: framing, echo, garbage, over-long lines, retries and
//! the read-back before a write is sent again.

use super::*;
use crate::bus::ScriptedPeer;
use crate::clock::{Clock, VirtualClock};
use crate::family::lenze_931::codec::ErrorCode;
use std::sync::Arc;
use std::sync::Mutex;

/// `OW:0010:00000BB8`, the write the lost-reply tests send.
const WRITE_3000: Request = Request::Write {
    object: 0x10,
    value: 3000,
};

fn link(script: Vec<Option<&[u8]>>) -> (LenzeLink, Arc<Mutex<ScriptedPeer>>, Arc<VirtualClock>) {
    let replies = script.into_iter().map(|r| r.map(<[u8]>::to_vec));
    let peer = ScriptedPeer::new(replies, Duration::from_millis(2));
    let (line, clock) = ScriptedPeer::line(&peer);
    let link = LenzeLink::new(line, clock.clone(), LinkConfig::default());
    (link, peer, clock)
}

/// The request lines sent, without their CR.
fn sent(peer: &Arc<Mutex<ScriptedPeer>>) -> Vec<String> {
    let sent = peer.lock().unwrap().sent();
    sent.iter()
        .map(|line| String::from_utf8_lossy(line).trim_end_matches('\r').to_string())
        .collect()
}

const READ_11: Request = Request::Read {
    command: ObjectCommand::Read,
    object: 0x11,
};

/// The reply to `READ_11`.
fn value_11(value: u32) -> Reply {
    Reply::Value { object: 0x11, value }
}

#[test]
fn a_read_returns_the_value() {
    let (mut l, peer, _) = link(vec![Some(b"0011:00000BB8\r")]);
    assert_eq!(l.exchange(&READ_11).unwrap(), value_11(3000));
    assert_eq!(sent(&peer), vec!["OR:0011"]);
}

#[test]
fn stray_lf_and_an_echo_are_tolerated() {
    let (mut l, _, _) = link(vec![Some(b"OR:0011\r\n\n0011:00000BB8\r\n")]);
    assert_eq!(l.exchange(&READ_11).unwrap(), value_11(3000));
    let (mut l, _, _) = link(vec![Some(b"\nOR:0011\r0011:\n00000001\r")]);
    assert_eq!(l.exchange(&READ_11).unwrap(), value_11(1));
}

#[test]
fn the_error_field_in_both_spellings() {
    for reply in [&b"OR:00040000\r"[..], b"OR:0004 0000\r"] {
        let (mut l, _, _) = link(vec![Some(reply)]);
        assert_eq!(
            l.exchange(&READ_11).unwrap(),
            Reply::Error {
                command: ObjectCommand::Read,
                code: ErrorCode::NO_OBJECT
            }
        );
    }
}

#[test]
fn a_lost_read_reply_is_retried() {
    let (mut l, peer, clock) = link(vec![None, Some(b"0011:00000001\r")]);
    assert!(l.exchange(&READ_11).is_ok());
    assert_eq!(sent(&peer), vec!["OR:0011", "OR:0011"]);
    assert_eq!(l.stats().timeouts, 1);
    assert!(clock.now() >= Duration::from_secs(1));
}

#[test]
fn garbage_is_retried_then_reported_with_the_line_and_reason() {
    let (mut l, peer, _) = link(vec![
        Some(b"\xff\xfe\r"),
        Some(b"HELLO\r"),
        Some(b"0012:00000001\r"),
    ]);
    let e = l.exchange(&READ_11).unwrap_err();
    assert_eq!(sent(&peer).len(), 3);
    let text = e.to_string();
    assert!(matches!(e, AccessError::BadReply { attempts: 3, .. }), "{text}");
    assert!(text.contains("`OR:0011` (read object 0x0011)"), "{text}");
    assert!(text.contains("\"0012:00000001\""), "{text}");
    assert!(text.contains("expected `0011:` and 8 hex digits"), "{text}");
}

#[test]
fn an_over_long_line_is_a_bad_reply_and_memory_stays_bounded() {
    let long = vec![b'7'; 10_000];
    let (mut l, _, _) = link(vec![Some(&long), Some(&long), Some(&long)]);
    let e = l.exchange(&READ_11).unwrap_err();
    assert!(
        e.to_string()
            .contains("no line of this protocol is longer than 128"),
        "{e}"
    );
    let mut long_then_ok = vec![b'7'; 500];
    long_then_ok.extend_from_slice(b"\r");
    let (mut l, _, _) = link(vec![Some(&long_then_ok), Some(b"0011:00000002\r")]);
    assert_eq!(l.exchange(&READ_11).unwrap(), value_11(2));
}

#[test]
fn a_lost_write_reply_is_read_back_and_not_sent_again_when_stored() {
    let write = WRITE_3000;
    let (mut l, peer, _) = link(vec![None, Some(b"0010:00000BB8\r")]);
    assert_eq!(l.exchange(&write).unwrap(), Reply::Ok);
    assert_eq!(sent(&peer), vec!["OW:0010:00000BB8", "OR:0010"]);
}

#[test]
fn a_lost_write_reply_is_read_back_before_the_write_is_sent_again() {
    let write = WRITE_3000;
    let (mut l, peer, _) = link(vec![None, Some(b"0010:00000000\r"), Some(b"OK!\r")]);
    assert_eq!(l.exchange(&write).unwrap(), Reply::Ok);
    assert_eq!(
        sent(&peer),
        vec!["OW:0010:00000BB8", "OR:0010", "OW:0010:00000BB8"]
    );
}

#[test]
fn a_garbled_write_reply_is_read_back_too() {
    let write = WRITE_3000;
    let (mut l, peer, _) = link(vec![Some(b"O#!\r"), Some(b"0010:00000BB8\r")]);
    assert_eq!(l.exchange(&write).unwrap(), Reply::Ok);
    assert_eq!(sent(&peer), vec!["OW:0010:00000BB8", "OR:0010"]);
}

#[test]
fn a_write_is_not_sent_again_when_the_read_back_fails() {
    let write = WRITE_3000;
    let (mut l, peer, _) = link(vec![None, None, Some(b"OK!\r")]);
    let e = l.exchange(&write).unwrap_err();
    assert_eq!(sent(&peer), vec!["OW:0010:00000BB8", "OR:0010"]);
    let text = e.to_string();
    assert!(
        text.contains("whether the drive stored the value is unknown and the write was not sent again"),
        "{text}"
    );
}

#[test]
fn service_commands_are_sent_once() {
    let (mut l, peer, _) = link(vec![None, Some(b"DONE\r")]);
    let e = l.exchange(&Request::Save).unwrap_err();
    assert_eq!(sent(&peer), vec!["SAVE!"]);
    assert!(e.to_string().contains("it is not sent again"), "{e}");
    let (mut l, _, _) = link(vec![Some(b"DONE\r")]);
    assert_eq!(l.exchange(&Request::Save).unwrap(), Reply::Done);
}

#[test]
fn every_other_command_gets_its_reply() {
    let cases: Vec<(Request, &[u8], Reply)> = vec![
        (Request::Type, b"TYPE:0931\r", Reply::Type("0931".into())),
        (
            Request::Version,
            b"0000:VERSION:0102\r",
            Reply::Version {
                status: "0000".into(),
                version: "0102".into(),
            },
        ),
        (
            Request::Boot,
            b"APPLICATION\r",
            Reply::Boot(super::super::codec::BootState::Application),
        ),
        (Request::Sep, b"DONE\r", Reply::Done),
        (
            Request::Reset,
            b"931E ready\r",
            Reply::SwitchOn("931E ready".into()),
        ),
        (Request::Baud(9600), b"OK!\r", Reply::Ok),
        (
            Request::SdoWrite {
                index: 0x6040,
                subindex: 0,
                data: vec![6, 0],
            },
            b"=604000:0600\r",
            Reply::Sdo {
                index: 0x6040,
                subindex: 0,
                data: vec![6, 0],
            },
        ),
        (
            Request::SdoRead {
                index: 0x6041,
                subindex: 0,
            },
            b"=604100:3702\r",
            Reply::Sdo {
                index: 0x6041,
                subindex: 0,
                data: vec![0x37, 2],
            },
        ),
        (Request::Bus, b"ERROR!\r", Reply::UnknownCommand),
    ];
    for (request, wire, expected) in cases {
        let (mut l, _, _) = link(vec![Some(wire)]);
        assert_eq!(l.exchange(&request).unwrap(), expected, "{request}");
    }
}

mod properties {
    use super::*;
    use proptest::prelude::*;

    fn reply_strategy() -> impl Strategy<Value = Option<Vec<u8>>> {
        prop_oneof![
            Just(None),
            Just(Some(b"OK!\r".to_vec())),
            Just(Some(b"0010:00000BB8\r".to_vec())),
            Just(Some(b"0010:00000000\r".to_vec())),
            Just(Some(b"OW:0000 0005\r".to_vec())),
            proptest::collection::vec(any::<u8>(), 0..300).prop_map(Some),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Whatever comes back, a write is never sent again without a read-back between,
        /// nothing panics, and the link gives up within its attempts.
        #[test]
        fn a_write_is_never_repeated_blind(script in proptest::collection::vec(reply_strategy(), 0..8)) {
            let script: Vec<Option<&[u8]>> = script.iter().map(|r| r.as_deref()).collect();
            let (mut l, peer, _) = link(script);
            let _ = l.exchange(&WRITE_3000);
            let sent = sent(&peer);
            prop_assert!(sent.len() <= 5, "{:?}", sent);
            for pair in sent.windows(2) {
                prop_assert!(!(pair[0].starts_with("OW") && pair[1].starts_with("OW")), "{:?}", sent);
            }
        }

        #[test]
        fn reads_survive_any_bytes(script in proptest::collection::vec(reply_strategy(), 0..4)) {
            let script: Vec<Option<&[u8]>> = script.iter().map(|r| r.as_deref()).collect();
            let (mut l, peer, _) = link(script);
            let _ = l.exchange(&READ_11);
            prop_assert!(sent(&peer).len() <= 3);
        }
    }
}

#[test]
fn maintenance_actions_read_error_and_unknown_replies_as_failures() {
    use crate::drive::ObjectAccess;
    use crate::family::lenze_931::LenzeAccess;
    // ERROR!: the drive does not know the command.
    let (l, peer, _) = link(vec![Some(b"ERROR!\r")]);
    let e = LenzeAccess::new(l).maintain("reset", None).unwrap().unwrap_err();
    assert!(
        e.to_string()
            .contains("refused to carry out object RESET!: the drive answered ERROR!"),
        "{e}"
    );
    assert_eq!(sent(&peer), ["RESET!"]);
    // A reply other than the documented one, sent once and not again.
    let (l, peer, _) = link(vec![Some(b"OK!\r"), Some(b"DONE\r")]);
    let e = LenzeAccess::new(l).maintain("load", None).unwrap().unwrap_err();
    assert!(
        e.to_string()
            .contains("\"OK!\" does not answer \"SEP!\": expected `DONE`"),
        "{e}"
    );
    assert!(e.to_string().contains("it is not sent again"), "{e}");
    assert_eq!(sent(&peer), ["SEP!"]);
    let (l, _, _) = link(vec![Some(b"DONE\r")]);
    assert!(LenzeAccess::new(l)
        .maintain("baud", Some(19200))
        .unwrap()
        .is_err());
    // Whatever a switch-on message says is taken as it, word for word.
    let (l, _, _) = link(vec![Some(b"LENZE 931 V1.0\r")]);
    let outcome = LenzeAccess::new(l).maintain("init", None).unwrap().unwrap();
    assert_eq!(outcome.reply, "LENZE 931 V1.0");
    assert_eq!(outcome.line_rate, None);
    // A value the codec cannot send is refused before anything is sent.
    let (l, peer, _) = link(vec![]);
    assert!(LenzeAccess::new(l)
        .maintain("baud", Some(2_000_000))
        .unwrap()
        .is_err());
    assert!(sent(&peer).is_empty());
}
