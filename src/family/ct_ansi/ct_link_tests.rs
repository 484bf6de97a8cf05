//! The CT ANSI link against scripted drives: retries, NAK, group writes, the baud-rate
//! change, stop requests and every shape of echo.

use super::*;
use crate::bus::{MemoryTransport, Peer, PeerReply, ScriptedPeer};
use crate::clock::{Clock, VirtualClock};
use crate::family::ct_ansi::codec::{DataValue, Parameter, ACK, NAK};
use crate::link::TelegramObserver;
use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::Mutex;

fn link(script: Vec<Option<Vec<u8>>>) -> (CtLink, Arc<Mutex<ScriptedPeer>>, Arc<VirtualClock>) {
    let peer = ScriptedPeer::new(script, Duration::from_millis(1));
    let (line, clock) = ScriptedPeer::line(&peer);
    let link = CtLink::new(line, clock.clone(), CtLinkConfig::default());
    (link, peer, clock)
}

fn read_121() -> Request {
    Request::Read {
        address: NodeAddress::new(1, 2).unwrap(),
        parameter: Parameter::new(1, 21).unwrap(),
    }
}

/// The reply carrying `digits` (one decimal place) of parameter `menu`.`param`.
fn value(menu: u8, param: u8, digits: i64) -> Reply {
    Reply::Value {
        parameter: Parameter::new(menu, param).unwrap(),
        value: DataValue::new(digits, 1),
    }
}

fn value_reply(menu: u8, param: u8, digits: i64) -> Vec<u8> {
    value(menu, param, digits).encode().unwrap()
}

/// The write of 1500.5 to #1.21 at `address` (`None`: a rewrite to the last address).
fn write_121_to(address: Option<(u8, u8)>) -> Request {
    Request::Write {
        address: address.map(|(group, unit)| NodeAddress::new(group, unit).unwrap()),
        parameter: Parameter::new(1, 21).unwrap(),
        value: DataValue::new(15005, 1),
    }
}

#[test]
fn a_read_returns_the_exact_value() {
    let (mut l, peer, _) = link(vec![Some(b"\x020121-47.6\x037".to_vec())]);
    let reply = l.transact(&read_121()).unwrap();
    assert_eq!(reply, Some(value(1, 21, -476)));
    assert_eq!(peer.lock().unwrap().sent()[0], b"\x0411220121\x05");
}

#[test]
fn a_damaged_reply_is_retried_and_a_lost_one_after_the_timeout() {
    let mut bad = value_reply(1, 21, 15005);
    let last = bad.len() - 1;
    bad[last] ^= 0x01;
    let (mut l, peer, clock) = link(vec![Some(bad), None, Some(value_reply(1, 21, 15005))]);
    assert!(l.transact(&read_121()).unwrap().is_some());
    assert_eq!(peer.lock().unwrap().received.len(), 3);
    assert_eq!(
        (l.stats().corrupt_replies, l.stats().timeouts, l.stats().retries),
        (1, 1, 2)
    );
    assert!(clock.now() >= Duration::from_secs(1));
}

#[test]
fn a_reply_for_another_parameter_is_refused_then_reported() {
    let other = || Some(value_reply(1, 22, 1));
    let (mut l, _, _) = link(vec![other(), other(), other()]);
    let e = l.transact(&read_121()).unwrap_err().to_string();
    assert!(e.contains("reply for parameter #1.22, expected #1.21"), "{e}");
    assert!(e.contains("EOT 11220121 ENQ: read #1.21"), "{e}");
}

#[test]
fn silence_names_port_drive_and_message() {
    let (mut l, peer, _) = link(vec![None, None, None]);
    let e = l.transact(&read_121()).unwrap_err();
    assert!(e.is_no_reply());
    let text = e.to_string();
    assert!(text.starts_with("no reply from drive 1.2 on scripted"), "{text}");
    assert!(text.contains("3 attempt(s)"), "{text}");
    assert_eq!(peer.lock().unwrap().received.len(), 3);
}

#[test]
fn a_group_write_gets_no_reply_and_is_sent_once() {
    let (mut l, peer, clock) = link(vec![None, None, None]);
    let write = write_121_to(Some((1, 0)));
    assert_eq!(l.transact(&write).unwrap(), None);
    assert_eq!(peer.lock().unwrap().received.len(), 1);
    assert_eq!(l.stats().retries, 0);
    // No reply wait at all: only the turnaround before the message.
    assert!(clock.now() < Duration::from_millis(10), "{:?}", clock.now());
}

