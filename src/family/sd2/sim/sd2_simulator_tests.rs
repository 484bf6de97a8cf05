//! Byte-level tests of the simulated SD2 drive: requests are built with the codec, fed
//! through `Peer::receive`, and the reply bytes decoded again.

use super::*;
use crate::drive::DeviceState;
use crate::family::sd2::codec::{checksum, Data, DecodeError, ServiceFunction};
use crate::hex::parse_hex;
use crate::sim::{SimulatedDrive, LOG_KEEPS};

const SD: DeviceState = DeviceState::SwitchOnDisabled;

fn sim() -> Sd2Simulator {
    Sd2Simulator::new(SimConfig::default())
}

fn secs(s: f64) -> Duration {
    Duration::from_secs_f64(s)
}

fn latency() -> Duration {
    SimConfig::default().response_latency
}

/// Sends `t` at `now` and returns the single reply, decoded.
fn ask(sim: &mut Sd2Simulator, t: Telegram, now: Duration) -> Telegram {
    let replies = sim.receive(&t.encode(WriteLength::Captured), now);
    assert_eq!(replies.len(), 1, "one reply to {t:?}");
    assert_eq!(replies[0].at, now + latency());
    Telegram::decode(&replies[0].bytes).expect("the reply decodes")
}

fn read(sim: &mut Sd2Simulator, index: u16, subindex: u32, now: Duration) -> Result<Data, ErrorCode> {
    let reply = ask(sim, Telegram::read_request(2, 1, index, subindex), now);
    assert_eq!((reply.dest, reply.source), (1, 2));
    match reply.body {
        Body::ReadReply { error, data } if error.is_ok() => Ok(data),
        Body::ReadReply { error, data } => {
            assert!(data.is_empty(), "an error reply carries count 0");
            Err(error)
        }
        other => panic!("not a read reply: {other:?}"),
    }
}

fn read_u16(sim: &mut Sd2Simulator, index: u16, now: Duration) -> u16 {
    let d = read(sim, index, 0, now).expect("readable");
    assert_eq!(d.len(), 2, "object {index} is a u16");
    u16::from_le_bytes([d.as_slice()[0], d.as_slice()[1]])
}

fn read_i32(sim: &mut Sd2Simulator, index: u16, now: Duration) -> i32 {
    let d = read(sim, index, 0, now).expect("readable");
    assert_eq!(d.len(), 4, "object {index} is an i32");
    let s = d.as_slice();
    i32::from_le_bytes([s[0], s[1], s[2], s[3]])
}

fn write_sub(sim: &mut Sd2Simulator, index: u16, subindex: u32, data: &[u8], now: Duration) -> ErrorCode {
    let t = Telegram::write_request(2, 1, index, subindex, data).expect("1..=48 bytes");
    match ask(sim, t, now).body {
        Body::WriteReply { error } => error,
        other => panic!("not a write reply: {other:?}"),
    }
}

fn write(sim: &mut Sd2Simulator, index: u16, data: &[u8], now: Duration) -> ErrorCode {
    write_sub(sim, index, 0, data, now)
}

fn control(sim: &mut Sd2Simulator, control_word: u16, now: Duration) {
    assert_eq!(write(sim, 68, &control_word.to_le_bytes(), now), ErrorCode::OK);
}

fn set_speed(sim: &mut Sd2Simulator, rpm: i32, now: Duration) {
    assert_eq!(write(sim, 395, &(rpm * 1000).to_le_bytes(), now), ErrorCode::OK);
}

/// Shutdown, switch on, enable operation at `now`.
fn enable(sim: &mut Sd2Simulator, now: Duration) {
    for cw in [6, 7, 15] {
        control(sim, cw, now);
    }
    assert_eq!(sim.state(), DeviceState::OperationEnabled);
}

fn cyclic(
    sim: &mut Sd2Simulator,
    control_word: u16,
    speed: i16,
    service: Option<ServiceChannel>,
    now: Duration,
) -> Cyclic {
    let mut c = Cyclic::request(control_word, speed, false);
    c.service = service;
    let t = Telegram {
        dest: 2,
        source: 1,
        body: Body::CyclicRequest(c),
    };
    match ask(sim, t, now).body {
        Body::CyclicReply(r) => r,
        other => panic!("not a cyclic reply: {other:?}"),
    }
}

fn hex(s: &str) -> Vec<u8> {
    parse_hex(s).expect("valid hex")
}

