//! The built-in Unidrive SP dictionary and the profile shapes it needs: exact decimals on
//! every parameter, a command writing another object, a write before every command,
//! commands and states the drive does not have, and the refusals of profiles that would
//! not be safe.

use crate::dictionary::{DecimalPlaces, Dictionary, DictionaryError, Quantity, RawValue};
use crate::drive::device_control::{DeviceCommand, DeviceState};
use crate::drive::state_path::{next_step_in, NextStep};
use crate::family::Registry;

fn ct() -> Dictionary {
    Registry::builtin()
        .load_dictionary("ct-unidrive-sp")
        .unwrap_or_else(|e| panic!("{e:?}"))
}

#[test]
fn every_parameter_gives_its_decimal_places() {
    let d = ct();
    assert_eq!(d.family(), "ct-ansi");
    for o in d.objects() {
        assert!(
            matches!(o.decimal_places, Some(DecimalPlaces::Fixed(_))),
            "{} has no decimals",
            o.name
        );
    }
    for common in [
        "speed_setpoint",
        "speed_actual",
        "current_actual",
        "bus_voltage",
        "status_word",
        "control_word",
        "ident",
    ] {
        assert!(d.get(common).is_some(), "{common}");
    }
    let setpoint = d.get("speed_setpoint").unwrap();
    let raw = setpoint.to_raw(&Quantity::parse("1500.5 rpm").unwrap()).unwrap();
    assert_eq!(
        raw,
        RawValue::Decimal {
            digits: 15005,
            places: 1
        }
    );
    assert_eq!(raw.to_string(), "1500.5");
    let current = d.get("current_actual").unwrap();
    let v = current
        .value_of(RawValue::Decimal {
            digits: 1234,
            places: 2,
        })
        .unwrap();
    assert_eq!(v.to_string(), "12.34 A");
}

#[test]
fn the_profile_maps_the_control_word_onto_the_common_names() {
    let d = ct();
    let p = d.profile().unwrap();
    assert_eq!(p.command_text(DeviceCommand::EnableOperation), "control word 131");
    assert_eq!(
        p.command_text(DeviceCommand::DisableOperation),
        "control word 129"
    );
    assert_eq!(p.command_text(DeviceCommand::Shutdown), "control word 128");
    assert_eq!(p.command_text(DeviceCommand::FaultReset), "user_trip = 100");
    assert!(!p.has_command(DeviceCommand::QuickStop));
    assert_eq!(p.before_commands().len(), 1);
    assert_eq!(p.before_commands()[0].object, "control_word_enable");
    assert_eq!(p.state_of(0x0001), Some(DeviceState::SwitchedOn));
    assert_eq!(p.state_of(0x0003), Some(DeviceState::OperationEnabled));
    assert_eq!(p.state_of(0x0007), Some(DeviceState::OperationEnabled));
    assert_eq!(p.state_of(0x0000), Some(DeviceState::Fault));
    assert_eq!(
        p.state_of(0x0002),
        Some(DeviceState::Fault),
        "active while tripping"
    );
    assert_eq!(p.state_ids(), vec!["switched_on", "operation_enabled", "fault"]);
}

#[test]
fn paths_go_only_through_the_states_the_drive_has() {
    let d = ct();
    let p = d.profile().unwrap();
    use DeviceState::*;
    assert_eq!(
        next_step_in(p, SwitchedOn, OperationEnabled),
        NextStep::Command(DeviceCommand::EnableOperation)
    );
    assert_eq!(
        next_step_in(p, OperationEnabled, SwitchedOn),
        NextStep::Command(DeviceCommand::DisableOperation)
    );
    assert_eq!(
        next_step_in(p, SwitchedOn, ReadyToSwitchOn),
        NextStep::Unreachable
    );
    assert_eq!(
        next_step_in(p, OperationEnabled, QuickStopActive),
        NextStep::Unreachable
    );
    assert_eq!(next_step_in(p, SwitchedOn, SwitchedOn), NextStep::Arrived);
    // A complete profile walks exactly as before.
    let sd2 = Registry::builtin().load_dictionary("sd2").unwrap();
    let full = sd2.profile().unwrap();
    for from in DeviceState::ALL {
        for to in DeviceState::ALL {
            assert_eq!(
                next_step_in(full, from, to),
                crate::drive::state_path::next_step(from, to)
            );
        }
    }
}

/// A small dictionary with `profile` (the lines under `profile:`).
fn with_profile(profile: &str) -> Result<Dictionary, DictionaryError> {
    let text = format!(
        "family: x\nobjects:\n  - {{ name: cw, index: 1, type: u16, access: rw }}\n  - {{ name: sw, index: 2, type: u16, access: ro }}\n  - {{ name: reset, index: 3, type: u16, access: rw }}\n  - {{ name: ro_word, index: 4, type: u16, access: ro }}\nprofile:\n  control_word: cw\n  status_word: sw\n{profile}"
    );
    Dictionary::from_yaml("test.yaml", &text)
}

