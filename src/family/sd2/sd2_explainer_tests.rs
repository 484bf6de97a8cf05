//! The one-line summaries, the JSON and the traces of the SD2 explainer.

use super::*;
use crate::family::sd2::codec::{ErrorCode, WriteLength};
use crate::hex::parse_hex;
use crate::link::TelegramObserver;
use crate::report::{hex_of_trace_line, is_trace_line, TraceHeader, TraceWriter};
use std::io::Write;
use std::path::Path;
use std::time::Duration;

fn explainer() -> Box<dyn TelegramExplainer> {
    Box::new(Sd2Explainer::new(Arc::new(
        crate::family::Registry::builtin().load_dictionary("sd2").unwrap(),
    )))
}

/// Line `i` of the trace ends with `end`; the message shows the whole line when not.
fn ends(l: &[String], i: usize, end: &str) {
    assert!(l[i].ends_with(end), "{}", l[i]);
}

fn send(trace: &mut TraceWriter<Vec<u8>>, ms: u64, direction: Direction, t: &Telegram) {
    let bytes = t.encode(WriteLength::Captured);
    trace.telegram(Duration::from_millis(ms), direction, &bytes);
}

fn lines(trace: TraceWriter<Vec<u8>>) -> Vec<String> {
    String::from_utf8(trace.into_inner())
        .unwrap()
        .lines()
        .map(String::from)
        .collect()
}

fn read_reply(data: &[u8], error: ErrorCode) -> Telegram {
    Telegram {
        dest: 1,
        source: 2,
        body: Body::ReadReply {
            error,
            data: Data::new(data).unwrap(),
        },
    }
}

#[test]
fn read_and_its_reply_are_named() {
    let mut trace = TraceWriter::new(Vec::new(), explainer());
    send(
        &mut trace,
        12,
        Direction::Sent,
        &Telegram::read_request(2, 1, 67, 0),
    );
    send(
        &mut trace,
        14,
        Direction::Received,
        &read_reply(&[0x37, 0x02], ErrorCode::OK),
    );
    let l = lines(trace);
    assert_eq!(
        l[0],
        "    0.012000 TX 00 09 02 01 0d 43 00 00 00 00 00 a3  # read object 67 status_word"
    );
    assert!(l[1].starts_with("    0.014000 RX 00 "), "{}", l[1]);
    ends(&l, 1, "  # reply status_word = 0x0237 operation enabled");
}

#[test]
fn writes_and_write_replies() {
    let mut trace = TraceWriter::new(Vec::new(), explainer());
    let w = Telegram::write_request(2, 1, 395, 0, &6_000_000i32.to_le_bytes()).unwrap();
    send(&mut trace, 1, Direction::Sent, &w);
    let ok = Telegram {
        dest: 1,
        source: 2,
        body: Body::WriteReply { error: ErrorCode::OK },
    };
    send(&mut trace, 2, Direction::Received, &ok);
    let cw = Telegram::write_request(2, 1, 68, 0, &[0x06, 0x00]).unwrap();
    send(&mut trace, 3, Direction::Sent, &cw);
    let refused = Telegram {
        body: Body::WriteReply {
            error: ErrorCode::READ_ONLY,
        },
        ..ok
    };
    send(&mut trace, 4, Direction::Received, &refused);
    let l = lines(trace);
    ends(&l, 0, "# write object 395 speed_setpoint = 6000 rpm");
    ends(&l, 1, "# write reply ok");
    ends(&l, 2, "# write object 68 control_word = 0x0006 shutdown");
    ends(&l, 3, "# write reply 0x8A attempt to write a read-only object");
}

#[test]
fn read_errors_unknown_objects_and_orphan_replies() {
    let mut trace = TraceWriter::new(Vec::new(), explainer());
    send(
        &mut trace,
        0,
        Direction::Received,
        &read_reply(&[0x7f, 0x50, 0x0f, 0x00], ErrorCode::OK),
    );
    send(
        &mut trace,
        1,
        Direction::Sent,
        &Telegram::read_request(2, 1, 9999, 0),
    );
    send(
        &mut trace,
        2,
        Direction::Received,
        &read_reply(&[], ErrorCode::OBJECT_DOES_NOT_EXIST),
    );
    send(
        &mut trace,
        3,
        Direction::Sent,
        &Telegram::read_request(2, 1, 398, 0),
    );
    send(
        &mut trace,
        4,
        Direction::Received,
        &read_reply(&[0x7f, 0x50, 0x0f, 0x00], ErrorCode::OK),
    );
    let l = lines(trace);
    ends(&l, 0, "# reply 1003647 (request not seen)");
    ends(&l, 1, "# read object 9999 (not in the dictionary)");
    ends(
        &l,
        2,
        "# read reply 0x8B object does not exist in the object dictionary",
    );
    ends(&l, 4, "# reply speed_actual = 1003.647 rpm");
}