/// The bytes of the one reply to the telegram `request` (hex), sent at time zero.
#[track_caller]
fn reply_to(sim: &mut Sd2Simulator, request: &str) -> Vec<u8> {
    let replies = sim.receive(&hex(request), Duration::ZERO);
    assert_eq!(replies.len(), 1, "one reply to {request}");
    replies[0].bytes.clone()
}

/// The telegram `s` with its check byte appended.
fn with_checksum(s: &str) -> Vec<u8> {
    let mut bytes = hex(s);
    bytes.push(checksum(&bytes[1..]));
    bytes
}

#[test]
fn boots_into_switch_on_disabled() {
    let mut s = sim();
    assert_eq!(s.state(), SD);
    assert_eq!(read_u16(&mut s, 67, Duration::ZERO), 0x0240);
    assert_eq!(s.describe(), "simulated SD2 at DNC address 2 (ramp 2000 rpm/s)");
}

#[test]
fn golden_write_telegrams_are_accepted_with_the_golden_reply() {
    let mut s = sim();
    let ok = hex("00 04 01 02 8e 00 6a");
    let steps = [
        (
            "00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 97",
            DeviceState::ReadyToSwitchOn,
        ),
        (
            "00 0b 02 01 0e 8b 01 00 00 00 00 04 40 42 0f 00 c2",
            DeviceState::ReadyToSwitchOn,
        ),
        (
            "00 0b 02 01 0e 8b 01 00 00 00 00 04 80 8d 5b 00 eb",
            DeviceState::ReadyToSwitchOn,
        ),
        (
            "00 0b 02 01 0e 44 00 00 00 00 00 02 07 00 96",
            DeviceState::SwitchedOn,
        ),
        (
            "00 0b 02 01 0e 44 00 00 00 00 00 02 0f 00 8e",
            DeviceState::OperationEnabled,
        ),
    ];
    for (i, (request, state)) in steps.into_iter().enumerate() {
        let now = Duration::from_millis(i as u64);
        let replies = s.receive(&hex(request), now);
        assert_eq!(
            replies,
            vec![PeerReply {
                at: now + latency(),
                bytes: ok.clone()
            }],
            "{request}"
        );
        assert_eq!(s.state(), state, "{request}");
    }
    assert_eq!(s.setpoint_rpm(), 6000.0);
    assert_eq!(s.control_words_written(), vec![6, 7, 15]);
    assert_eq!(s.corrupt_blocks(), 0);
}

#[test]
fn golden_read_requests_get_values_of_the_right_size() {
    let mut s = sim();
    let now = Duration::ZERO;
    let reply = |s: &mut Sd2Simulator, h: &str| {
        let r = s.receive(&hex(h), now);
        assert_eq!(r.len(), 1);
        r[0].bytes.clone()
    };
    // Actual speed at rest, power off: exactly 0.
    assert_eq!(reply(&mut s, "00 09 02 01 0d 8e 01 00 00 00 00 57"), {
        let mut b = hex("00 09 01 02 8d 04 00 00 00 00 00");
        b.push(checksum(&b[1..]));
        b
    });
    // Status word: switch on disabled.
    let status = reply(&mut s, "00 09 02 01 0d 43 00 00 00 00 00 a3");
    assert_eq!(status[..9], hex("00 07 01 02 8d 02 00 40 02")[..]);
    // Ident: max length 32, "Test Motor", NUL: 12 bytes.
    let ident = reply(&mut s, "00 09 02 01 0d 16 00 00 00 00 00 d0");
    let mut expected = vec![0x00, 5 + 12, 0x01, 0x02, 0x8d, 12, 0x00, 0x20];
    expected.extend_from_slice(b"Test Motor\0");
    expected.push(checksum(&expected[1..]));
    assert_eq!(ident, expected);
}

#[test]
fn every_object_reads_with_its_size() {
    let mut s = sim();
    let now = Duration::ZERO;
    for (index, size) in [
        (33, 2),
        (39, 2),
        (67, 2),
        (68, 2),
        (168, 4),
        (352, 2),
        (395, 4),
        (398, 4),
        (400, 4),
        (401, 2),
    ] {
        assert_eq!(
            read(&mut s, index, 0, now).map(|d| d.len()),
            Ok(size),
            "object {index}"
        );
    }
    assert_eq!(read(&mut s, 22, 0, now).map(|d| d.len()), Ok(12));
    // The string accepts subindices up to its length and returns the whole string.
    assert_eq!(read(&mut s, 22, 32, now).map(|d| d.len()), Ok(12));
    set_speed(&mut s, -1234, now);
    assert_eq!(read_i32(&mut s, 395, now), -1_234_000);
    control(&mut s, 6, now);
    assert_eq!(read_u16(&mut s, 68, now), 6);
    assert_eq!(read_u16(&mut s, 401, now), 0);
}

