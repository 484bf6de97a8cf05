//! The drive API and the link against the simulated drive, in virtual time: every
//! dictionary object read back, the documented write telegrams, the state walk, refusals
//! that send nothing, and every fault injection producing the right retry or error.

use crate::support::assert_has;
use drivescript::bus::{MemoryTransport, Peer};
use drivescript::clock::{SharedClock, VirtualClock};
use drivescript::dictionary::{Quantity, Unit};
use drivescript::drive::device_control::{DeviceCommand, DeviceState};
use drivescript::drive::AccessError;
use drivescript::drive::{Drive, DriveError};
use drivescript::family::sd2::codec::{Body, WriteLength};
use drivescript::family::sd2::{LinkConfig, Sd2Access, Sd2Link, Sd2Simulator, SimConfig};
use drivescript::hex::to_hex;
use drivescript::sim::SimulatedDrive;
use std::sync::{Arc, Mutex};
use std::time::Duration;

struct Bench {
    drive: Drive,
    sim: Arc<Mutex<Sd2Simulator>>,
    clock: SharedClock,
}

fn bench() -> Bench {
    let clock: SharedClock = Arc::new(VirtualClock::new());
    let sim = Arc::new(Mutex::new(Sd2Simulator::new(SimConfig::default())));
    let peer: Arc<Mutex<dyn Peer>> = sim.clone();
    let link = Sd2Link::new(
        MemoryTransport::shared("simulated drive", peer, clock.clone()),
        clock.clone(),
        LinkConfig::default(),
    );
    let dictionary = Arc::new(
        drivescript::family::Registry::builtin()
            .load_dictionary("sd2")
            .expect("the built-in dictionary is valid"),
    );
    Bench {
        drive: Drive::new(Box::new(Sd2Access::new(link, 2)), dictionary),
        sim,
        clock,
    }
}

fn sent(b: &Bench) -> Vec<String> {
    b.sim
        .lock()
        .unwrap()
        .received()
        .iter()
        .map(|(_, t)| to_hex(&t.encode(WriteLength::Captured)))
        .collect()
}

#[test]
fn every_dictionary_object_reads_back_with_its_type_and_unit() {
    let mut b = bench();
    let dictionary = b.drive.dictionary().clone();
    let mut read = 0;
    for def in dictionary.objects() {
        if !def.readable() {
            continue;
        }
        let value = b
            .drive
            .read(&def.name)
            .unwrap_or_else(|e| panic!("{}: {e}", def.name));
        assert_eq!(value.unit(), def.unit, "{}", def.name);
        if def.data_type.range().is_some() {
            assert!(value.number().is_some(), "{} has no number: {value}", def.name);
        } else {
            assert_eq!(value.text(), Some("Test Motor"), "{}", def.name);
        }
        read += 1;
    }
    assert!(read >= 10, "only {read} objects read");
    let bus = b.drive.read_number("bus_voltage").unwrap();
    assert!((320.0..330.0).contains(&bus), "bus voltage {bus} V");
}

