//! The link against the simulated inverter and against scripted replies: reads and
//! writes, broadcast without a reply, a wrong slave, a bad CRC and a late TCP reply
//! retried with located errors, and the inter-frame silence.

use super::*;
use crate::bus::{MemoryTransport, Peer, PeerReply, ScriptedPeer};
use crate::clock::{Clock, VirtualClock};
use crate::family::modbus::codec::{ExceptionCode, Function};
use crate::family::modbus::ModbusSimulator;
use crate::sim::{SimConfig, SimulatedDrive};
use std::sync::{Arc, Mutex};

fn link_to(peer: Arc<Mutex<dyn Peer>>, unit: u8, framing: Framing) -> (ModbusLink, Arc<VirtualClock>) {
    let clock = Arc::new(VirtualClock::new());
    let config = LinkConfig {
        framing,
        ..LinkConfig::default()
    };
    (
        ModbusLink::new(
            MemoryTransport::shared("test line", peer, clock.clone()),
            clock.clone(),
            unit,
            config,
        ),
        clock,
    )
}

fn scripted(replies: Vec<Option<Vec<u8>>>) -> Arc<Mutex<ScriptedPeer>> {
    ScriptedPeer::new(replies, Duration::from_millis(2))
}

const READ_STATUS: Request = Request::Read {
    function: Function::ReadHolding,
    start: 0x2000,
    count: 1,
};

fn reply(unit: u8, values: Vec<u16>) -> Vec<u8> {
    rtu::encode(
        unit,
        &Response::Registers {
            function: Function::ReadHolding,
            values,
        }
        .encode(),
    )
}

#[test]
fn reads_and_writes_the_simulated_inverter_over_rtu_and_tcp() {
    for framing in [Framing::Rtu, Framing::Tcp] {
        let sim = Arc::new(Mutex::new(ModbusSimulator::new(3, framing, SimConfig::default())));
        let (mut link, _) = link_to(sim.clone(), 3, framing);
        assert_eq!(
            link.exchange(&READ_STATUS).unwrap(),
            Some(Response::Registers {
                function: Function::ReadHolding,
                values: vec![3]
            })
        );
        let run = Request::WriteSingle {
            address: 0x1001,
            value: 1,
        };
        assert_eq!(
            link.exchange(&run).unwrap(),
            Some(Response::WriteSingle {
                address: 0x1001,
                value: 1
            })
        );
        assert_eq!(
            sim.lock().unwrap().control_words_written(),
            vec![1],
            "{framing:?}"
        );
        let refused = link
            .exchange(&Request::Read {
                function: Function::ReadHolding,
                start: 0x7777,
                count: 1,
            })
            .unwrap();
        assert_eq!(
            refused,
            Some(Response::Exception {
                function: 3,
                code: ExceptionCode::ILLEGAL_DATA_ADDRESS
            })
        );
    }
}

#[test]
fn a_broadcast_write_is_sent_once_and_acted_on_by_every_slave_without_a_reply() {
    let a = Arc::new(Mutex::new(ModbusSimulator::new(
        1,
        Framing::Rtu,
        SimConfig::default(),
    )));
    let (mut link, clock) = link_to(a.clone(), 0, Framing::Rtu);
    let start = clock.now();
    let stop = Request::WriteSingle {
        address: 0x1001,
        value: 3,
    };
    assert_eq!(link.exchange(&stop).unwrap(), None);
    assert_eq!(a.lock().unwrap().control_words_written(), vec![3]);
    assert!(
        clock.now() - start < Duration::from_millis(50),
        "no reply is awaited"
    );
    let e = link.exchange(&READ_STATUS).unwrap_err().to_string();
    assert!(e.contains("broadcast (slave 0) gets no reply"), "{e}");
}