#[test]
fn long_ident_is_cut_at_32_without_nul() {
    let mut s = Sd2Simulator::new(SimConfig {
        ident: "x".repeat(40),
        ..SimConfig::default()
    });
    let d = read(&mut s, 22, 0, Duration::ZERO).unwrap();
    assert_eq!(d.len(), 33);
    assert_eq!(d.as_slice()[0], 32);
    assert!(d.as_slice()[1..].iter().all(|&b| b == b'x'));
}

#[test]
fn every_error_code_path() {
    let mut s = sim();
    let t = Duration::ZERO;
    // Unknown index.
    assert_eq!(read(&mut s, 999, 0, t), Err(ErrorCode(0x8B)));
    assert_eq!(write(&mut s, 999, &[0, 0], t), ErrorCode(0x8B));
    // Read-only objects refuse writes, whatever the length.
    for index in [22, 33, 39, 67, 168, 398, 400, 401] {
        assert_eq!(
            write(&mut s, index, &[0, 0], t),
            ErrorCode(0x8A),
            "object {index}"
        );
    }
    // Write-only: store parameters.
    assert_eq!(read(&mut s, 402, 0, t), Err(ErrorCode(0x89)));
    assert_eq!(write(&mut s, 402, &1u16.to_le_bytes(), t), ErrorCode::OK);
    assert_eq!(write(&mut s, 402, &0u16.to_le_bytes(), t), ErrorCode(0x95));
    // Length: too long, too short.
    assert_eq!(write(&mut s, 68, &[6, 0, 0, 0], t), ErrorCode(0x92));
    assert_eq!(write(&mut s, 68, &[6], t), ErrorCode(0x93));
    assert_eq!(write(&mut s, 395, &[0, 0], t), ErrorCode(0x93));
    assert_eq!(write(&mut s, 395, &[0; 5], t), ErrorCode(0x92));
    // Subindex.
    assert_eq!(read(&mut s, 67, 1, t), Err(ErrorCode(0x94)));
    assert_eq!(read(&mut s, 22, 33, t), Err(ErrorCode(0x94)));
    assert_eq!(write_sub(&mut s, 68, 1, &[6, 0], t), ErrorCode(0x94));
    // Ranges.
    assert_eq!(write(&mut s, 352, &65u16.to_le_bytes(), t), ErrorCode(0x95));
    assert_eq!(
        write(&mut s, 395, &60_000_001i32.to_le_bytes(), t),
        ErrorCode(0x96)
    );
    assert_eq!(
        write(&mut s, 395, &(-60_000_001i32).to_le_bytes(), t),
        ErrorCode(0x97)
    );
    assert_eq!(write(&mut s, 395, &60_000_000i32.to_le_bytes(), t), ErrorCode::OK);
    assert_eq!(
        write(&mut s, 395, &(-60_000_000i32).to_le_bytes(), t),
        ErrorCode::OK
    );
    // State of the control.
    assert_eq!(write(&mut s, 352, &3u16.to_le_bytes(), t), ErrorCode::OK);
    set_speed(&mut s, 0, t);
    enable(&mut s, t);
    assert_eq!(write(&mut s, 352, &4u16.to_le_bytes(), t), ErrorCode(0x9B));
    assert_eq!(read_u16(&mut s, 352, t), 3);
    // None of the refused control-word writes counted, nor changed anything.
    assert_eq!(s.control_words_written(), vec![6, 7, 15]);
    // An error read reply is 7 bytes: count 0.
    let r = s.receive(
        &Telegram::read_request(2, 1, 999, 0).encode(WriteLength::Captured),
        t,
    );
    assert_eq!(r[0].bytes, {
        let mut b = vec![0x00, 0x05, 0x01, 0x02, 0x8d, 0x00, 0x8b];
        b.push(checksum(&b[1..]));
        b
    });
}

