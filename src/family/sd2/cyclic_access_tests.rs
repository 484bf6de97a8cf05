//! The cyclic channel against the simulated SD2 drive: the printed telegrams of start-up,
//! stop and the service channel, the period, refusals, a reopen and reads that share one
//! round trip.

use super::*;
use crate::bus::MemoryTransport;
use crate::clock::{Clock, VirtualClock};
use crate::family::sd2::codec::CMD_CYCLIC;
use crate::family::sd2::{LinkConfig, Sd2Link, Sd2Simulator, SimConfig};
use crate::link::{Direction, TelegramObserver};
use crate::sim::SimulatedDrive;
use std::sync::{Arc, Mutex};

/// The cyclic telegrams the engine sent, as bytes.
#[derive(Clone, Default)]
struct Sent(Arc<Mutex<Vec<Vec<u8>>>>);

impl TelegramObserver for Sent {
    fn telegram(&mut self, _at: Duration, direction: Direction, bytes: &[u8]) {
        if direction == Direction::Sent && bytes.get(4) == Some(&CMD_CYCLIC) {
            self.0.lock().unwrap().push(bytes.to_vec());
        }
    }
    fn event(&mut self, _at: Duration, _text: &str) {}
}

impl Sent {
    fn take(&self) -> Vec<String> {
        std::mem::take(&mut *self.0.lock().unwrap())
            .iter()
            .map(|b| crate::hex::to_hex(b))
            .collect()
    }
}

struct Bench {
    access: Sd2CyclicAccess,
    sent: Sent,
    clock: Arc<VirtualClock>,
    sim: Arc<Mutex<Sd2Simulator>>,
}

/// A cyclic access to the simulated drive at DNC address 2 with 24 000 rpm scaling,
/// after `prepare` ran over the object channel.
fn bench(heartbeat: bool, prepare: &[(u16, i64, DataType)]) -> Bench {
    let clock = Arc::new(VirtualClock::new());
    let sim = Arc::new(Mutex::new(Sd2Simulator::new(SimConfig::default())));
    let mut link = Sd2Link::new(
        MemoryTransport::shared("sim", sim.clone(), clock.clone()),
        clock.clone(),
        LinkConfig::default(),
    );
    let sent = Sent::default();
    link.set_observer(Box::new(sent.clone()));
    let mut object = Sd2Access::new(link, 2);
    for (index, value, data_type) in prepare {
        object
            .write(&Address::indexed(*index, 0), &RawValue::Int(*value), *data_type)
            .unwrap();
    }
    let settings = CyclicSettings {
        velocity_scaling_rpm: 24_000.0,
        period: Duration::from_millis(20),
        heartbeat,
        current_scale_a: None,
    };
    Bench {
        access: Sd2CyclicAccess::new(object, settings),
        sent,
        clock,
        sim,
    }
}

impl Bench {
    /// Writes `value` to object `index` (subindex 0) through the cyclic access.
    fn write(&mut self, index: u16, value: i64, data_type: DataType) -> WriteResult {
        self.access
            .write(&Address::indexed(index, 0), &RawValue::Int(value), data_type)
    }

    /// Switch on and enable operation: control words 6, 7 and 15.
    fn enable(&mut self) {
        for command in [6, 7, 15] {
            self.write(WORD, command, DataType::U16).unwrap();
        }
    }
}

fn vector(name: &str) -> String {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/vectors/sd2-dnc.yaml"),
    )
    .or_else(|_| {
        std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/vectors/sd2-dnc.yaml"),
        )
    })
    .unwrap();
    let at = text
        .find(&format!("- name: {name}\n"))
        .unwrap_or_else(|| panic!("no vector {name}"));
    let line = text[at..].lines().nth(1).unwrap();
    line.trim()
        .trim_start_matches("hex: ")
        .trim_matches('"')
        .to_string()
}

fn expected(header: u8, word: u16, speed: i16) -> String {
    use crate::family::sd2::codec::{Body, Telegram, WriteLength};
    let mut c = Cyclic::request(word, speed, false);
    c.header[0] = header;
    let t = Telegram {
        dest: 2,
        source: 1,
        body: Body::CyclicRequest(c),
    };
    crate::hex::to_hex(&t.encode(WriteLength::Captured))
}

const WORD: u16 = CONTROL_WORD;

#[test]
fn start_up_and_stop_are_the_printed_telegrams() {
    // The drive already holds 12 000 rpm (50 % of 24 000): the channel repeats it.
    let mut b = bench(true, &[(SPEED_SETPOINT, 12_000_000, DataType::I32)]);
    b.enable();
    assert_eq!(
        b.sent.take(),
        [
            vector("cyclic telegram, control word 6, speed 0x1fff (50 %)"),
            vector("cyclic telegram, toggle set, control word 7"),
            vector("cyclic telegram, control word 15"),
        ]
    );
    // Change speed to 6000 rpm (25 %: 0x0FFF), disable operation, shutdown; the
    // heartbeat toggle keeps alternating.
    b.write(SPEED_SETPOINT, 6_000_000, DataType::I32).unwrap();
    b.write(WORD, 7, DataType::U16).unwrap();
    b.write(WORD, 6, DataType::U16).unwrap();
    assert_eq!(
        b.sent.take(),
        [
            expected(0x05, 15, 0x0FFF),
            expected(0x01, 7, 0x0FFF),
            expected(0x05, 6, 0x0FFF)
        ]
    );
    assert_eq!(
        b.sim.lock().unwrap().control_words_written(),
        [6, 7, 15, 15, 7, 6]
    );
}