#[test]
fn cyclic_telegrams() {
    let mut trace = TraceWriter::new(Vec::new(), explainer());
    let req = Telegram {
        dest: 2,
        source: 1,
        body: Body::CyclicRequest(Cyclic::request(0x000f, 4095, true)),
    };
    send(&mut trace, 0, Direction::Sent, &req);
    let reply = Telegram {
        dest: 1,
        source: 2,
        body: Body::CyclicReply(Cyclic::reply([0, 0], 0x0237, 4095, 0, 12)),
    };
    send(&mut trace, 1, Direction::Received, &reply);
    let l = lines(trace);
    ends(&l, 0, "# cyclic control 0x000f enable operation, speed 25.0 %");
    assert!(
        l[1].ends_with(
            "# cyclic reply status 0x0237 operation enabled, speed 25.0 %, drive error 0, current 12"
        ),
        "{}",
        l[1]
    );
}

#[test]
fn rejected_blocks_and_events() {
    let mut trace = TraceWriter::new(Vec::new(), explainer());
    let bytes = parse_hex("00 09 01 02 8d 02 00 37 02 00").unwrap();
    trace.telegram(Duration::from_micros(1_500_250), Direction::Received, &bytes);
    trace.event(Duration::from_secs(2), "no reply within 100 ms\n(retry follows)");
    trace.comment("a note");
    let l = lines(trace);
    assert_eq!(
        l[0],
        "    1.500250 RX 00 09 01 02 8d 02 00 37 02 00  # rejected: truncated: needed 12 bytes \
         (length field 0x09), have 10"
    );
    assert_eq!(l[1], "    2.000000 -- no reply within 100 ms (retry follows)");
    assert_eq!(l[2], "# a note");
    assert_eq!(hex_of_trace_line(&l[0]), Some("00 09 01 02 8d 02 00 37 02 00"));
    assert_eq!(hex_of_trace_line(&l[1]), None);
    assert_eq!(hex_of_trace_line(&l[2]), None);
}

#[test]
fn hex_is_read_back_from_every_kind_of_line() {
    let mut trace = TraceWriter::new(Vec::new(), explainer());
    let sent = Telegram::write_request(2, 1, 395, 0, &6_000_000i32.to_le_bytes()).unwrap();
    send(&mut trace, 7_200_000, Direction::Sent, &sent);
    // Past the column width (100 h) the line only grows.
    send(&mut trace, 360_000_000, Direction::Sent, &sent);
    let l = lines(trace);
    assert!(l[0].starts_with(" 7200.000000 TX 00 0b "), "{}", l[0]);
    assert!(l[1].starts_with("360000.000000 TX 00 0b "), "{}", l[1]);
    assert_eq!(hex_of_trace_line(&l[1]), hex_of_trace_line(&l[0]));
    let hex = hex_of_trace_line(&l[0]).unwrap();
    let bytes = parse_hex(hex).unwrap();
    assert_eq!(Telegram::decode(&bytes).unwrap(), sent);

    assert_eq!(hex_of_trace_line("    0.5 TX 00 0b  # x # y"), Some("00 0b"));
    assert_eq!(hex_of_trace_line("0.5 RX 00 0b"), Some("00 0b"));
    assert_eq!(hex_of_trace_line("0.5 RX (no bytes)  # rejected: no bytes"), None);
    assert_eq!(hex_of_trace_line("# drivescript telegram trace"), None);
    assert_eq!(hex_of_trace_line("00 0b 02 01"), None);
    assert_eq!(hex_of_trace_line("0.5 TXT 00"), None);
    assert_eq!(hex_of_trace_line(""), None);

    for line in [
        l[0].as_str(),
        "    2.000000 -- no reply within 100 ms",
        "# comment",
    ] {
        assert!(is_trace_line(line), "{line}");
    }
    for line in ["00 09 02 01 0d 43 00", "000902010d", "0x00 0x09", "", "1.5 17 00"] {
        assert!(!is_trace_line(line), "{line}");
    }
}

#[test]
fn a_trace_file_is_flushed_line_by_line() {
    let dir = std::env::temp_dir().join(format!("drivescript-trace-{}", std::process::id()));
    let path = dir.join("sub/run.trace");
    let mut trace = TraceWriter::create(&path, &TraceHeader::default(), false, explainer()).unwrap();
    send_file(&mut trace);
    // Read while the writer is alive: the line is there already.
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("# drivescript telegram trace"), "{text}");
    let hex: Vec<&str> = text.lines().filter_map(hex_of_trace_line).collect();
    assert_eq!(hex, vec!["00 09 02 01 0d 43 00 00 00 00 00 a3"]);
    drop(trace);
    std::fs::remove_dir_all(&dir).unwrap();

    let err = TraceWriter::create(
        Path::new("/proc/no/such/dir/x.trace"),
        &TraceHeader::default(),
        false,
        explainer(),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(err.contains("/proc/no/such/dir"), "{err}");
}

fn send_file(trace: &mut TraceWriter<std::fs::File>) {
    let t = Telegram::read_request(2, 1, 67, 0);
    trace.telegram(Duration::ZERO, Direction::Sent, &t.encode(WriteLength::Captured));
}

#[test]
fn write_errors_do_not_reach_the_link() {
    struct Broken;
    impl Write for Broken {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::Error::other("disk full"))
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let mut trace = TraceWriter::new(Broken, explainer());
    trace.event(Duration::ZERO, "x");
    trace.event(Duration::ZERO, "y");
    assert_eq!(trace.error(), Some("disk full"));
}