const COMMANDS: &str = "  commands:\n    shutdown: 128\n    switch_on: 129\n    disable_voltage: 128\n    quick_stop: none\n    disable_operation: 129\n    enable_operation: 131\n    fault_reset: { object: reset, value: 100 }\n";
const STATES: &str = "  states:\n    not_ready_to_switch_on: none\n    switch_on_disabled: none\n    ready_to_switch_on: none\n    switched_on: { mask: 3, value: 1 }\n    operation_enabled: { mask: 3, value: 3 }\n    quick_stop_active: none\n    fault_reaction_active: none\n    fault: { mask: 1, value: 0 }\n";

#[test]
fn a_reduced_profile_reads_and_unsafe_ones_are_refused() {
    let ok = with_profile(&format!(
        "  before_commands: [{{ object: reset, value: 0 }}]\n{COMMANDS}{STATES}"
    ));
    assert!(ok.is_ok(), "{ok:?}");
    let refused = |profile: String, why: &str| {
        let e = format!("{:?}", with_profile(&profile).unwrap_err());
        assert!(e.contains(why), "expected `{why}` in {e}");
    };
    refused(
        format!("{}{STATES}", COMMANDS.replace("shutdown: 128", "shutdown: none")),
        "`shutdown` cannot be `none`",
    );
    refused(
        format!(
            "{}{STATES}",
            COMMANDS.replace(
                "disable_operation: 129",
                "disable_operation: { object: reset, value: 1 }"
            )
        ),
        "`disable_operation` must write the control word",
    );
    refused(
        format!("{}{STATES}", COMMANDS.replace("object: reset", "object: nothing")),
        "the profile writes `nothing` (written by `fault_reset`), which is not an object",
    );
    refused(
        format!("{}{STATES}", COMMANDS.replace("object: reset", "object: ro_word")),
        "but it is read-only u16",
    );
    refused(
        format!("  before_commands: [{{ object: ro_word, value: 1 }}]\n{COMMANDS}{STATES}"),
        "written before every command",
    );
    refused(
        format!(
            "{COMMANDS}{}",
            STATES.replace("fault: { mask: 1, value: 0 }", "fault: none")
        ),
        "`fault` cannot be `none`",
    );
    refused(
        format!(
            "{COMMANDS}{}",
            STATES.replace("switched_on: { mask: 3, value: 1 }", "switched_on: none")
        ),
        "no state where the drive is stopped",
    );
    refused(
        format!(
            "{}{STATES}",
            COMMANDS.replace("disable_operation: 129", "disable_operation: 131")
        ),
        "keeps every bit of `enable_operation`",
    );
}

#[test]
fn decimals_are_read_and_checked() {
    let object = |keys: &str| {
        Dictionary::from_yaml(
            "test.yaml",
            &format!("family: x\nobjects:\n  - {{ name: speed, index: 1, type: i32, access: rw, {keys} }}\n"),
        )
    };
    let d = object("decimals: 2, unit: rpm").unwrap();
    let o = d.get("speed").unwrap();
    assert_eq!(
        (o.decimal_places, o.decimals()),
        (Some(DecimalPlaces::Fixed(2)), 2)
    );
    let raw = o.to_raw(&Quantity::parse("12.34 rpm").unwrap()).unwrap();
    assert_eq!(raw.to_string(), "12.34");
    let e = format!("{:?}", object("decimals: 1, scale: 0.1").unwrap_err());
    assert!(e.contains("give `decimals` or `scale`, not both"), "{e}");
    let e = format!("{:?}", object("decimals: 11").unwrap_err());
    assert!(e.contains("decimals"), "{e}");
    let e = Dictionary::from_yaml(
        "test.yaml",
        "family: x\nobjects:\n  - { name: t, index: 1, type: string(8), access: rw, decimals: 1 }\n",
    )
    .unwrap_err();
    assert!(
        format!("{e:?}").contains("a string object has no `decimals`"),
        "{e:?}"
    );
}

/// A user's file written before family ids were unified (`family: ct_ansi`) still extends
/// the dictionary, with a note at its `family:` naming today's spelling for `check`.
#[test]
fn a_user_file_with_the_former_family_id_extends_with_a_note() {
    let mut d = ct();
    let user = Dictionary::from_yaml(
        "mine.yaml",
        "family: ct_ansi\nobjects:\n  - name: motor_temperature\n    index: 500\n    type: i16\n    access: ro\n",
    )
    .unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(user.family(), "ct-ansi");
    d.extend(user).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(d.lookup("motor_temperature").is_ok());
    let notes: Vec<String> = d.notes().iter().map(|n| n.located()).collect();
    assert_eq!(
        notes,
        ["mine.yaml:1:9: `family: ct_ansi` is the former spelling of the family id `ct-ansi`; it still works"]
    );
    assert_eq!(d.notes()[0].help(), Some("write `family: ct-ansi`"));
    let wrong = Dictionary::from_yaml("bad.yaml", "family: Ct.Ansi\nobjects: []\n").unwrap_err();
    assert!(
        format!("{wrong:?}").contains("`Ct.Ansi` is not a family id"),
        "{wrong:?}"
    );
}
