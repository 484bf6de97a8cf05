use super::*;
use crate::family::ct_ansi::codec::{DataValue, ACK, EOT, NAK};
use crate::sim::SimulatedDrive;

fn sim() -> CtSimulator {
    CtSimulator::new(NodeAddress::new(1, 2).unwrap(), SimConfig::default())
}

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// The bytes of the single reply, or `None` for silence.
fn ask(s: &mut CtSimulator, bytes: &[u8], at: u64) -> Option<Vec<u8>> {
    let mut r = s.receive(bytes, ms(at));
    assert!(r.len() <= 1, "{r:?}");
    r.pop().map(|r| {
        assert_eq!(r.at, ms(at) + TURNAROUND);
        r.bytes
    })
}

fn write(address: &str, param: &str, text: &str) -> Vec<u8> {
    Request::Write {
        address: Some(NodeAddress::parse(address).unwrap()),
        parameter: Parameter::parse(param).unwrap(),
        value: DataValue::parse(text.as_bytes(), 0).unwrap(),
    }
    .encode()
    .unwrap()
}

fn read(address: &str, param: &str) -> Vec<u8> {
    Request::Read {
        address: NodeAddress::parse(address).unwrap(),
        parameter: Parameter::parse(param).unwrap(),
    }
    .encode()
    .unwrap()
}

#[test]
fn the_worked_write_and_read_of_the_notes() {
    let mut s = sim();
    assert_eq!(ask(&mut s, b"\x041122\x020121-34.5\x030", 0), Some(vec![ACK]));
    assert_eq!(
        ask(&mut s, b"\x0411220121\x05", 10).unwrap(),
        b"\x020121-34.5\x030"
    );
    assert_eq!(s.setpoint_rpm(), -34.5);
}

#[test]
fn exact_decimals_go_in_and_come_back() {
    let mut s = sim();
    assert_eq!(ask(&mut s, &write("1.2", "1.21", "1500.5"), 0), Some(vec![ACK]));
    let reply = ask(&mut s, &read("1.2", "1.21"), 5).unwrap();
    assert_eq!(&reply[5..12], b"+1500.5");
}

#[test]
fn the_printed_message_with_the_wrong_block_check_gets_no_answer() {
    let mut s = CtSimulator::new(NodeAddress::new(2, 6).unwrap(), SimConfig::default());
    assert_eq!(ask(&mut s, b"\x042266\x020121+076.4\x031", 0), None);
    assert_eq!(s.setpoint_rpm(), 0.0);
    // The corrected block check is taken.
    assert_eq!(ask(&mut s, b"\x042266\x020121+076.4\x03!", 5), Some(vec![ACK]));
    assert_eq!(s.setpoint_rpm(), 76.4);
}

#[test]
fn rewrites_and_short_commands_follow_an_established_address() {
    let mut s = sim();
    // Nothing established yet: a rewrite and a short command are ignored.
    let rewrite = Request::Write {
        address: None,
        parameter: Parameter::new(1, 21).unwrap(),
        value: DataValue::new(100, 1),
    }
    .encode()
    .unwrap();
    assert_eq!(ask(&mut s, &rewrite, 0), None);
    assert_eq!(ask(&mut s, &[NAK], 1), None);
    // A read of a parameter that does not exist still establishes it.
    assert_eq!(ask(&mut s, &read("1.2", "99.99"), 2), Some(vec![EOT]));
    assert_eq!(ask(&mut s, &rewrite, 3), Some(vec![ACK]));
    assert_eq!(s.setpoint_rpm(), 10.0);
    let again = ask(&mut s, &[NAK], 4).unwrap();
    assert_eq!(&again[1..5], b"0121");
    assert!(ask(&mut s, &read("1.2", "10.02"), 5).is_some());
    let next = ask(&mut s, &[ACK], 5).unwrap();
    assert_eq!(&next[1..5], b"1003");
    let previous = ask(&mut s, &[0x08], 6).unwrap();
    assert_eq!(&previous[1..5], b"1002");
    // A message to another drive takes the address away.
    assert_eq!(ask(&mut s, &read("1.3", "1.21"), 7), None);
    assert_eq!(ask(&mut s, &[NAK], 8), None);
}