#[test]
fn unlisted_commands_are_acknowledged_and_change_nothing() {
    let mut s = sim();
    let t = Duration::ZERO;
    control(&mut s, 15, t);
    assert_eq!(s.state(), SD);
    control(&mut s, 7, t);
    assert_eq!(s.state(), SD);
    control(&mut s, 6, t);
    control(&mut s, 15, t);
    assert_eq!(s.state(), DeviceState::ReadyToSwitchOn);
    assert_eq!(read_u16(&mut s, 67, t), 0x0231);
    control(&mut s, 7, t);
    assert_eq!(read_u16(&mut s, 67, t), 0x0233);
}

#[test]
fn the_formula_length_form_is_accepted_too() {
    let mut s = sim();
    let t = Telegram::write_request(2, 1, 68, 0, &[6, 0]).unwrap();
    let r = s.receive(&t.encode(WriteLength::Formula), Duration::ZERO);
    assert_eq!(r[0].bytes, hex("00 04 01 02 8e 00 6a"));
    assert_eq!(s.state(), DeviceState::ReadyToSwitchOn);
}

#[test]
fn bytes_split_across_calls() {
    let mut s = sim();
    let mut bytes = hex("00 0b 02 01 0e 8b 01 00 00 00 00 04 80 8d 5b 00 eb");
    bytes.extend(hex("00 09 02 01 0d 43 00 00 00 00 00 a3"));
    let mut replies = Vec::new();
    for (i, b) in bytes.iter().enumerate() {
        let now = Duration::from_micros(200 * i as u64);
        let got = s.receive(&[*b], now);
        if i == 16 || i == bytes.len() - 1 {
            assert_eq!(got.len(), 1, "a reply after byte {i}");
            assert_eq!(got[0].at, now + latency());
        } else {
            assert!(got.is_empty(), "no reply after byte {i}");
        }
        replies.extend(got);
    }
    assert_eq!(replies[0].bytes, hex("00 04 01 02 8e 00 6a"));
    assert_eq!(s.setpoint_rpm(), 6000.0);
    assert_eq!(s.received().len(), 2);
    // Two requests in one piece: two replies, in order.
    let mut both = Telegram::read_request(2, 1, 67, 0).encode(WriteLength::Captured);
    both.extend(Telegram::read_request(2, 1, 68, 0).encode(WriteLength::Captured));
    let r = s.receive(&both, secs(1.0));
    assert_eq!(r.len(), 2);
    assert_eq!(Telegram::decode(&r[1].bytes).unwrap().source, 2);
}

#[test]
fn other_addresses_replies_and_corrupt_blocks_get_no_answer() {
    let mut s = sim();
    let t = Duration::ZERO;
    let for_drive_3 = Telegram::write_request(3, 1, 68, 0, &[6, 0]).unwrap();
    assert!(s
        .receive(&for_drive_3.encode(WriteLength::Captured), t)
        .is_empty());
    assert_eq!(s.state(), SD);
    let some_reply = Telegram {
        dest: 2,
        source: 3,
        body: Body::WriteReply { error: ErrorCode::OK },
    };
    assert!(s.receive(&some_reply.encode(WriteLength::Captured), t).is_empty());
    assert!(s.received().is_empty());
    let mut bad = hex("00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 97");
    bad[14] ^= 0x01;
    assert!(s.receive(&bad, t).is_empty());
    assert!(s.corrupt_blocks() >= 1);
    assert_eq!(s.state(), SD, "a corrupt block is not executed");
    // The next good block is answered.
    assert_eq!(read_u16(&mut s, 67, t), 0x0240);
}

#[test]
fn ramp_reaches_the_setpoint_after_three_seconds_not_before() {
    let mut s = sim();
    set_speed(&mut s, 6000, Duration::ZERO);
    enable(&mut s, secs(1.0));
    assert_eq!(s.speed_rpm(secs(2.5)), 3000.0);
    assert!(s.speed_rpm(secs(3.999)) < 6000.0);
    assert_eq!(s.speed_rpm(secs(4.0)), 6000.0);
    assert_eq!(
        read_u16(&mut s, 67, secs(2.5)),
        0x0237,
        "ramping: target not reached"
    );
    let current = read_i32(&mut s, 400, secs(2.5));
    // 3000 rpm: 0.24 A load + 2000 rpm/s × 0.0005 A = 1.24 A.
    assert!((current - 1240).abs() <= 5, "{current}");
    assert!(s.speed_rpm(secs(3.999)) < 6000.0);
    assert_eq!(read_u16(&mut s, 67, secs(4.0)), 0x0637);
    let speed = read_i32(&mut s, 398, secs(4.0));
    assert!((speed - 6_000_000).abs() <= 500, "{speed}");
    let second = read_i32(&mut s, 168, secs(4.0));
    assert!((second - 6_000_000).abs() <= 500, "{second}");
    // A new setpoint while running ramps from where the motor is.
    set_speed(&mut s, 2000, secs(5.0));
    assert_eq!(s.speed_rpm(secs(6.0)), 4000.0);
    assert_eq!(s.speed_rpm(secs(7.0)), 2000.0);
}

