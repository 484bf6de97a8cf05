//! The Modbus dictionaries: the inverter profile in the profile format's two additions
//! for inverters (`control: codes`, a state's `values:`), which without them would be
//! refused or would not read a running inverter as running.

use crate::dictionary::{Dictionary, DictionaryError};
use crate::drive::device_control::DeviceState;
use crate::family::modbus::register_address::parse_address;
use crate::family::Registry;

fn e500_text() -> String {
    let r = Registry::builtin();
    r.dictionary("sunfar-e500").unwrap().1.text.to_string()
}

fn load(text: &str) -> Result<Dictionary, DictionaryError> {
    Dictionary::from_yaml_for("test.yaml", text, parse_address)
}

/// Every problem of a dictionary that must be refused, as text to look for words in.
fn refusal(text: &str) -> String {
    format!("{:?}", load(text).unwrap_err())
}

#[test]
fn every_status_code_of_the_e500_reads_as_its_state() {
    let d = Registry::builtin().load_dictionary("sunfar-e500").unwrap();
    let p = d.profile().unwrap();
    for (code, state) in [
        (0x0000, Some(DeviceState::NotReadyToSwitchOn)),
        (0x0001, Some(DeviceState::OperationEnabled)),
        (0x0002, Some(DeviceState::OperationEnabled)),
        (0x0011, Some(DeviceState::OperationEnabled)),
        (0x0015, Some(DeviceState::OperationEnabled)),
        (0x0003, Some(DeviceState::SwitchedOn)),
        (0x0020, Some(DeviceState::Fault)),
        (0x0016, None),
    ] {
        assert_eq!(p.state_of(code), state, "{code:#06x}");
    }
}

#[test]
fn command_codes_need_control_codes_and_a_stop_that_is_not_the_run_code() {
    let text = e500_text();
    assert!(load(&text).is_ok());
    let as_bits = refusal(&text.replace("  control: codes\n", ""));
    assert!(as_bits.contains("keeps every bit"), "{as_bits}");
    let bad = refusal(&text.replace("    disable_operation: 3\n", "    disable_operation: 1\n"));
    assert!(bad.contains("is the run code 1"), "{bad}");
    let unknown = refusal(&text.replace("control: codes", "control: words"));
    assert!(unknown.contains("`control` is `bits` or `codes`"), "{unknown}");
}

#[test]
fn states_given_by_several_values_must_not_overlap_other_states() {
    let text = e500_text().replace("values: [0x0001, 0x0002,", "values: [0x0003, 0x0002,");
    let e = refusal(&text);
    assert!(e.contains("overlap"), "{e}");
}