#[test]
fn a_nak_is_the_drives_answer_and_not_retried() {
    let (mut l, peer, _) = link(vec![Some(vec![0x15])]);
    let write = write_121();
    assert_eq!(l.transact(&write).unwrap(), Some(Reply::Refused));
    assert_eq!(peer.lock().unwrap().received.len(), 1);
}

#[test]
fn the_turnaround_pause_separates_messages() {
    let (mut l, _, clock) = link(vec![Some(value_reply(1, 21, 1)), Some(value_reply(1, 21, 1))]);
    l.transact(&read_121()).unwrap();
    let first = clock.now();
    l.transact(&read_121()).unwrap();
    // Turnaround (2 ms) plus the drive's 1 ms answer.
    assert_eq!(clock.now() - first, Duration::from_millis(3));
}

/// What the line hands back, piece by piece, `ms` after each message has arrived.
enum Piece {
    /// The first `n` bytes of the message itself (`usize::MAX`: all of it).
    Echo(usize),
    Bytes(Vec<u8>),
}

/// A line whose adapter may echo: each message gets the next scripted pieces.
struct Timed {
    script: VecDeque<Vec<(u64, Piece)>>,
    received: usize,
}

impl Peer for Timed {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        self.received += 1;
        let pieces = self.script.pop_front().unwrap_or_default();
        pieces
            .into_iter()
            .map(|(ms, piece)| PeerReply {
                at: now + Duration::from_millis(ms),
                bytes: match piece {
                    Piece::Echo(n) => bytes[..n.min(bytes.len())].to_vec(),
                    Piece::Bytes(b) => b,
                },
            })
            .collect()
    }
}

struct Events(Arc<Mutex<Vec<String>>>);

impl TelegramObserver for Events {
    fn telegram(&mut self, _: Duration, _: Direction, _: &[u8]) {}
    fn event(&mut self, _: Duration, text: &str) {
        self.0.lock().unwrap().push(text.to_string());
    }
}

struct TimedLink {
    link: CtLink,
    peer: Arc<Mutex<Timed>>,
    clock: Arc<VirtualClock>,
    events: Arc<Mutex<Vec<String>>>,
}

impl TimedLink {
    /// Fails the test unless the link traced `event`, showing what it traced.
    #[track_caller]
    fn assert_traced(&self, event: &str) {
        let events = self.events.lock().unwrap();
        assert!(events.iter().any(|e| e == event), "{events:?}");
    }
}

fn timed(script: Vec<Vec<(u64, Piece)>>) -> TimedLink {
    let clock = Arc::new(VirtualClock::new());
    let peer = Arc::new(Mutex::new(Timed {
        script: script.into(),
        received: 0,
    }));
    let mut link = CtLink::new(
        MemoryTransport::shared("echoing", peer.clone(), clock.clone()),
        clock.clone(),
        CtLinkConfig::default(),
    );
    let events = Arc::new(Mutex::new(Vec::new()));
    link.set_observer(Box::new(Events(events.clone())));
    TimedLink {
        link,
        peer,
        clock,
        events,
    }
}

const ALL: usize = usize::MAX;

fn echo_then(reply: Vec<u8>) -> Vec<(u64, Piece)> {
    vec![(0, Piece::Echo(ALL)), (1, Piece::Bytes(reply))]
}

fn write_121() -> Request {
    write_121_to(Some((1, 2)))
}

/// A group write's echo comes back late on a slow adapter; its tail reads exactly like
/// a value reply of the same parameter, so it must be gone before the next message.
#[test]
fn a_late_echo_of_a_group_write_is_never_the_next_reads_reply() {
    let group_write = write_121_to(Some((1, 0)));
    let mut l = timed(vec![
        vec![(5, Piece::Echo(ALL))],
        vec![(0, Piece::Echo(ALL)), (10, Piece::Bytes(value_reply(1, 21, 42)))],
    ]);
    assert_eq!(l.link.transact(&group_write).unwrap(), None);
    let reply = l.link.transact(&read_121()).unwrap();
    assert_eq!(reply, Some(value(1, 21, 42)));
}

#[test]
fn the_echo_of_a_read_is_skipped_counted_and_traced() {
    let mut l = timed(vec![echo_then(value_reply(1, 21, 15005))]);
    let reply = l.link.transact(&read_121()).unwrap();
    assert_eq!(reply, Some(value(1, 21, 15005)));
    let stats = l.link.stats();
    assert_eq!((stats.echoes, stats.retries, stats.corrupt_replies), (1, 0, 0));
    l.assert_traced("echo of our message skipped: EOT 11220121 ENQ");
}

