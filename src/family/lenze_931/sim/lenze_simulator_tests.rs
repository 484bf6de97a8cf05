//! The simulated 931 answers real request lines: every command, every error code it can
//! produce, limited writes, limits, garbage, echo and CR LF.

use super::*;
use crate::drive::DeviceState;
use crate::sim::{SimConfig, SimulatedDrive};

fn ask(sim: &mut LenzeSimulator, line: &str) -> String {
    let mut bytes = line.as_bytes().to_vec();
    bytes.push(b'\r');
    let replies = sim.receive(&bytes, Duration::from_millis(1));
    replies
        .iter()
        .map(|r| String::from_utf8_lossy(&r.bytes).into_owned())
        .collect::<Vec<_>>()
        .join("|")
}

/// Sends each line of `(request, reply)` in turn, naming the request whose reply differs.
#[track_caller]
fn converse(sim: &mut LenzeSimulator, lines: &[(&str, &str)]) {
    for (request, reply) in lines {
        assert_eq!(ask(sim, request), *reply, "the reply to {request}");
    }
}

fn sim() -> LenzeSimulator {
    LenzeSimulator::new(SimConfig::default())
}

#[test]
fn object_commands_and_their_error_codes() {
    let mut s = sim();
    converse(
        &mut s,
        &[
            ("OW:0010:00000BB8", "OK!\r"),
            ("OR:0010", "0010:00000BB8\r"),
            ("OW:0010:FFFFF448", "OK!\r"),
            ("OR:0010", "0010:FFFFF448\r"),
            ("OI:0010", "0010:FFFFF448\r"),
            ("ON:0010", "0010:FFFFE890\r"),
            ("OX:0010", "0010:00001770\r"),
            // Written but limited, both ways; the stored value is the limit.
            ("OW:0010:00001F40", "OW:00000005\r"),
            ("OR:0010", "0010:00001770\r"),
            ("OW:0010:FFFFE0C0", "OW:00000004\r"),
            ("OR:0010", "0010:FFFFE890\r"),
            // Refused, not written.
            ("OW:0014:00000004", "OW:00000003\r"),
            ("OW:0014:FFFFFFFF", "OW:00000002\r"),
            ("OR:0014", "0014:00000000\r"),
            ("OW:0020:00000005", "OW:00000008\r"),
            ("OW:0011:00000001", "OW:00050000\r"),
            ("OR:0099", "OR:00040000\r"),
            ("ON:0011", "ON:00020000\r"),
            ("OX:0011", "OX:00030000\r"),
        ],
    );
    // Code 9: the operating mode cannot change while enabled.
    for cw in ["00000006", "00000007", "0000000F"] {
        assert_eq!(ask(&mut s, &format!("OW:0020:{cw}")), "OK!\r");
    }
    assert_eq!(s.state(), DeviceState::OperationEnabled);
    assert_eq!(ask(&mut s, "OW:0014:00000001"), "OW:00000009\r");
    assert_eq!(s.control_words_written(), vec![6, 7, 15]);
}

#[test]
fn the_status_word_has_the_manuals_bits() {
    let mut s = sim();
    let word = |s: &mut LenzeSimulator| {
        let r = ask(s, "OR:0001");
        u32::from_str_radix(r.trim_end().split_once(':').unwrap().1, 16).unwrap()
    };
    assert_eq!(word(&mut s), 1 << 13, "at rest, switch on disabled");
    ask(&mut s, "OW:0020:00000006");
    assert_eq!(
        word(&mut s),
        1 << 13 | 1 << 15,
        "ready to switch on: ready, power stage still off"
    );
}

#[test]
fn identification_service_and_sdo_commands() {
    let mut s = sim();
    converse(
        &mut s,
        &[
            ("TYPE?", "TYPE:0931\r"),
            ("VERSION?", "0000:VERSION:0100\r"),
            ("BOOT?", "APPLICATION\r"),
            ("BUS?", "0000:BUS:01:0500:0000\r"),
            ("SAVE!", "DONE\r"),
            ("SEP!", "DONE\r"),
            ("BAUD9600", "OK!\r"),
            ("?604100", "=604100:4002\r"),
            ("=604000:0600", "=604000:0600\r"),
        ],
    );
    assert_eq!(s.state(), DeviceState::ReadyToSwitchOn);
    assert_eq!(ask(&mut s, "?123400"), "ERROR!\r");
    ask(&mut s, "OW:0010:00000064");
    assert!(ask(&mut s, "INIT!").starts_with("931 SIMULATED"));
    assert_eq!(ask(&mut s, "OR:0010"), "0010:00000000\r");
    assert!(ask(&mut s, "RESET!").starts_with("931 SIMULATED"));
}

#[test]
fn garbage_and_over_long_lines_get_error() {
    let mut s = sim();
    assert_eq!(ask(&mut s, "HELLO"), "ERROR!\r");
    assert_eq!(ask(&mut s, "\u{1}\u{2}"), "ERROR!\r");
    assert_eq!(ask(&mut s, &"7".repeat(5000)), "ERROR!\r");
    assert_eq!(ask(&mut s, "OR:0010"), "0010:00000000\r");
}

#[test]
fn echo_crlf_and_injected_reply_faults() {
    let mut s = sim();
    s.set_echo(true);
    s.set_crlf(true);
    assert_eq!(ask(&mut s, "OR:0010"), "OR:0010\r|0010:00000000\r\n");
    let mut s = sim();
    s.faults().drop_replies(1);
    assert_eq!(ask(&mut s, "OW:0010:00000001"), "");
    assert_eq!(
        ask(&mut s, "OR:0010"),
        "0010:00000001\r",
        "the request behind a lost reply was executed"
    );
    s.faults().corrupt_checksum(1);
    assert!(ask(&mut s, "OR:0010").contains('#'));
    s.faults().wrong_address(1);
    assert_eq!(ask(&mut s, "OR:0010"), "0011:00000001\r");
}

#[test]
fn maintenance_commands_restore_defaults_load_the_flash_and_take_the_rate() {
    let mut s = sim();
    ask(&mut s, "OW:0014:00000002");
    assert_eq!(ask(&mut s, "SAVE!"), "DONE\r");
    ask(&mut s, "OW:0014:00000001");
    assert_eq!(ask(&mut s, "SEP!"), "DONE\r");
    assert_eq!(s.operating_mode(), 2, "SEP! loads what SAVE! stored");
    ask(&mut s, "OW:0010:00000064");
    ask(&mut s, "OW:0020:00000006");
    assert_eq!(s.state(), DeviceState::ReadyToSwitchOn);
    assert_eq!(
        ask(&mut s, "INIT!"),
        "931 SIMULATED: default parameter set loaded\r"
    );
    assert_eq!(s.operating_mode(), 0);
    assert_eq!(ask(&mut s, "OR:0010"), "0010:00000000\r");
    assert_eq!(s.state(), DeviceState::SwitchOnDisabled);
    ask(&mut s, "OW:0014:00000003");
    assert_eq!(ask(&mut s, "RESET!"), "931 SIMULATED: reset\r");
    assert_eq!(s.operating_mode(), 0);
    assert_eq!(s.line_rate(), 9600);
    assert_eq!(ask(&mut s, "BAUD19200"), "OK!\r");
    assert_eq!(s.line_rate(), 19200);
}