#[test]
fn a_reply_from_another_slave_or_with_a_bad_crc_is_retried_and_named_when_it_persists() {
    let good = reply(1, vec![3]);
    let mut bad_crc = good.clone();
    *bad_crc.last_mut().unwrap() ^= 1;
    let peer = scripted(vec![Some(reply(2, vec![3])), Some(bad_crc.clone()), Some(good)]);
    let (mut link, _) = link_to(peer.clone(), 1, Framing::Rtu);
    assert!(link.exchange(&READ_STATUS).unwrap().is_some());
    let stats = link.stats();
    assert_eq!(
        (stats.mismatched_replies, stats.corrupt_replies, stats.retries),
        (1, 1, 2)
    );

    let peer = scripted(vec![Some(reply(2, vec![3])); 3]);
    let (mut link, _) = link_to(peer, 1, Framing::Rtu);
    let e = link.exchange(&READ_STATUS).unwrap_err().to_string();
    assert!(e.contains("slave 1 on test line"), "{e}");
    assert!(e.contains("it comes from slave 2, not slave 1"), "{e}");
    assert!(
        e.contains("`03 20 00 00 01` (read holding registers 0x2000, 1)"),
        "{e}"
    );
    assert!(e.contains("3 attempt(s)"), "{e}");

    let peer = scripted(vec![Some(bad_crc); 3]);
    let (mut link, _) = link_to(peer, 1, Framing::Rtu);
    let e = link.exchange(&READ_STATUS).unwrap_err().to_string();
    assert!(e.contains("bad CRC"), "{e}");
}

#[test]
fn a_reply_to_another_function_is_retried() {
    let wrong = rtu::encode(
        1,
        &Response::Registers {
            function: Function::ReadInput,
            values: vec![3],
        }
        .encode(),
    );
    let peer = scripted(vec![Some(wrong), Some(reply(1, vec![3]))]);
    let (mut link, _) = link_to(peer, 1, Framing::Rtu);
    assert!(link.exchange(&READ_STATUS).unwrap().is_some());
    assert_eq!(link.stats().mismatched_replies, 1);
}

#[test]
fn a_silent_slave_gives_a_located_error_with_the_advice() {
    let peer = scripted(vec![None, None, None]);
    let (mut link, _) = link_to(peer.clone(), 7, Framing::Rtu);
    let e = link.exchange(&READ_STATUS).unwrap_err().to_string();
    assert!(e.starts_with("no reply from drive slave 7 on test line"), "{e}");
    assert!(e.contains("19200 8E1"), "{e}");
    assert_eq!(peer.lock().unwrap().received.len(), 3);
    // Over Modbus TCP the advice is the server's and the unit id, nothing of a serial line.
    let (mut link, _) = link_to(scripted(vec![None, None, None]), 7, Framing::Tcp);
    let e = link.exchange(&READ_STATUS).unwrap_err().to_string();
    assert!(e.contains("Modbus TCP server") && e.contains("unit id"), "{e}");
    for serial in ["RS485", "baud", "parity"] {
        assert!(!e.contains(serial), "{serial}: {e}");
    }
}

#[test]
fn a_late_tcp_reply_of_an_earlier_transaction_is_dropped() {
    let pdu = Response::Registers {
        function: Function::ReadHolding,
        values: vec![3],
    }
    .encode();
    // The first request's reply comes only together with the second's.
    let mut both = mbap::encode(1, 1, &pdu);
    both.extend(mbap::encode(2, 1, &pdu));
    let peer = scripted(vec![None, Some(both)]);
    let (mut link, _) = link_to(peer, 1, Framing::Tcp);
    assert!(link.exchange(&READ_STATUS).unwrap().is_some());
    assert_eq!(link.stats().timeouts, 1);
}

#[test]
fn frames_are_separated_by_the_silence_of_three_and_a_half_characters() {
    let peer = scripted(vec![Some(reply(1, vec![3])), Some(reply(1, vec![3]))]);
    let (mut link, _) = link_to(peer.clone(), 1, Framing::Rtu);
    link.exchange(&READ_STATUS).unwrap();
    link.exchange(&READ_STATUS).unwrap();
    let received = peer.lock().unwrap().received.clone();
    // The reply ended 2 ms after the first request; the next starts a silence later.
    let gap = received[1].0 - received[0].0;
    assert!(
        gap >= Duration::from_millis(2) + LinkConfig::default().silence,
        "{gap:?}"
    );
}