#[test]
fn disabled_motor_coasts_without_current() {
    let mut s = sim();
    set_speed(&mut s, 6000, Duration::ZERO);
    enable(&mut s, Duration::ZERO);
    control(&mut s, 7, secs(10.0)); // disable operation
    assert_eq!(s.state(), DeviceState::SwitchedOn);
    assert_eq!(read_i32(&mut s, 400, secs(10.0)), 0);
    assert_eq!(s.speed_rpm(secs(20.0)), 3000.0);
    assert_eq!(s.speed_rpm(secs(30.0)), 0.0);
    assert_eq!(
        read_i32(&mut s, 398, secs(30.0)),
        0,
        "no noise at rest with the power stage off"
    );
    assert_eq!(read_u16(&mut s, 67, secs(30.0)), 0x0233);
}

#[test]
fn quick_stop_brakes_then_switches_on_disabled() {
    let mut s = sim();
    set_speed(&mut s, 6000, Duration::ZERO);
    enable(&mut s, Duration::ZERO);
    control(&mut s, 2, secs(10.0));
    assert_eq!(s.state(), DeviceState::QuickStopActive);
    assert_eq!(read_u16(&mut s, 67, secs(10.3)), 0x0217);
    assert_eq!(s.speed_rpm(secs(10.3)), 3000.0);
    // Enable operation out of quick stop active resumes the ramp.
    control(&mut s, 15, secs(10.3));
    assert_eq!(s.state(), DeviceState::OperationEnabled);
    assert_eq!(s.speed_rpm(secs(11.3)), 5000.0);
    control(&mut s, 2, secs(12.0));
    assert_eq!(read_u16(&mut s, 67, secs(12.6)), 0x0240);
    assert_eq!(s.state(), SD);
    // Quick stop active –disable voltage→ switch on disabled, the motor coasts.
    enable(&mut s, secs(13.0));
    control(&mut s, 2, secs(16.0));
    control(&mut s, 0, secs(16.1));
    assert_eq!(s.state(), SD);
    assert_eq!(s.speed_rpm(secs(17.1)), 5000.0 - 300.0);
}

#[test]
fn dropped_replies_are_executed_but_not_answered() {
    let mut s = sim();
    s.faults().drop_replies(2);
    let shutdown = hex("00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 97");
    assert!(s.receive(&shutdown, Duration::ZERO).is_empty());
    assert_eq!(s.state(), DeviceState::ReadyToSwitchOn);
    assert!(s.receive(&shutdown, Duration::ZERO).is_empty());
    assert_eq!(s.receive(&shutdown, Duration::ZERO).len(), 1);
    assert_eq!(s.received().len(), 3);
    assert!(s.faults().is_idle());
}

#[test]
fn corrupt_checksum_inverts_the_check_byte() {
    let mut s = sim();
    s.faults().corrupt_checksum(1);
    let shutdown = hex("00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 97");
    let r = s.receive(&shutdown, Duration::ZERO);
    assert_eq!(r[0].bytes, hex("00 04 01 02 8e 00 95"));
    assert!(matches!(
        Telegram::decode(&r[0].bytes),
        Err(DecodeError::BadChecksum {
            expected: 0x6a,
            actual: 0x95,
            ..
        })
    ));
    assert_eq!(
        s.receive(&shutdown, Duration::ZERO)[0].bytes,
        hex("00 04 01 02 8e 00 6a")
    );
}

#[test]
fn delayed_and_misaddressed_replies() {
    let mut s = sim();
    let late = Duration::from_millis(1500);
    s.faults().delay_replies(1, late).wrong_address(1);
    let t = secs(2.0);
    let r = s.receive(
        &Telegram::read_request(2, 1, 67, 0).encode(WriteLength::Captured),
        t,
    );
    assert_eq!(r[0].at, t + latency() + late);
    let reply = Telegram::decode(&r[0].bytes).expect("a valid block from the wrong drive");
    assert_eq!(reply.source, 3);
    let r = s.receive(
        &Telegram::read_request(2, 1, 67, 0).encode(WriteLength::Captured),
        t,
    );
    assert_eq!(r[0].at, t + latency());
    assert_eq!(Telegram::decode(&r[0].bytes).unwrap().source, 2);
}