#[test]
fn group_and_global_writes_act_without_an_answer() {
    let mut s = sim();
    assert_eq!(ask(&mut s, &write("1.0", "1.21", "200.5"), 0), None);
    assert_eq!(s.setpoint_rpm(), 200.5);
    assert_eq!(ask(&mut s, &write("0.0", "1.21", "-5"), 1), None);
    assert_eq!(s.setpoint_rpm(), -5.0);
    assert_eq!(ask(&mut s, &write("2.0", "1.21", "7"), 2), None);
    assert_eq!(
        s.setpoint_rpm(),
        -5.0,
        "another group's write is not for this drive"
    );
    assert_eq!(
        ask(&mut s, &read("1.0", "1.21"), 3),
        None,
        "group reads get no answer"
    );
    assert_eq!(s.received().len(), 3);
}

#[test]
fn the_control_word_runs_and_stops_the_drive_and_the_status_word_shows_it() {
    let mut s = sim();
    let status = |s: &mut CtSimulator, at| {
        let r = ask(s, &read("1.2", "10.40"), at).unwrap();
        let v = Reply::decode(&r).unwrap();
        match v {
            Reply::Value { value, .. } => value.digits,
            other => panic!("{other:?}"),
        }
    };
    assert_eq!(status(&mut s, 0) & 0x3, 0x1, "healthy, not active");
    assert_eq!(ask(&mut s, &write("1.2", "6.42", "131"), 1), Some(vec![ACK]));
    assert_eq!(s.state(), DeviceState::SwitchOnDisabled, "#6.43 is still 0");
    assert_eq!(ask(&mut s, &write("1.2", "6.43", "1"), 2), Some(vec![ACK]));
    assert_eq!(ask(&mut s, &write("1.2", "6.42", "131"), 3), Some(vec![ACK]));
    assert_eq!(s.state(), DeviceState::OperationEnabled);
    assert_eq!(status(&mut s, 4) & 0x3, 0x3, "healthy and active");
    assert_eq!(ask(&mut s, &write("1.2", "6.42", "129"), 5), Some(vec![ACK]));
    assert_eq!(s.state(), DeviceState::SwitchedOn);
    assert_eq!(ask(&mut s, &write("1.2", "6.42", "128"), 6), Some(vec![ACK]));
    assert_eq!(s.state(), DeviceState::SwitchOnDisabled);
    assert_eq!(s.control_words_written(), vec![131, 131, 129, 128]);
}

#[test]
fn a_trip_shows_as_not_healthy_and_100_in_10_38_resets_it() {
    let mut s = sim();
    s.faults().trip_at(ms(1), 7);
    let r = ask(&mut s, &read("1.2", "10.01"), 2).unwrap();
    assert_eq!(&r[5..7], b"+0");
    assert_eq!(s.state(), DeviceState::Fault);
    assert_eq!(ask(&mut s, &write("1.2", "10.38", "100"), 3), Some(vec![ACK]));
    assert_eq!(s.state(), DeviceState::SwitchOnDisabled);
    let r = ask(&mut s, &read("1.2", "10.20"), 4).unwrap();
    assert_eq!(&r[5..7], b"+7", "the last trip outlives the reset");
}

#[test]
fn refusals_and_unknown_parameters() {
    let mut s = sim();
    assert_eq!(ask(&mut s, &write("1.2", "10.40", "1"), 0), Some(vec![NAK]));
    assert_eq!(ask(&mut s, &write("1.2", "1.21", "99999"), 1), Some(vec![NAK]));
    assert_eq!(ask(&mut s, &write("1.2", "42.42", "1"), 2), Some(vec![NAK]));
    assert_eq!(ask(&mut s, &read("1.2", "42.42"), 3), Some(vec![EOT]));
    // Noise before a message is skipped.
    let mut noisy = b"zz".to_vec();
    noisy.extend(read("1.2", "1.21"));
    assert!(ask(&mut s, &noisy, 4).is_some());
}