#[test]
fn the_echo_of_a_write_is_never_its_ack() {
    let mut l = timed(vec![echo_then(vec![ACK]), echo_then(vec![NAK])]);
    assert_eq!(l.link.transact(&write_121()).unwrap(), Some(Reply::Accepted));
    assert_eq!(l.link.transact(&write_121()).unwrap(), Some(Reply::Refused));
    assert_eq!(l.link.stats().echoes, 2);
    // A rewrite (no address) echoes as a data block, which is no answer to it either.
    let rewrite = write_121_to(None);
    let mut l = timed(vec![echo_then(vec![ACK])]);
    assert_eq!(l.link.transact(&rewrite).unwrap(), Some(Reply::Accepted));
    assert_eq!(l.link.stats().mismatched_replies, 0);
}

#[test]
fn a_short_command_echoed_as_ack_is_not_an_answer() {
    let mut l = timed(vec![echo_then(value_reply(1, 22, 7))]);
    let reply = l.link.transact(&Request::ReadNext).unwrap();
    assert!(matches!(reply, Some(Reply::Value { .. })), "{reply:?}");
    assert_eq!(l.link.stats().echoes, 1);
}

#[test]
fn an_echo_without_a_reply_times_out_and_says_so() {
    for request in [read_121(), write_121()] {
        let only_echo = || vec![(0, Piece::Echo(ALL))];
        let mut l = timed(vec![only_echo(), only_echo(), only_echo()]);
        let e = l.link.transact(&request).unwrap_err();
        assert!(e.is_no_reply(), "{e}");
        let text = e.to_string();
        assert!(
            text.contains("the echo of the message came back (the RS485 adapter echoes what it sends; drivescript skips it), but the drive did not answer"),
            "{text}"
        );
        let stats = l.link.stats();
        assert_eq!(
            (
                stats.echoes,
                stats.timeouts,
                stats.corrupt_replies,
                stats.mismatched_replies
            ),
            (3, 3, 0, 0)
        );
        l.assert_traced("no reply within 1000 ms after the echo of our message");
    }
}

#[test]
fn a_broken_echo_is_dropped_and_the_reply_after_the_garbage_is_read() {
    let mut l = timed(vec![vec![
        (0, Piece::Echo(4)),
        (0, Piece::Bytes(b"?x".to_vec())),
        (1, Piece::Bytes(value_reply(1, 21, 15005))),
    ]]);
    assert!(matches!(
        l.link.transact(&read_121()),
        Ok(Some(Reply::Value { .. }))
    ));
    assert_eq!(l.link.stats().echoes, 1);
    let events = l.events.lock().unwrap().join("\n");
    assert!(
        events.contains("skipped 4 byte(s) that began an echo of our message and broke off: EOT 112"),
        "{events}"
    );
    assert!(events.contains("skipped 2 byte(s) of line noise"), "{events}");
}

#[test]
fn a_write_echo_broken_by_garbage_is_neither_an_ack_nor_data() {
    // `EOT 1122 STX 01`, two bytes of garbage, then the rest of the echo: nothing of it
    // is an answer, and without one the write fails as unanswered.
    let write = write_121().encode().unwrap();
    let piece = || {
        vec![
            (0, Piece::Echo(8)),
            (0, Piece::Bytes(b"zz".to_vec())),
            (0, Piece::Bytes(write[8..].to_vec())),
        ]
    };
    let mut l = timed(vec![piece(), piece(), piece()]);
    let e = l.link.transact(&write_121()).unwrap_err();
    assert!(e.is_no_reply(), "{e}");
    let stats = l.link.stats();
    assert_eq!(
        (stats.echoes, stats.corrupt_replies, stats.mismatched_replies),
        (3, 0, 0)
    );
    // The same with the drive's ACK after it: the ACK is the answer.
    let mut with_ack = piece();
    with_ack.push((1, Piece::Bytes(vec![ACK])));
    let mut l = timed(vec![with_ack]);
    assert_eq!(l.link.transact(&write_121()).unwrap(), Some(Reply::Accepted));
}

#[test]
fn a_partial_echo_and_then_silence_says_how_much_came_back() {
    let part = || vec![(0, Piece::Echo(4))];
    let mut l = timed(vec![part(), part(), part()]);
    let e = l.link.transact(&read_121()).unwrap_err().to_string();
    assert!(
        e.contains("only the first 4 byte(s) of the echo of the message came back"),
        "{e}"
    );
}