#[test]
fn trip_splits_the_advance_and_fault_reset_clears_it() {
    let mut s = sim();
    set_speed(&mut s, 6000, Duration::ZERO);
    enable(&mut s, Duration::ZERO);
    s.faults().trip_at(secs(5.0), 0x1234);
    // No block between: the model still brakes from 5.0 s, not from the next block.
    assert_eq!(s.speed_rpm(secs(5.3)), 3000.0);
    assert_eq!(read_u16(&mut s, 67, secs(5.3)), 0x020F);
    assert_eq!(s.state(), DeviceState::FaultReactionActive);
    assert_eq!(read_u16(&mut s, 401, secs(5.3)), 0x1234);
    assert_eq!(read_u16(&mut s, 67, secs(6.0)), 0x0208);
    assert_eq!(s.state(), DeviceState::Fault);
    // Commands other than a fault reset do nothing.
    control(&mut s, 6, secs(6.0));
    control(&mut s, 15, secs(6.0));
    assert_eq!(s.state(), DeviceState::Fault);
    // Blocked: the cause persists.
    s.faults().fault_reset_blocked(true);
    control(&mut s, 0x80, secs(7.0));
    assert_eq!(
        (s.state(), read_u16(&mut s, 401, secs(7.0))),
        (DeviceState::Fault, 0x1234)
    );
    s.faults().fault_reset_blocked(false);
    // Bit 7 is still high from the last write: no edge, no reset.
    control(&mut s, 0x80, secs(8.0));
    assert_eq!(s.state(), DeviceState::Fault);
    control(&mut s, 0x00, secs(8.0));
    control(&mut s, 0x80, secs(8.0));
    assert_eq!(s.state(), SD);
    assert_eq!(read_u16(&mut s, 401, secs(8.0)), 0);
    // A trip at rest goes straight through to fault.
    s.faults().trip_at(secs(9.0), 7);
    assert_eq!(read_u16(&mut s, 67, secs(9.0)), 0x0208);
}

#[test]
fn cyclic_telegram_golden_bytes() {
    let mut s = sim();
    assert_eq!(
        reply_to(&mut s, "00 0d 02 01 10 01 00 06 00 ff 1f 00 00 00 00 ba"),
        with_checksum("00 0d 01 02 90 01 00 31 02 00 00 00 00 00 00")
    );
    assert!((s.setpoint_rpm() - 8191.0 / 16383.0 * 24000.0).abs() < 1e-9);
    // Header echoed, toggle and all.
    let r = reply_to(&mut s, "00 0d 02 01 10 05 00 07 00 ff 1f 00 00 00 00 b5");
    assert_eq!(r[5..9], hex("05 00 33 02")[..]);
    assert_eq!(s.state(), DeviceState::SwitchedOn);
    let r = reply_to(&mut s, "00 0d 02 01 10 01 00 0f 00 ff 1f 00 00 00 00 b1");
    assert_eq!(r[7..9], hex("37 02")[..]);
    assert_eq!(s.control_words_written(), vec![6, 7, 15]);
}

#[test]
fn cyclic_process_data_at_speed() {
    let mut s = sim();
    for cw in [6, 7, 15] {
        cyclic(&mut s, cw, 0x3FFF, None, Duration::ZERO);
    }
    assert_eq!(s.setpoint_rpm(), 24_000.0);
    let r = cyclic(&mut s, 15, 0x3FFF, None, secs(12.0));
    assert_eq!(r.word(), 0x0637);
    assert!((i32::from(r.speed()) - 0x3FFF).abs() <= 1, "{}", r.speed());
    assert_eq!(r.drive_error(), 0);
    // 24000 rpm: 1.92 A in 0.01 A.
    assert!((i32::from(r.current()) - 192).abs() <= 1, "{}", r.current());
    assert!(r.service.is_none());
    // -0x4000 is a little beyond -100 %: ramps through zero in just over 24 s.
    cyclic(&mut s, 15, -0x4000, None, secs(12.0));
    assert_eq!(s.speed_rpm(secs(36.0)), -24_000.0);
    assert_eq!(s.speed_rpm(secs(37.0)), -24_000.0 * 16384.0 / 16383.0);
    let r = cyclic(&mut s, 15, -0x4000, None, secs(37.0));
    assert!(r.speed() < -16_380, "{}", r.speed());
    assert!(r.current() < 0);
}