#[test]
fn a_busy_slave_is_asked_again() {
    let busy = rtu::encode(
        1,
        &Response::Exception {
            function: 3,
            code: ExceptionCode::SERVER_DEVICE_BUSY,
        }
        .encode(),
    );
    let peer = scripted(vec![Some(busy.clone()), Some(reply(1, vec![3]))]);
    let (mut link, _) = link_to(peer, 1, Framing::Rtu);
    assert!(matches!(
        link.exchange(&READ_STATUS).unwrap(),
        Some(Response::Registers { .. })
    ));
    // Busy at every attempt: asked again a reply timeout later each time, and the last
    // "busy" is the slave's answer (a refusal with its own text, not a bad reply).
    let peer = scripted(vec![Some(busy); 3]);
    let (mut link, _) = link_to(peer.clone(), 1, Framing::Rtu);
    assert_eq!(
        link.exchange(&READ_STATUS).unwrap(),
        Some(Response::Exception {
            function: 3,
            code: ExceptionCode::SERVER_DEVICE_BUSY
        })
    );
    let times: Vec<Duration> = peer.lock().unwrap().received.iter().map(|(t, _)| *t).collect();
    assert_eq!(times.len(), 3);
    for pair in times.windows(2) {
        assert!(
            pair[1] - pair[0] >= LinkConfig::default().reply_timeout,
            "{times:?}"
        );
    }
    // "Acknowledge" to a read carries no values: asked again; to a write: accepted.
    let ack = |function: u8| {
        rtu::encode(
            1,
            &Response::Exception {
                function,
                code: ExceptionCode::ACKNOWLEDGE,
            }
            .encode(),
        )
    };
    let peer = scripted(vec![Some(ack(3)), Some(reply(1, vec![7]))]);
    let (mut link, _) = link_to(peer, 1, Framing::Rtu);
    assert!(matches!(
        link.exchange(&READ_STATUS).unwrap(),
        Some(Response::Registers { values, .. }) if values == vec![7]
    ));
}

/// Answers every read, 1.5 s after it came, with the register's own address as its value.
struct Slow;

impl Peer for Slow {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        let start = u16::from_be_bytes([bytes[2], bytes[3]]);
        vec![PeerReply {
            at: now + Duration::from_millis(1500),
            bytes: reply(1, vec![start]),
        }]
    }
}

#[test]
fn a_slave_slower_than_the_timeout_never_gives_a_register_another_ones_value() {
    let (mut link, _) = link_to(Arc::new(Mutex::new(Slow)), 1, Framing::Rtu);
    link.config.reply_timeout = Duration::from_secs(1);
    let seen = Arc::new(Mutex::new(Vec::new()));
    link.set_observer(Box::new(Events(seen.clone())));
    for start in [0x2000, 0xD000, 0xF008, 0x2001] {
        let read = Request::Read {
            function: Function::ReadHolding,
            start,
            count: 1,
        };
        match link.exchange(&read) {
            Ok(Some(Response::Registers { values, .. })) => {
                assert_eq!(
                    values,
                    vec![start],
                    "the read of 0x{start:04X} got another register's value"
                )
            }
            other => panic!("0x{start:04X}: {other:?}"),
        }
    }
    let seen = seen.lock().unwrap().join("\n");
    assert!(seen.contains("late reply(ies) to earlier attempts"), "{seen}");
}

/// The link's events, as a trace shows them.
struct Events(Arc<Mutex<Vec<String>>>);

impl crate::link::TelegramObserver for Events {
    fn telegram(&mut self, _: Duration, _: Direction, _: &[u8]) {}
    fn event(&mut self, _: Duration, text: &str) {
        self.0.lock().unwrap().push(text.to_string());
    }
}

#[test]
fn the_wait_of_a_busy_slave_survives_time_passing_between_its_readings() {
    let busy = rtu::encode(
        1,
        &Response::Exception {
            function: 3,
            code: ExceptionCode::SERVER_DEVICE_BUSY,
        }
        .encode(),
    );
    // Readings that many steps apart: one lands just short of the end of the wait.
    for tick in 1..=20 {
        let clock = Arc::new(crate::clock::TickingClock::new(Duration::from_micros(tick * 300)));
        let peer = scripted(vec![Some(busy.clone()); 3]);
        let mut link = ModbusLink::new(
            MemoryTransport::shared("test line", peer, clock.clone()),
            clock,
            1,
            LinkConfig::default(),
        );
        link.set_stop_requests(Arc::new(crate::stop_request::StopRequests::new()));
        let _ = link.exchange(&READ_STATUS);
    }
}