#[test]
fn speed_writes_produce_the_documented_bytes() {
    let mut b = bench();
    for (rpm, data) in [
        (1000.0, "40 42 0f 00"),
        (6000.0, "80 8d 5b 00"),
        (6500.0, "a0 2e 63 00"),
        (18000.0, "80 a8 12 01"),
    ] {
        b.drive
            .write("speed_setpoint", &Quantity::new(rpm, Some(Unit::Rpm)))
            .unwrap();
        let sim = b.sim.lock().unwrap();
        let (_, last) = sim.received().last().unwrap();
        match last.body {
            Body::WriteRequest {
                index,
                subindex,
                data: d,
            } => {
                assert_eq!((index, subindex), (395, 0));
                assert_eq!(to_hex(d.as_slice()), data, "{rpm} rpm");
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(sim.setpoint_rpm(), rpm);
    }
    let all = sent(&b);
    // The two the SD2 sources print, byte for byte.
    assert_eq!(all[0], "00 0b 02 01 0e 8b 01 00 00 00 00 04 40 42 0f 00 c2");
    assert_eq!(all[1], "00 0b 02 01 0e 8b 01 00 00 00 00 04 80 8d 5b 00 eb");
}

#[test]
fn refusals_send_nothing() {
    let mut b = bench();
    let refusals: Vec<DriveError> = vec![
        b.drive
            .write("status_word", &Quantity::new(7.0, None))
            .unwrap_err(),
        b.drive
            .write("speed_setpoint", &Quantity::new(70_000.0, Some(Unit::Rpm)))
            .unwrap_err(),
        b.drive
            .write("speed_setpoint", &Quantity::new(5.0, Some(Unit::Ampere)))
            .unwrap_err(),
        b.drive
            .write("speed_setpont", &Quantity::new(1.0, None))
            .unwrap_err(),
        b.drive.read("store_parameters").unwrap_err(),
        b.drive
            .write("parameter_set", &Quantity::new(65.0, None))
            .unwrap_err(),
    ];
    assert!(sent(&b).is_empty(), "sent: {:?}", sent(&b));
    let texts: Vec<String> = refusals.iter().map(|e| e.to_string()).collect();
    let parts = [
        "status_word is read-only; nothing was sent",
        "above the maximum of speed_setpoint, 60000 rpm",
        "speed_setpoint",
        "did you mean `speed_setpoint`",
        "write-only",
        "64",
    ];
    assert_eq!(texts.len(), parts.len(), "{texts:?}");
    for (text, part) in texts.iter().zip(parts) {
        assert!(text.contains(part), "{texts:?}");
    }
}

#[test]
fn the_state_walk_reaches_operation_enabled_from_every_state_and_back() {
    let never = || false;
    for start in [
        DeviceState::SwitchOnDisabled,
        DeviceState::ReadyToSwitchOn,
        DeviceState::SwitchedOn,
        DeviceState::OperationEnabled,
        DeviceState::QuickStopActive,
    ] {
        let mut b = bench();
        // Bring the drive into the start state.
        if start == DeviceState::QuickStopActive {
            b.drive
                .go_to(DeviceState::OperationEnabled, Duration::from_secs(1), &never)
                .unwrap();
            b.drive
                .write("speed_setpoint", &Quantity::new(3000.0, Some(Unit::Rpm)))
                .unwrap();
            b.clock.sleep(Duration::from_secs(2));
            b.drive.command(DeviceCommand::QuickStop).unwrap();
        } else {
            b.drive.go_to(start, Duration::from_secs(1), &never).unwrap();
        }
        assert_eq!(b.drive.state().unwrap(), start);
        b.drive
            .go_to(DeviceState::OperationEnabled, Duration::from_secs(1), &never)
            .unwrap_or_else(|e| panic!("from {start}: {e}"));
        assert_eq!(
            b.sim.lock().unwrap().state(),
            DeviceState::OperationEnabled,
            "from {start}"
        );
        b.drive
            .go_to(DeviceState::SwitchOnDisabled, Duration::from_secs(1), &never)
            .unwrap();
        assert_eq!(b.sim.lock().unwrap().state(), DeviceState::SwitchOnDisabled);
    }
    // The normal start is shutdown, switch on, enable operation: 6, 7, 15.
    let mut b = bench();
    b.drive
        .go_to(DeviceState::OperationEnabled, Duration::from_secs(1), &never)
        .unwrap();
    assert_eq!(b.sim.lock().unwrap().control_words_written(), vec![6, 7, 15]);
}

#[test]
fn a_faulted_drive_is_reported_and_reset_explicitly() {
    let mut b = bench();
    let never = || false;
    b.sim.lock().unwrap().faults().trip_at(Duration::ZERO, 0x0042);
    let e = b
        .drive
        .go_to(DeviceState::OperationEnabled, Duration::from_secs(1), &never)
        .unwrap_err();
    assert!(e.is_fault(), "{e}");
    assert!(e.to_string().contains("drive error 66, 0x0042"), "{e}");
    b.drive.command(DeviceCommand::FaultReset).unwrap();
    assert_eq!(b.drive.state().unwrap(), DeviceState::SwitchOnDisabled);
    b.drive
        .go_to(DeviceState::OperationEnabled, Duration::from_secs(1), &never)
        .unwrap();
}

#[test]
fn a_blocked_fault_reset_names_the_state_it_is_stuck_in() {
    let mut b = bench();
    b.sim
        .lock()
        .unwrap()
        .faults()
        .trip_at(Duration::ZERO, 9)
        .fault_reset_blocked(true);
    let _ = b.drive.state();
    b.drive.command(DeviceCommand::FaultReset).unwrap();
    assert_eq!(b.drive.state().unwrap(), DeviceState::Fault);
}

#[test]
fn lost_corrupt_late_and_misaddressed_replies_are_retried() {
    type Inject = Box<dyn Fn(&mut Sd2Simulator)>;
    let cases: Vec<(&str, Inject)> = vec![
        (
            "drop",
            Box::new(|s| {
                s.faults().drop_replies(1);
            }),
        ),
        (
            "corrupt",
            Box::new(|s| {
                s.faults().corrupt_checksum(1);
            }),
        ),
        (
            "late",
            Box::new(|s| {
                s.faults().delay_replies(1, Duration::from_millis(1500));
            }),
        ),
        (
            "wrong address",
            Box::new(|s| {
                s.faults().wrong_address(1);
            }),
        ),
    ];
    for (name, inject) in cases {
        let mut b = bench();
        inject(&mut b.sim.lock().unwrap());
        let v = b
            .drive
            .read("status_word")
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(v.raw.as_int(), Some(0x0240), "{name}");
        // The retry went out: two identical requests.
        assert_eq!(sent(&b).len(), 2, "{name}");
    }
}

#[test]
fn a_dead_line_is_a_clear_error_after_the_retries() {
    let mut b = bench();
    b.sim.lock().unwrap().faults().drop_replies(10);
    let e = b.drive.read("status_word").unwrap_err();
    assert!(e.is_communication(), "{e}");
    assert!(
        matches!(e, DriveError::Access(AccessError::NoReply { attempts: 3, .. })),
        "{e}"
    );
    assert_eq!(sent(&b).len(), 3);
    // 3 timeouts of 1 s and 2 settle periods, in virtual time.
    assert_eq!(b.clock.now(), Duration::from_millis(3040));
}

#[test]
fn a_drive_refusal_names_the_object_and_the_code() {
    let mut b = bench();
    let never = || false;
    b.drive
        .go_to(DeviceState::OperationEnabled, Duration::from_secs(1), &never)
        .unwrap();
    // The simulator refuses a parameter-set change while operation is enabled (0x9B).
    let e = b
        .drive
        .write("parameter_set", &Quantity::new(2.0, None))
        .unwrap_err();
    let text = e.to_string();
    assert_has(&text, &["refused to write parameter_set", "0x9B"]);
}

/// Two simulated drives on one line, as on an RS485 bus: every request reaches both, only
/// the addressed one answers.
struct Line(Vec<Arc<Mutex<Sd2Simulator>>>);

impl Peer for Line {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<drivescript::bus::PeerReply> {
        self.0
            .iter()
            .flat_map(|d| d.lock().unwrap().receive(bytes, now))
            .collect()
    }
}

#[test]
fn two_drives_share_one_line_and_their_exchanges_never_interleave() {
    let clock: SharedClock = drivescript::clock::RealClock::shared();
    let sims: Vec<Arc<Mutex<Sd2Simulator>>> = [2u8, 3]
        .iter()
        .map(|&address| {
            Arc::new(Mutex::new(Sd2Simulator::new(SimConfig {
                address,
                ..SimConfig::default()
            })))
        })
        .collect();
    let peer: Arc<Mutex<dyn Peer>> = Arc::new(Mutex::new(Line(sims.clone())));
    let line = MemoryTransport::shared("rs485 line", peer, clock.clone());
    let dictionary = Arc::new(
        drivescript::family::Registry::builtin()
            .load_dictionary("sd2")
            .expect("the built-in dictionary is valid"),
    );
    let workers: Vec<_> = [(2u8, 1000.0), (3u8, 2000.0)]
        .into_iter()
        .map(|(dest, rpm)| {
            // No retries: an exchange that another drive's broke would fail the test.
            let config = LinkConfig {
                retries: 0,
                ..LinkConfig::default()
            };
            let link = Sd2Link::new(line.clone(), clock.clone(), config);
            let mut drive = Drive::new(Box::new(Sd2Access::new(link, dest)), dictionary.clone());
            std::thread::spawn(move || {
                drive
                    .write("speed_setpoint", &Quantity::new(rpm, Some(Unit::Rpm)))
                    .expect("write");
                for _ in 0..300 {
                    let v = drive.read_number("speed_setpoint").expect("read");
                    assert_eq!(v, rpm, "drive {dest} read another drive's value");
                }
            })
        })
        .collect();
    for w in workers {
        w.join().expect("a drive's exchanges failed");
    }
    assert_eq!(line.users(), 1, "both links are done with the line");
    for (sim, rpm) in sims.iter().zip([1000.0, 2000.0]) {
        assert_eq!(sim.lock().unwrap().setpoint_rpm(), rpm);
    }
}
