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

/// The E500's frequency registers count 0.1 Hz: their rpm follow the motor's pole pairs
/// (rpm = Hz × 60 / pole pairs), the scale and the 400 Hz limit alike, and Hz is accepted.
#[test]
fn the_e500s_rpm_follow_the_pole_pairs_and_hz_converts() {
    use crate::dictionary::{Quantity, RawValue, Unit, ValueError};
    let mut d = Registry::builtin().load_dictionary("sunfar-e500").unwrap();
    assert_eq!(d.pole_pairs().map(|p| p.count), Some(1));
    let hz = |v: f64| Quantity::new(v, Some(Unit::Hertz));
    let setpoint = d.get("speed_setpoint").unwrap().clone();
    assert_eq!(setpoint.to_raw(&hz(50.0)).unwrap(), RawValue::Int(500));
    assert_eq!(setpoint.max, Some(24000.0));
    // Beyond 400 Hz in either unit: the 300 000 rpm a recipe once passed `check` with.
    assert!(matches!(
        setpoint.to_raw(&Quantity::new(300_000.0, Some(Unit::Rpm))),
        Err(ValueError::AboveMax { .. })
    ));
    assert!(matches!(
        setpoint.to_raw(&hz(400.1)),
        Err(ValueError::AboveMax { .. })
    ));
    d.set_pole_pairs(2, "--link-option pole-pairs=2").unwrap();
    for name in ["speed_setpoint", "speed_actual"] {
        let o = d.get(name).unwrap();
        assert_eq!((o.scale, o.pole_pairs), (3.0, Some(2)), "{name}");
    }
    let setpoint = d.get("speed_setpoint").unwrap();
    assert_eq!(setpoint.max, Some(12000.0));
    // 100 Hz is 3000 rpm for a 4-pole motor: 1000 counts of 0.1 Hz either way written.
    assert_eq!(setpoint.to_raw(&hz(100.0)).unwrap(), RawValue::Int(1000));
    let rpm = Quantity::new(3000.0, Some(Unit::Rpm));
    assert_eq!(setpoint.to_raw(&rpm).unwrap(), RawValue::Int(1000));
    assert_eq!(setpoint.in_own_unit(100.0, Unit::Hertz).unwrap(), 3000.0);
    assert_eq!(setpoint.factor_to(Unit::Hertz).unwrap(), 1.0 / 30.0);
    assert_eq!(setpoint.factor_to(Unit::Krpm).unwrap(), 0.001);
    // The current is no speed: no pole pairs, no Hz.
    let current = d.get("current_actual").unwrap();
    assert_eq!(current.pole_pairs, None);
    assert!(matches!(
        current.in_own_unit(1.0, Unit::Hertz),
        Err(ValueError::WrongUnit { .. })
    ));
    // Back to one pole pair: the dictionary's own numbers again.
    d.set_pole_pairs(1, "test").unwrap();
    let setpoint = d.get("speed_setpoint").unwrap();
    assert_eq!((setpoint.scale, setpoint.max), (6.0, Some(24000.0)));
}

/// A servo's dictionary says no pole pairs: Hz is refused with what to give, and the
/// pole pairs cannot be set on it.
#[test]
fn without_pole_pairs_hz_is_refused_with_a_hint() {
    use crate::dictionary::{Quantity, Unit, ValueError};
    let mut d = Registry::builtin().load_dictionary("sd2").unwrap();
    let setpoint = d.get("speed_setpoint").unwrap().clone();
    let e = setpoint
        .to_raw(&Quantity::new(100.0, Some(Unit::Hertz)))
        .unwrap_err();
    assert!(matches!(e, ValueError::NoPolePairs { .. }), "{e:?}");
    let text = e.to_string();
    assert!(
        text.contains("the dictionary does not say the motor's pole pairs"),
        "{text}"
    );
    assert!(text.contains("give `pole_pairs: N`"), "{text}");
    assert!(matches!(
        setpoint.factor_to(Unit::Hertz),
        Err(ValueError::NoPolePairs { .. })
    ));
    assert!(matches!(
        d.set_pole_pairs(2, "--link-option pole-pairs=2"),
        Err(ValueError::PolePairsNotUsed { .. })
    ));
}

/// `pole_pairs:` in a dictionary file is a whole number 1..=32, refused at its line else.
#[test]
fn a_dictionarys_pole_pairs_are_checked() {
    let text = e500_text().replace("pole_pairs: 1", "pole_pairs: 0");
    let e = refusal(&text);
    assert!(e.contains("not a number of pole pairs"), "{e}");
    let text = e500_text().replace("pole_pairs: 1", "pole_pairs: 2");
    let d = load(&text).unwrap();
    assert_eq!(d.get("speed_actual").unwrap().pole_pairs, Some(2));
}

/// A user's file with `pole_pairs:` speaks for the whole dictionary: the built-in speed
/// objects it does not replace are rescaled to its motor.
#[test]
fn a_users_file_with_pole_pairs_rescales_the_objects_it_keeps() {
    let mut d = Registry::builtin().load_dictionary("sunfar-e500").unwrap();
    let mine = "family: modbus-rtu\npole_pairs: 2\nobjects:\n  - { name: spare, address: \"holding 0x3000\", type: u16, access: ro }\n";
    d.extend(load(mine).unwrap()).unwrap();
    assert_eq!(d.pole_pairs().map(|p| p.count), Some(2));
    let setpoint = d.get("speed_setpoint").unwrap();
    assert_eq!(
        (setpoint.scale, setpoint.max, setpoint.pole_pairs),
        (3.0, Some(12000.0), Some(2))
    );
}