#[test]
fn a_lone_eot_is_the_drives_answer_once_nothing_follows_it() {
    // Unknown line: the EOT waits the echo window, then counts as the drive's answer.
    let eot = || vec![(1, Piece::Bytes(vec![EOT]))];
    let mut l = timed(vec![eot(), vec![(1, Piece::Bytes(value_reply(1, 21, 1)))], eot()]);
    let start = l.clock.now();
    assert_eq!(
        l.link.transact(&read_121()).unwrap(),
        Some(Reply::NoSuchParameter)
    );
    assert!(l.clock.now() - start >= Duration::from_millis(50));
    assert!(l
        .events
        .lock()
        .unwrap()
        .iter()
        .any(|e| e.contains("EOT and nothing after it for 50 ms")));
    // A reply with nothing before it shows the line does not echo: no more waiting.
    l.link.transact(&read_121()).unwrap();
    let before = l.clock.now();
    assert_eq!(
        l.link.transact(&read_121()).unwrap(),
        Some(Reply::NoSuchParameter)
    );
    assert_eq!(l.clock.now() - before, Duration::from_millis(3));
}

#[test]
fn on_an_echoing_line_a_lone_eot_is_the_start_of_the_echo() {
    // The echo comes back in two batches, the second long after the first (a slow USB
    // adapter); the drive then answers EOT: the parameter does not exist.
    let split_echo = |gap: u64| {
        vec![
            (0, Piece::Echo(1)),
            (gap, Piece::Bytes(b"11220121\x05".to_vec())),
            (gap + 1, Piece::Bytes(vec![EOT])),
        ]
    };
    let mut l = timed(vec![split_echo(30), split_echo(300)]);
    assert_eq!(
        l.link.transact(&read_121()).unwrap(),
        Some(Reply::NoSuchParameter)
    );
    // Known to echo now: even a 300 ms gap after EOT is still the echo.
    assert_eq!(
        l.link.transact(&read_121()).unwrap(),
        Some(Reply::NoSuchParameter)
    );
    assert_eq!(l.link.stats().echoes, 2);
    assert_eq!(l.peer.lock().unwrap().received, 2);
}

fn baud_link(script: Vec<Option<Vec<u8>>>) -> (CtLink, Arc<Mutex<ScriptedPeer>>, Arc<VirtualClock>) {
    let (l, peer, clock) = link(script);
    let config = CtLinkConfig {
        baud_parameter: Parameter::new(11, 25),
        ..CtLinkConfig::default()
    };
    let transport = l.transport.clone();
    (CtLink::new(transport, clock.clone(), config), peer, clock)
}

fn write_to(menu: u8, param: u8, unit: u8, digits: i64) -> Request {
    Request::Write {
        address: Some(NodeAddress::new(1, unit).unwrap()),
        parameter: Parameter::new(menu, param).unwrap(),
        value: DataValue::new(digits, 0),
    }
}

#[test]
fn an_accepted_baud_rate_write_waits_20_ms_and_then_nothing_more_is_sent() {
    let (mut l, peer, clock) = baud_link(vec![Some(vec![ACK]), Some(vec![ACK])]);
    // Another parameter: no wait beyond the turnaround and the 1 ms answer.
    l.transact(&write_to(1, 21, 2, 15)).unwrap();
    let before = clock.now();
    let e = l.transact(&write_to(11, 25, 2, 6)).unwrap_err();
    // Turnaround 2 ms, the ACK 1 ms later (at the old rate), then the 20 ms wait.
    assert_eq!(clock.now() - before, Duration::from_millis(2 + 1 + 20));
    let text = e.to_string();
    assert!(
        text.starts_with(
            "drive 1.2 on scripted: the write of #11.25 = 6 was accepted (ACK), and drivescript waited 20 ms"
        ),
        "{text}"
    );
    assert!(
        text.contains("restart drivescript with --baud set to the new rate"),
        "{text}"
    );
    // Later messages are not sent at the old rate, and fail at once.
    let at = clock.now();
    let e = l.transact(&read_121()).unwrap_err().to_string();
    assert!(
        e.contains("the write of #11.25 = 6 changed the drive's baud rate"),
        "{e}"
    );
    assert_eq!(clock.now(), at);
    assert_eq!(peer.lock().unwrap().received.len(), 2);
}