#[test]
fn service_channel_read_and_write_are_the_printed_telegrams() {
    let mut b = bench(
        true,
        &[
            (WORD, 6, DataType::U16),
            (SPEED_SETPOINT, 6_000_000, DataType::I32),
        ],
    );
    let load = b.access.read(&Address::indexed(39, 0), DataType::U16).unwrap();
    b.write(352, 1, DataType::U16).unwrap();
    assert_eq!(
        b.sent.take(),
        [
            vector("cyclic telegram with service channel, read object 39"),
            vector("cyclic telegram with service channel, write object 352 = 1"),
        ]
    );
    // The values are the drive's: the same as the object channel reads.
    let object = &mut b.access.object;
    assert_eq!(
        object.read(&Address::indexed(39, 0), DataType::U16).unwrap(),
        load
    );
    assert_eq!(
        object.read(&Address::indexed(352, 0), DataType::U16).unwrap(),
        RawValue::Int(1)
    );
}

#[test]
fn bus_voltage_comes_through_the_service_channel() {
    let mut b = bench(false, &[]);
    let via_service = b.access.read(&Address::indexed(33, 0), DataType::U16).unwrap();
    let sent = b.sent.take();
    assert_eq!(sent.len(), 1, "{sent:?}");
    assert!(sent[0].starts_with("00 15 02 01 10"), "{}", sent[0]);
    let via_object = b
        .access
        .object
        .read(&Address::indexed(33, 0), DataType::U16)
        .unwrap();
    // The simulated bus voltage ripples by a few tenths of a volt between reads.
    let (a, b) = (via_service.as_int().unwrap(), via_object.as_int().unwrap());
    assert!((a - b).abs() <= 10 && a > 3000, "{a} vs {b}");
}

#[test]
fn a_refused_service_names_the_error() {
    let mut b = bench(false, &[]);
    // Object 398 is the actual speed: read-only.
    let e = b.write(SPEED_ACTUAL + 1000, 1, DataType::U16).unwrap_err();
    assert!(matches!(e, AccessError::Refused { .. }), "{e}");
    assert!(e.to_string().contains("service channel"), "{e}");
}

#[test]
fn a_setpoint_beyond_the_scaling_is_refused_before_sending() {
    let mut b = bench(false, &[]);
    let e = b.write(SPEED_SETPOINT, 24_001_000, DataType::I32).unwrap_err();
    assert!(e.to_string().contains("beyond ±100 %"), "{e}");
    assert!(b.sent.take().is_empty());
    // -100 % exactly is allowed.
    b.write(SPEED_SETPOINT, -24_000_000, DataType::I32).unwrap();
    assert_eq!(b.sent.take(), [expected(0x01, 0, -0x3FFF)]);
}

#[test]
fn the_telegram_goes_out_every_period_with_the_last_output() {
    let mut b = bench(false, &[(WORD, 6, DataType::U16)]);
    let start = b.clock.now();
    let mut next = Duration::ZERO;
    while b.clock.now() < start + Duration::from_secs(1) {
        if b.clock.now() >= next {
            let wait = b.access.keep_alive().unwrap().unwrap();
            next = b.clock.now() + wait;
        }
        b.clock.advance(Duration::from_millis(1));
    }
    let sent = b.sent.take();
    // 1 s at 20 ms: 50 telegrams, each repeating control word 6 and speed 0.
    assert!((50..=51).contains(&sent.len()), "{}", sent.len());
    assert!(sent.iter().all(|t| *t == expected(0x01, 6, 0)), "{sent:?}");
}

#[test]
fn a_refused_rider_fails_alone() {
    let mut b = bench(false, &[]);
    let objects = [
        (Address::indexed(STATUS_WORD, 0), DataType::U16),
        (Address::indexed(SPEED_ACTUAL + 1000, 0), DataType::U16),
    ];
    let mut values = Vec::new();
    b.access.read_many(&objects, &mut values);
    assert!(values[0].is_ok(), "{values:?}");
    assert!(
        matches!(values[1], Err(AccessError::Refused { .. })),
        "{values:?}"
    );
}

#[test]
fn after_a_reopen_the_channel_does_not_resume_the_old_speed() {
    let mut b = bench(false, &[(SPEED_SETPOINT, 6_000_000, DataType::I32)]);
    b.enable();
    b.sent.take();
    b.access.reopen().unwrap();
    b.access
        .read(&Address::indexed(STATUS_WORD, 0), DataType::U16)
        .unwrap();
    // The drive's control word as it holds it, and speed 0.
    assert_eq!(b.sent.take(), [expected(0x01, 15, 0)]);
}

#[test]
fn one_round_trip_answers_the_process_values_and_one_service_read() {
    let mut b = bench(false, &[]);
    let objects = [
        (Address::indexed(STATUS_WORD, 0), DataType::U16),
        (Address::indexed(SPEED_ACTUAL, 0), DataType::I32),
        (Address::indexed(DRIVE_ERROR, 0), DataType::U16),
        (Address::indexed(33, 0), DataType::U16),
    ];
    let mut values = Vec::new();
    b.access.read_many(&objects, &mut values);
    assert_eq!(b.sent.take().len(), 1);
    let status = values[0].as_ref().unwrap().clone();
    assert_eq!(
        status,
        b.access.object.read(&objects[0].0, DataType::U16).unwrap()
    );
    assert!(values.iter().all(Result::is_ok), "{values:?}");
}