#[test]
fn service_channel_golden_requests() {
    let mut s = sim();
    let r = reply_to(
        &mut s,
        "00 15 02 01 10 01 00 06 00 ff 0f 00 00 00 00 00 08 27 00 00 00 00 00 93",
    );
    let reply = Telegram::decode(&r).unwrap();
    let Body::CyclicReply(c) = reply.body else {
        panic!("{reply:?}")
    };
    let sc = c.service.expect("the service channel is answered");
    assert_eq!(
        (sc.reserved, sc.ctrl, sc.index, sc.data),
        (0, 0x08, 39, [0, 0, 0, 0])
    );
    assert_eq!(
        reply_to(
            &mut s,
            "00 15 02 01 10 05 00 06 00 ff 0f 00 00 00 00 00 0d 60 01 01 00 00 00 4f"
        ),
        with_checksum("00 15 01 02 90 05 00 31 02 00 00 00 00 00 00 00 0d 60 01 01 00 00 00")
    );
    assert_eq!(read_u16(&mut s, 352, Duration::ZERO), 1);
}

#[test]
fn service_channel_toggle_semantics_and_failures() {
    let mut s = sim();
    let t = Duration::ZERO;
    let svc = |toggle, f, valid, index, value: u32| {
        ServiceChannel::request(toggle, f, valid, index, value.to_le_bytes())
    };
    let w5 = svc(true, ServiceFunction::Write, 2, 352, 5);
    let first = cyclic(&mut s, 6, 0, Some(w5), t).service.unwrap();
    assert_eq!(first.data, [5, 0, 0, 0]);
    // Same toggle, new value: not executed, the previous reply again.
    let w6 = svc(true, ServiceFunction::Write, 2, 352, 6);
    assert_eq!(cyclic(&mut s, 6, 0, Some(w6), t).service, Some(first));
    assert_eq!(read_u16(&mut s, 352, t), 5);
    // New toggle: a read.
    let r = cyclic(
        &mut s,
        6,
        0,
        Some(svc(false, ServiceFunction::Read, 2, 352, 0)),
        t,
    )
    .service
    .unwrap();
    assert_eq!((r.ctrl, r.data), (0x08, [5, 0, 0, 0]));
    // A write with too few valid bytes for an i32.
    let short = svc(true, ServiceFunction::Write, 2, 395, 1000);
    let r = cyclic(&mut s, 6, 0, Some(short), t).service.unwrap();
    assert_eq!((r.ctrl, r.data), (short.ctrl | 0x80, [0x93, 0, 0, 0]));
    // A full i32 write; the PDO's speed reference was applied first, so this one stays.
    let full = svc(false, ServiceFunction::Write, 4, 395, 1_500_000);
    assert_eq!(
        cyclic(&mut s, 6, 0, Some(full), t).service.unwrap().ctrl,
        full.ctrl
    );
    assert_eq!(s.setpoint_rpm(), 1500.0);
    // The string does not fit: unsupported access.
    let r = cyclic(&mut s, 6, 0, Some(svc(true, ServiceFunction::Read, 4, 22, 0)), t)
        .service
        .unwrap();
    assert_eq!(r.data[0], 0x88);
    assert!(r.ctrl & 0x80 != 0);
    // A control word written through the service channel counts as one.
    let cw = svc(false, ServiceFunction::Write, 2, 68, 7);
    cyclic(&mut s, 6, 0, Some(cw), t);
    assert_eq!(s.state(), DeviceState::SwitchedOn);
    assert_eq!(s.control_words_written().last(), Some(&7));
    // Function 3: fault, drive error 3.
    let bad = svc(true, ServiceFunction::Invalid, 1, 0, 0);
    let r = cyclic(&mut s, 7, 0, Some(bad), t);
    assert_eq!(r.service.unwrap().ctrl & 0x80, 0x80);
    assert_eq!((r.word(), r.drive_error()), (0x0208, 3));
    assert_eq!(s.state(), DeviceState::Fault);
}