#[test]
fn a_refused_baud_rate_write_changes_nothing() {
    let (mut l, _, clock) = baud_link(vec![Some(vec![NAK]), Some(value_reply(1, 21, 1))]);
    let before = clock.now();
    assert_eq!(
        l.transact(&write_to(11, 25, 2, 99)).unwrap(),
        Some(Reply::Refused)
    );
    assert_eq!(clock.now() - before, Duration::from_millis(3));
    assert!(l.transact(&read_121()).is_ok());
}

#[test]
fn a_group_baud_rate_write_also_waits_before_giving_up_the_line() {
    let (mut l, peer, clock) = baud_link(vec![None]);
    let before = clock.now();
    let e = l.transact(&write_to(11, 25, 0, 6)).unwrap_err().to_string();
    // Turnaround, then the echo window of a line not yet known not to echo (the group
    // write's quiet time), then the drive's 20 ms.
    assert_eq!(clock.now() - before, Duration::from_millis(2 + 50 + 20));
    assert!(e.contains("(a group or global write: no drive answers)"), "{e}");
    assert_eq!(peer.lock().unwrap().received.len(), 1);
}

#[test]
fn an_unanswered_baud_rate_write_says_the_rate_may_have_changed() {
    let (mut l, _, _) = baud_link(vec![None, None, None, Some(value_reply(1, 21, 1))]);
    let e = l.transact(&write_to(11, 25, 2, 6)).unwrap_err();
    assert!(e.is_no_reply(), "{e}");
    assert!(
        e.to_string().ends_with("if the write of #11.25 = 6 reached the drive, it now talks at the new baud rate: then restart drivescript with --baud set to it"),
        "{e}"
    );
    // Not known to have changed: the link still talks at the rate it has.
    assert!(l.transact(&read_121()).is_ok());
}

#[test]
fn noise_before_the_echo_does_not_turn_its_eot_into_an_answer() {
    let mut l = timed(vec![vec![
        (0, Piece::Bytes(vec![0x00, 0x7f])),
        (0, Piece::Echo(ALL)),
        (1, Piece::Bytes(value_reply(1, 21, 15005))),
    ]]);
    assert!(matches!(
        l.link.transact(&read_121()),
        Ok(Some(Reply::Value { .. }))
    ));
    assert_eq!(l.link.stats().echoes, 1);
}

mod properties {
    use super::*;
    use proptest::prelude::*;

    fn exchange() -> impl Strategy<Value = (Request, Reply)> {
        let par = (0u8..=99, 0u8..=99).prop_map(|(m, p)| Parameter { menu: m, param: p });
        let value = (-99_999i64..99_999, 0u8..=3).prop_map(|(d, p)| DataValue::new(d, p));
        let address = (0u8..=9, 1u8..=9).prop_map(|(g, u)| NodeAddress { group: g, unit: u });
        prop_oneof![
            (address.clone(), par.clone(), value.clone(), any::<bool>()).prop_map(
                |(address, parameter, value, missing)| {
                    let reply = if missing {
                        Reply::NoSuchParameter
                    } else {
                        Reply::Value { parameter, value }
                    };
                    (Request::Read { address, parameter }, reply)
                }
            ),
            (proptest::option::of(address), par, value, any::<bool>()).prop_map(
                |(address, parameter, value, ok)| {
                    let reply = if ok { Reply::Accepted } else { Reply::Refused };
                    (
                        Request::Write {
                            address,
                            parameter,
                            value,
                        },
                        reply,
                    )
                }
            ),
        ]
    }

    proptest! {
        /// With or without an echo, with or without noise before it, whatever the
        /// drive answers is what the link returns: never the echo.
        #[test]
        fn the_answer_is_the_drives_never_the_echo(
            (request, reply) in exchange(),
            echo in any::<bool>(),
            noise in proptest::collection::vec(0x20u8..0x7f, 0..3),
            delay in 1u64..80,
        ) {
            let mut pieces = vec![(0, Piece::Bytes(noise))];
            if echo {
                pieces.push((0, Piece::Echo(ALL)));
            }
            pieces.push((delay, Piece::Bytes(reply.encode().unwrap())));
            let mut l = timed(vec![pieces]);
            prop_assert_eq!(l.link.transact(&request).unwrap(), Some(reply));
            prop_assert_eq!(l.link.stats().echoes, u64::from(echo));
            prop_assert_eq!(l.link.stats().retries, 0);
        }
    }
}