#[test]
fn service_array_index_selects_the_subindex() {
    let mut s = sim();
    let t = Duration::ZERO;
    let set = ServiceChannel::request(true, ServiceFunction::SetArrayIndex, 1, 67, [1, 0, 0, 0]);
    assert_eq!(cyclic(&mut s, 0, 0, Some(set), t).service.unwrap().ctrl, set.ctrl);
    let r = ServiceChannel::request(false, ServiceFunction::Read, 2, 67, [0; 4]);
    assert_eq!(cyclic(&mut s, 0, 0, Some(r), t).service.unwrap().data[0], 0x94);
}

#[test]
fn logs_and_clear() {
    let mut s = sim();
    control(&mut s, 6, secs(1.0));
    read(&mut s, 67, 0, secs(2.0)).unwrap();
    let log: Vec<Duration> = s.received().iter().map(|(t, _)| *t).collect();
    assert_eq!(log, vec![secs(1.0), secs(2.0)]);
    assert_eq!(s.received()[1].1, Telegram::read_request(2, 1, 67, 0));
    s.clear_log();
    assert!(s.received().is_empty());
    assert!(s.control_words_written().is_empty());
    s.set_logging(false);
    control(&mut s, 7, secs(3.0));
    assert!(s.received().is_empty() && s.control_words_written().is_empty());
    assert_eq!(s.state(), DeviceState::SwitchedOn);
}

/// A scripted session: writes, ramps, polls with noise, a cyclic exchange, a trip.
fn session(seed: u64) -> Vec<PeerReply> {
    let mut s = Sd2Simulator::new(SimConfig {
        seed,
        ..SimConfig::default()
    });
    s.faults().trip_at(secs(20.0), 9);
    let mut out = Vec::new();
    let mut send = |s: &mut Sd2Simulator, t: Telegram, now: Duration| {
        out.extend(s.receive(&t.encode(WriteLength::Captured), now));
    };
    send(
        &mut s,
        Telegram::write_request(2, 1, 395, 0, &6_000_000i32.to_le_bytes()).unwrap(),
        secs(0.0),
    );
    for (i, cw) in [6u16, 7, 15].into_iter().enumerate() {
        send(
            &mut s,
            Telegram::write_request(2, 1, 68, 0, &cw.to_le_bytes()).unwrap(),
            secs(0.1 * i as f64),
        );
    }
    for i in 0..200 {
        let now = secs(0.5 + 0.1 * f64::from(i));
        for index in [33, 39, 67, 398, 400] {
            send(&mut s, Telegram::read_request(2, 1, index, 0), now);
        }
    }
    send(
        &mut s,
        Telegram {
            dest: 2,
            source: 1,
            body: Body::CyclicRequest(Cyclic::request(15, 0x1FFF, false)),
        },
        secs(30.0),
    );
    out
}

#[test]
fn deterministic_for_the_same_seed_bytes_and_times() {
    let a = session(42);
    assert_eq!(a, session(42));
    assert_ne!(a, session(43), "the seed changes the noise");
}

#[test]
fn a_two_hour_run_in_polled_a_hundred_thousand_times_stays_exact() {
    let mut s = sim();
    set_speed(&mut s, 12_000, Duration::ZERO);
    enable(&mut s, Duration::ZERO);
    s.set_logging(false);
    let request = Telegram::read_request(2, 1, 398, 0).encode(WriteLength::Captured);
    let step = Duration::from_millis(72); // 100 000 polls in 2 h
    let mut now = Duration::ZERO;
    for _ in 0..100_000 {
        now += step;
        assert_eq!(s.receive(&request, now).len(), 1);
    }
    assert_eq!(now, Duration::from_secs(7200));
    assert_eq!(s.speed_rpm(now), 12_000.0);
    assert_eq!(s.state(), DeviceState::OperationEnabled);
}

#[test]
fn the_request_log_stays_bounded_on_a_long_run() {
    let mut sim = Sd2Simulator::new(SimConfig::default());
    let read = Telegram::read_request(2, 1, 67, 0).encode(WriteLength::Captured);
    for i in 0..(5 * LOG_KEEPS as u64) {
        sim.receive(&read, Duration::from_millis(i));
    }
    assert!(sim.received().len() <= 2 * LOG_KEEPS, "{}", sim.received().len());
    assert!(sim.received().len() >= LOG_KEEPS);
    assert_eq!(
        sim.received().last().map(|(t, _)| *t),
        Some(Duration::from_millis(5 * LOG_KEEPS as u64 - 1))
    );
}
