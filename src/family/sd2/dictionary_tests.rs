//! Tests of the dictionary format on the SD2 family's dictionary (the reference file): the built-in file, every validation error with
//! its line and column, collecting all errors, lookup with suggestions, extend.

use crate::diag::Diagnostic;
use crate::dictionary::*;
use crate::drive::device_control::{DeviceCommand, DeviceState};

const SD2: &str = include_str!("../../../dictionary/sd2.yaml");

fn parse(text: &str) -> Result<Dictionary, DictionaryError> {
    Dictionary::from_yaml("test.yaml", text)
}

/// (line, column, message) of every problem.
fn problems(text: &str) -> Vec<(usize, usize, String)> {
    match parse(text) {
        Ok(_) => panic!("expected problems in:\n{text}"),
        Err(e) => e
            .problems()
            .map(|p| (p.line(), p.column(), p.message().to_string()))
            .collect(),
    }
}

/// The single problem of `text`.
fn problem(text: &str) -> Diagnostic {
    let e = parse(text).expect_err("expected a problem");
    assert_eq!(
        e.count(),
        1,
        "expected one problem, got: {:#?}",
        e.problems().map(|p| p.located()).collect::<Vec<_>>()
    );
    e.first().clone()
}

/// 1-based line and column of the first occurrence of `needle` in `text`.
fn pos(text: &str, needle: &str) -> (usize, usize) {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in text"));
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, column)
}

/// The built-in SD2 file with `from` replaced by `to`, and its one problem.
#[track_caller]
fn sd2_problem(from: &str, to: &str) -> (String, Diagnostic) {
    assert!(SD2.contains(from), "the SD2 file has no {from:?}");
    let text = SD2.replace(from, to);
    let e = problem(&text);
    (text, e)
}

/// Fails the test, showing the message, unless problem `e`'s message holds `part`.
#[track_caller]
fn assert_says(e: &Diagnostic, part: &str) {
    assert!(e.message().contains(part), "{}", e.message());
}

/// The built-in SD2 dictionary, as a recipe without its own gets it.
fn builtin() -> Dictionary {
    crate::family::Registry::builtin()
        .load_dictionary(crate::family::DEFAULT_DICTIONARY)
        .unwrap()
}

/// Fails the test unless problem `e` is at `(line, column)` and says `message`.
#[track_caller]
fn assert_problem(e: &Diagnostic, line_column: (usize, usize), message: &str) {
    assert_eq!(at(e), line_column, "{}", e.message());
    assert_eq!(e.message(), message);
}

fn at(e: &Diagnostic) -> (usize, usize) {
    (e.line(), e.column())
}

/// The problem as a user reads it: miette's report, plain.
fn rendered(e: &dyn miette::Diagnostic) -> String {
    let mut out = String::new();
    crate::diag::report_handler(false)
        .render_report(&mut out, e)
        .unwrap();
    out
}

/// A valid one-object file; `extra` lines are appended to the object.
fn object(extra: &str) -> String {
    format!("family: sd2\nobjects:\n  - name: a\n    index: 1\n    type: u16\n    access: ro\n{extra}")
}

/// name, index, type, access, unit, scale
type Row = (&'static str, u16, DataType, Access, Option<Unit>, f64);

#[test]
fn builtin_sd2_loads_and_validates() {
    let d = builtin();
    assert_eq!(d.family(), "sd2");
    assert!(d.title().contains("SD2"));
    let names: Vec<&str> = d.objects().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "ident",
            "bus_voltage",
            "power_stage_load",
            "status_word",
            "control_word",
            "speed_actual_2",
            "parameter_set",
            "speed_setpoint",
            "speed_actual",
            "current_actual",
            "drive_error",
            "store_parameters",
            "motor_temperature"
        ]
    );
    #[rustfmt::skip]
    let table: [Row; 12] = [
        ("ident", 22, DataType::String { max: 32 }, Access::ReadOnly, None, 1.0),
        ("bus_voltage", 33, DataType::U16, Access::ReadOnly, Some(Unit::Volt), 0.1),
        ("power_stage_load", 39, DataType::U16, Access::ReadOnly, Some(Unit::Percent), 0.1),
        ("status_word", 67, DataType::U16, Access::ReadOnly, None, 1.0),
        ("control_word", 68, DataType::U16, Access::ReadWrite, None, 1.0),
        ("speed_actual_2", 168, DataType::I32, Access::ReadOnly, Some(Unit::Rpm), 0.001),
        ("parameter_set", 352, DataType::U16, Access::ReadWrite, None, 1.0),
        ("speed_setpoint", 395, DataType::I32, Access::ReadWrite, Some(Unit::Rpm), 0.001),
        ("speed_actual", 398, DataType::I32, Access::ReadOnly, Some(Unit::Rpm), 0.001),
        ("current_actual", 400, DataType::I32, Access::ReadOnly, Some(Unit::Ampere), 0.001),
        ("drive_error", 401, DataType::U16, Access::ReadOnly, None, 1.0),
        ("store_parameters", 402, DataType::U16, Access::WriteOnly, None, 1.0),
    ];
    for (name, index, data_type, access, unit, scale) in table {
        let o = d.lookup(name).unwrap();
        assert_eq!(o.address, Address::indexed(index, 0), "{name}");
        assert_eq!(
            (o.data_type, o.access, o.unit, o.scale),
            (data_type, access, unit, scale),
            "{name}"
        );
    }
    for unconfirmed in [
        "bus_voltage",
        "power_stage_load",
        "speed_actual_2",
        "parameter_set",
        "current_actual",
        "drive_error",
        "store_parameters",
    ] {
        assert!(
            d.lookup(unconfirmed).unwrap().unconfirmed.is_some(),
            "{unconfirmed}"
        );
    }
    for confirmed in [
        "ident",
        "status_word",
        "control_word",
        "speed_setpoint",
        "speed_actual",
    ] {
        assert!(d.lookup(confirmed).unwrap().unconfirmed.is_none(), "{confirmed}");
    }
    let sp = d.lookup("speed_setpoint").unwrap();
    assert_eq!((sp.min, sp.max), (Some(-60000.0), Some(60000.0)));
    assert!(sp.description.contains("default"));
    let ps = d.lookup("parameter_set").unwrap();
    assert_eq!((ps.min, ps.max), (Some(0.0), Some(64.0)));

    let p = d.profile().unwrap();
    assert_eq!(p.object(Role::ControlWord), Some("control_word"));
    assert_eq!(p.object(Role::StatusWord), Some("status_word"));
    assert_eq!(p.object(Role::SpeedSetpoint), Some("speed_setpoint"));
    assert_eq!(p.object(Role::SpeedActual), Some("speed_actual"));
    assert_eq!(p.object(Role::CurrentActual), Some("current_actual"));
    assert_eq!(p.object(Role::DriveError), Some("drive_error"));
    assert_eq!(
        d.role(Role::StatusWord).map(|o| o.address),
        Some(Address::indexed(67, 0))
    );
    for c in DeviceCommand::ALL {
        assert_eq!(p.command_value(c), c.default_control_word(), "{c}");
    }
    for s in DeviceState::ALL {
        let (mask, value) = s.default_mask_value();
        assert_eq!(p.state_mask(s), StateMask { mask, value }, "{s}");
    }
    assert_eq!(p.state_of(0x0237), Some(DeviceState::OperationEnabled));
}

#[test]
fn builtin_speeds_to_bytes() {
    let d = builtin();
    let sp = d.lookup("speed_setpoint").unwrap();
    let counts = |text: &str| sp.to_raw(&Quantity::parse(text).unwrap()).unwrap();
    assert_eq!(counts("1000 rpm"), RawValue::Int(1_000_000));
    assert_eq!(counts("6000 rpm"), RawValue::Int(6_000_000));
    assert_eq!(counts("6500 rpm"), RawValue::Int(6_500_000));
    assert_eq!(counts("18000 rpm"), RawValue::Int(18_000_000));
    let e = sp.to_raw(&Quantity::parse("60001 rpm").unwrap()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "60001 rpm is above the maximum of speed_setpoint, 60000 rpm"
    );
    let e = sp.to_raw(&Quantity::parse("2 A").unwrap()).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("A is not a unit of speed_setpoint (rpm)"),
        "{e}"
    );
    let ps = d.lookup("parameter_set").unwrap();
    assert!(ps
        .to_raw(&Quantity::parse("65").unwrap())
        .unwrap_err()
        .to_string()
        .contains("maximum of parameter_set, 64"));
    let ident = d.lookup("ident").unwrap();
    let v = ident.value_of(RawValue::Text("Test Motor".into())).unwrap();
    assert_eq!(v.to_string(), "\"Test Motor\"");
    let bus = d.lookup("bus_voltage").unwrap();
    assert_eq!(bus.value_of(RawValue::Int(3253)).unwrap().to_string(), "325.3 V");
    let sw = d.lookup("status_word").unwrap();
    assert_eq!(sw.value_of(RawValue::Int(0x237)).unwrap().to_string(), "0x0237");
}

#[test]
fn lookup_ignores_case_and_knows_aliases() {
    let d = builtin();
    assert_eq!(d.lookup("SPEED_SETPOINT").unwrap().name, "speed_setpoint");
    assert_eq!(
        d.lookup("spg_target_velocity_vl_uunit").unwrap().name,
        "speed_setpoint"
    );
    assert_eq!(d.lookup("target_speed").unwrap().name, "speed_setpoint");
    assert_eq!(d.lookup("spindle").unwrap().name, "parameter_set");
    assert_eq!(
        d.by_address(398, 0).map(|o| o.name.as_str()),
        Some("speed_actual")
    );
    assert!(d.by_address(398, 1).is_none());
}

#[test]
fn did_you_mean_for_unknown_objects() {
    let d = builtin();
    let e = d.lookup("speed_setpont").unwrap_err();
    assert_eq!(e.suggestions.first().map(String::as_str), Some("speed_setpoint"));
    assert!(e.suggestions.len() <= 3);
    assert!(
        e.to_string()
            .starts_with("no object `speed_setpont` in the sd2 dictionary; did you mean `speed_setpoint`"),
        "{e}"
    );
    let e = d.lookup("actual_sped").unwrap_err();
    assert!(
        e.suggestions.contains(&"speed_actual".to_string()),
        "{:?}",
        e.suggestions
    );
    let e = d.lookup("xyzzy").unwrap_err();
    assert!(e.suggestions.is_empty());
    assert!(e.help().contains("drivescript objects"));
}

#[test]
fn filter_by_name_alias_and_description() {
    let d = builtin();
    let names = |f: &str| {
        d.filter(f)
            .into_iter()
            .map(|o| o.name.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(
        names("speed"),
        ["speed_actual_2", "speed_setpoint", "speed_actual"]
    );
    assert_eq!(names("DEV_CTRL"), ["status_word", "control_word"]);
    assert_eq!(names("supply"), ["bus_voltage"]);
    assert_eq!(names("").len(), 13);
    assert!(names("nothing like this").is_empty());
}

// ---- validation errors, each with its line and column ----

#[test]
fn a_minimal_file_is_valid() {
    let d = parse(&object("")).unwrap();
    assert!(d.profile().is_none());
    let a = d.lookup("a").unwrap();
    assert_eq!((a.span.line(), a.span.column()), (3, 5));
    assert_eq!(a.span.path(), "test.yaml");
}

#[test]
fn unknown_type() {
    let text = object("").replace("type: u16", "type: u64");
    let e = problem(&text);
    assert_problem(&e, (5, 11), "unknown type `u64`");
    assert_eq!(e.label(), "not a type");
    let e = problem(&object("").replace("type: u16", "type: string"));
    assert_eq!(at(&e), (5, 11));
    assert!(e.message().contains("string(32)"));
}

#[test]
fn unknown_unit() {
    let e = problem(&object("    unit: rpn\n"));
    assert_problem(&e, (7, 11), "unknown unit `rpn`");
    assert!(
        e.help().unwrap_or("").starts_with("did you mean `rpm`?"),
        "{:?}",
        e.help()
    );
}

#[test]
fn bad_access() {
    let e = problem(&object("").replace("access: ro", "access: read"));
    assert_problem(&e, (6, 13), "unknown access `read`");
    assert!(e.help().unwrap_or("").contains("ro (read-only)"));
}

#[test]
fn min_greater_than_max() {
    let e = problem(&object("    min: 10\n    max: 5\n"));
    assert_problem(&e, (7, 10), "`min` 10 is greater than `max` 5");
}

#[test]
fn limits_outside_the_type_after_scaling() {
    let text = object("    unit: rpm\n    scale: 0.001\n    min: -60000\n    max: 60000\n")
        .replace("type: u16", "type: i16");
    let all = problems(&text);
    assert_eq!(all.len(), 2, "{all:#?}");
    assert_eq!((all[0].0, all[0].1), (9, 10));
    assert_eq!(
        all[0].2,
        "`min` -60000 rpm is -60000000 counts, outside the range of i16: -32.768 rpm..=32.767 rpm"
    );
    assert_eq!((all[1].0, all[1].1), (10, 10));
    let e = problem(&object("    max: 70000\n"));
    assert_eq!(at(&e), (7, 10));
    assert_says(&e, "outside the range of u16: 0..=65535");
}

#[test]
fn bad_scale_and_kinds_of_values() {
    let e = problem(&object("    scale: 0\n"));
    assert_eq!(at(&e), (7, 12));
    assert!(e.message().contains("greater than 0"));
    let e = problem(&object("").replace("index: 1", "index: abc"));
    assert_problem(
        &e,
        (4, 12),
        "`index` must be a whole number (decimal or 0x hex), found text",
    );
    let e = problem(&object("").replace("index: 1", "index: 0x10000"));
    assert_eq!(at(&e), (4, 12));
    assert_says(&e, "out of range 0..=65535");
    let e = problem(&object("    subindex: -1\n"));
    assert_eq!(at(&e), (7, 15));
    let e = problem(&object("    aliases: FOO\n"));
    assert_eq!(at(&e), (7, 14));
    assert!(e.message().starts_with("`aliases` must be a list"));
    let e = problem(&object("    aliases: [\"not ok\"]\n"));
    assert_eq!(at(&e), (7, 15));
    let e = problem(&object("    format: octal\n"));
    assert_eq!(at(&e), (7, 13));
}

#[test]
fn names_must_be_identifiers() {
    let e = problem(&object("").replace("name: a", "name: Speed"));
    assert_problem(&e, (3, 11), "`Speed` is not a valid object name");
    let e = problem(&object("").replace("family: sd2", "family: SD-2"));
    assert_eq!(at(&e), (1, 9));
}

#[test]
fn missing_required_keys() {
    let e = problem(&object("").replace("    index: 1\n", ""));
    assert_problem(&e, (3, 5), "an object has no `index` (or `address`)");
    assert!(e.help().unwrap_or("").contains("index: 395"));
    let e = problem("objects: []\n");
    assert_problem(&e, (1, 1), "the dictionary has no `family`");
    let e = problem(&object("").replace("index: 1", "index:"));
    assert_eq!(
        at(&e),
        (4, 5),
        "an empty value counts as missing, pointed at its key"
    );
}

#[test]
fn addresses_in_the_familys_notation() {
    let parse = |text: &str| {
        Dictionary::from_yaml_for("test.yaml", text, |t| {
            t.parse::<u16>()
                .map(|i| Address::indexed(i, 7))
                .map_err(|_| "a number".to_string().into())
        })
    };
    let d = parse(&object("").replace("    index: 1\n", "    address: \"12\"\n")).unwrap();
    assert_eq!(d.lookup("a").unwrap().address, Address::indexed(12, 7));
    let e = parse(&object("").replace("    index: 1\n", "    address: x1\n")).unwrap_err();
    let p = e.first();
    assert_eq!((p.line(), p.column()), (4, 14));
    assert_eq!(p.message(), "address `x1`: a number");
    // Without a family's notation an address cannot be read.
    let e = problem(&object("").replace("    index: 1\n", "    address: \"12\"\n"));
    assert_says(&e, "no address notation");
}

#[test]
fn string_objects_take_no_unit_or_limits() {
    let text = object("    unit: V\n    max: 3\n").replace("type: u16", "type: string(8)");
    let all = problems(&text);
    assert_eq!(
        all.iter().map(|p| (p.0, p.1)).collect::<Vec<_>>(),
        [(7, 5), (8, 5)]
    );
    assert_eq!(all[0].2, "a string object has no `unit`");
}

#[test]
fn unknown_keys_with_suggestions() {
    let e = problem(&object("    unti: rpm\n"));
    assert_problem(&e, (7, 5), "unknown key `unti` in an object");
    assert_eq!(e.help(), Some("did you mean `unit`?"));
    let e = problem(&format!("{}colour: red\n", object("")));
    assert_problem(&e, (7, 1), "unknown key `colour` in the dictionary");
}

#[test]
fn duplicate_names_and_aliases_name_both_places() {
    let text = "family: sd2\nobjects:\n  - name: a\n    aliases: [Alpha]\n    index: 1\n    type: u16\n    access: ro\n  - name: alpha\n    index: 2\n    type: u16\n    access: ro\n";
    let e = problem(text);
    assert_problem(
        &e,
        (8, 11),
        "`alpha` is the name of `alpha` and already an alias of `a`",
    );
    let out = rendered(&e);
    assert!(
        out.contains("first defined here") && out.contains("defined again here"),
        "{out}"
    );
    assert!(out.contains("Alpha"), "{out}");

    // Within one object a repeated spelling is harmless (the manual's `PARAMETER_SET`
    // for `parameter_set`): both find the same object.
    let text = "family: sd2\nobjects:\n  - name: a\n    aliases: [b, B, A]\n    index: 1\n    type: u16\n    access: ro\n";
    assert_eq!(parse(text).unwrap().lookup("B").unwrap().name, "a");
}

#[test]
fn duplicate_addresses() {
    let text = format!(
        "{}  - name: b\n    index: 1\n    type: u16\n    access: ro\n",
        object("")
    );
    let e = problem(&text);
    assert_problem(&e, (7, 5), "`b` has the same address as `a`: index 1 (0x0001)");
}

#[test]
fn yaml_syntax_errors_are_located() {
    let e = problem("family: sd2\nobjects: [\n  - name: a\n");
    assert!(e.line() >= 2, "{}", e.located());
    assert!(e.message().starts_with("not valid YAML"));
    let e = problem(&object("    unit: V\n    unit: A\n"));
    assert_eq!(e.line(), 8);
    assert_says(&e, "`unit` is written twice");
}

// ---- profile errors ----

#[test]
fn profile_role_naming_an_unknown_object() {
    let (text, e) = sd2_problem("  speed_actual: speed_actual\n", "  speed_actual: speed_actul\n");
    assert_problem(
        &e,
        pos(&text, "speed_actul"),
        "the profile's speed_actual is `speed_actul`, which is not an object of this dictionary",
    );
    assert_eq!(
        e.help(),
        Some("did you mean `speed_actual`, `speed_actual_2` or `speed_setpoint`?")
    );
}

#[test]
fn profile_role_of_the_wrong_type_or_access() {
    let (text, e) = sd2_problem("  status_word: status_word\n", "  status_word: ident\n");
    assert_problem(
        &e,
        pos(&text, "ident\n  speed_setpoint"),
        "the status word must be an integer, not string(32)",
    );
    let (text, e) = sd2_problem("  control_word: control_word\n", "  control_word: status_word\n");
    assert_problem(
        &e,
        pos(&text, "status_word\n  status_word"),
        "the control word is written by the engine, but `status_word` is read-only (ro)",
    );
    let (_, e) = sd2_problem("  status_word: status_word\n", "  status_word: speed_actual\n");
    assert_says(&e, "must be 8 or 16 bits wide");
}

#[test]
fn missing_command_and_state() {
    let text = SD2
        .replace("    fault_reset: 128\n", "")
        .replace("    fault:                  { mask: 0x4F, value: 0x08 }\n", "");
    let all = problems(&text);
    assert_eq!(all.len(), 2, "{all:#?}");
    assert_eq!((all[0].0, all[0].1), pos(&text, "shutdown: 6"));
    assert_eq!(all[0].2, "the commands has no `fault_reset`");
    assert_eq!((all[1].0, all[1].1), pos(&text, "not_ready_to_switch_on"));
    assert_eq!(all[1].2, "the states has no `fault`");
    let text = SD2.replace("  commands:\n", "  comands:\n");
    let all = problems(&text);
    assert!(
        all.iter().any(|p| p.2 == "unknown key `comands` in the profile"),
        "{all:#?}"
    );
    assert!(
        all.iter().any(|p| p.2 == "the profile has no `commands`"),
        "{all:#?}"
    );
}

#[test]
fn unknown_command_or_state_names() {
    let (text, e) = sd2_problem("    quick_stop: 2\n", "    quick_stop: 2\n    quickstop: 2\n");
    assert_eq!(at(&e), pos(&text, "quickstop"));
    assert_eq!(e.help(), Some("did you mean `quick_stop`?"));
    let (text, e) = sd2_problem(
        "    fault:  ",
        "    faulty: { mask: 0x4F, value: 0x08 }\n    fault:  ",
    );
    assert_eq!(at(&e), pos(&text, "faulty"));
}

#[test]
fn mask_zero_and_value_outside_the_mask() {
    let (text, e) = sd2_problem(
        "fault:                  { mask: 0x4F,",
        "fault:                  { mask: 0,",
    );
    let (line, column) = pos(&text, "mask: 0,");
    assert_eq!(at(&e), (line, column + 6), "points at the value");
    assert_eq!(
        e.message(),
        "the mask of `fault` is 0, so every status word would match it"
    );
    let (text, e) = sd2_problem(
        "switch_on_disabled:     { mask: 0x4F, value: 0x40 }",
        "switch_on_disabled:     { mask: 0x4F, value: 0x50 }",
    );
    assert_problem(&e, pos(&text, "0x50"), "value 0x50 of `switch_on_disabled` has bits outside its mask 0x4F (0x10), so no status word can match");
    let (text, e) = sd2_problem("    shutdown: 6\n", "    shutdown: 0x10000\n");
    assert_eq!(at(&e), pos(&text, "0x10000"));
}

#[test]
fn overlapping_states() {
    // quick stop active with mask 0x4F no longer looks at bit 5: it overlaps operation enabled.
    let (text, e) = sd2_problem(
        "quick_stop_active:      { mask: 0x6F,",
        "quick_stop_active:      { mask: 0x4F,",
    );
    let (line, _) = pos(&text, "quick_stop_active:");
    assert_problem(
        &e,
        (line, pos(&text, "{ mask: 0x4F, value: 0x07").1),
        "states `operation_enabled` and `quick_stop_active` overlap: status word 0x0027 matches both",
    );
}

#[test]
fn all_errors_of_a_file_are_collected() {
    let text = "family: sd2\nobjects:\n  - name: a\n    index: 1\n    type: u17\n    access: ro\n    unit: rpn\n  - name: b\n    index: 2\n    type: u16\n    access: rx\n";
    let all = problems(text);
    assert_eq!(
        all,
        [
            (5, 11, "unknown type `u17`".to_string()),
            (7, 11, "unknown unit `rpn`".to_string()),
            (11, 13, "unknown access `rx`".to_string()),
        ]
    );
    let e = parse(text).unwrap_err();
    assert_eq!(
        e.to_string(),
        "test.yaml:5:11: unknown type `u17` (and 2 more problems)"
    );
    let out = rendered(&e);
    assert!(
        out.contains("test.yaml:7:11") && out.contains("test.yaml:11:13"),
        "{out}"
    );
}

#[test]
fn a_broken_object_named_by_the_profile_is_reported_once() {
    let text = SD2.replace(
        "  - name: status_word\n    aliases: [DEV_CTRL_STATUS_WORD]\n    index: 67\n    type: u16",
        "  - name: status_word\n    aliases: [DEV_CTRL_STATUS_WORD]\n    index: 67\n    type: u61",
    );
    let all = problems(&text);
    assert_eq!(all.len(), 1, "{all:#?}");
    assert_eq!(all[0].2, "unknown type `u61`");
}

// ---- extend ----

#[test]
fn extend_adds_and_replaces() {
    let mut d = builtin();
    let user = parse(
        "family: sd2\nobjects:\n  - name: speed_setpoint\n    aliases: [SPG_TARGET_VELOCITY_VL_UUNIT]\n    index: 395\n    type: i32\n    unit: rpm\n    scale: 0.001\n    access: rw\n    min: -24000\n    max: 24000\n  - name: motor_temperature\n    index: 500\n    type: i16\n    access: ro\n",
    )
    .unwrap();
    d.extend(user).unwrap();
    let sp = d.lookup("speed_setpoint").unwrap();
    assert_eq!(sp.max, Some(24000.0));
    assert_eq!(sp.span.path(), "test.yaml");
    assert!(
        d.lookup("target_speed").is_err(),
        "the replacement's aliases replace the old ones"
    );
    assert_eq!(
        d.objects().position(|o| o.name == "speed_setpoint"),
        Some(7),
        "replaced in place"
    );
    assert_eq!(
        d.objects().last().map(|o| o.name.as_str()),
        Some("motor_temperature")
    );
    assert!(d.profile().is_some(), "the built-in profile stays");
    let e = sp.to_raw(&Quantity::parse("30000 rpm").unwrap()).unwrap_err();
    assert!(e.to_string().contains("maximum of speed_setpoint, 24000 rpm"));
}

#[test]
fn extend_refuses_clashes_and_leaves_the_dictionary_unchanged() {
    let mut d = builtin();
    let text = "family: sd2\nobjects:\n  - name: my_speed\n    aliases: [target_speed]\n    index: 600\n    type: i32\n    access: rw\n";
    let e = d.extend(parse(text).unwrap()).unwrap_err().first().clone();
    assert_eq!(
        (e.path(), e.line(), e.column()),
        ("test.yaml", 4, 15),
        "points into the user's file"
    );
    assert_eq!(
        e.message(),
        "`target_speed` is an alias of `my_speed` and already an alias of `speed_setpoint`"
    );
    assert!(
        e.help()
            .unwrap_or("")
            .contains("first defined here: dictionary/sd2.yaml:"),
        "{:?}",
        e.help()
    );
    assert!(d.lookup("my_speed").is_err());

    let text = "family: sd2\nobjects:\n  - name: speed_copy\n    index: 395\n    type: i32\n    access: rw\n";
    let e = d.extend(parse(text).unwrap()).unwrap_err().first().clone();
    assert_eq!((e.line(), e.column()), (3, 5));

    // Replacing the status word by a string breaks the profile: re-validated.
    let text =
        "family: sd2\nobjects:\n  - name: status_word\n    index: 67\n    type: string(8)\n    access: ro\n";
    let e = d.extend(parse(text).unwrap()).unwrap_err().first().clone();
    assert_says(&e, "status word must be an integer");
    assert_eq!(d.lookup("status_word").unwrap().data_type, DataType::U16);

    let text = "family: lenze\nobjects: []\n";
    let e = d.extend(parse(text).unwrap()).unwrap_err().first().clone();
    assert_eq!((e.line(), e.column()), (1, 9));
}

#[test]
fn extend_from_a_file_whose_profile_names_builtin_objects() {
    let dir = std::env::temp_dir().join(format!("drivescript-dict-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("user.yaml");
    let profile = &SD2[SD2.find("profile:").unwrap()..]
        .replace("speed_actual: speed_actual", "speed_actual: speed_actual_2");
    std::fs::write(&path, format!("family: sd2\nobjects: []\n{profile}")).unwrap();
    let mut d = builtin();
    assert!(
        Dictionary::load(&path).is_err(),
        "alone, its profile names objects it lacks"
    );
    d.extend_from(&path).unwrap();
    assert_eq!(
        d.role(Role::SpeedActual).map(|o| o.name.as_str()),
        Some("speed_actual_2")
    );
    let e = Dictionary::load(dir.join("missing.yaml"))
        .unwrap_err()
        .first()
        .clone();
    assert!(
        e.message().starts_with("cannot read the dictionary file"),
        "{}",
        e.message()
    );
    assert_eq!(e.line(), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn problems_of_broken_objects_are_all_reported_too() {
    // Object b is unusable (bad access), yet its alias clash and its limits are reported.
    let text = "family: sd2\nobjects:\n  - name: a\n    aliases: [target]\n    index: 1\n    type: u17\n    access: ro\n    unit: rpn\n    unti: x\n  - name: b\n    aliases: [Target]\n    index: 2\n    type: u16\n    access: rx\n    min: 5\n    max: 1\n";
    let all = problems(text);
    let places: Vec<(usize, usize)> = all.iter().map(|p| (p.0, p.1)).collect();
    assert_eq!(
        places,
        [(6, 11), (8, 11), (9, 5), (11, 15), (14, 13), (15, 10)],
        "{all:#?}"
    );
    assert_eq!(
        all[3].2,
        "`Target` is an alias of `b` and already an alias of `a`"
    );
    assert_eq!(all[5].2, "`min` 5 is greater than `max` 1");
}

// ---- issue 9: profiles whose stops keep the drive running; non-finite numbers ----

#[test]
fn stop_commands_that_keep_the_drive_enabled_are_refused() {
    let (text, e) = sd2_problem("disable_operation: 7", "disable_operation: 15");
    assert_problem(&e, pos(&text, "15\n    enable_operation"), "`disable_operation` 15 (0x000F) keeps every bit of `enable_operation` 15 (0x000F): this stop command would leave the drive enabled");
    assert_eq!(e.label(), "keeps the drive running");
    assert!(e.help().unwrap_or("").contains("disable_operation is 7"), "{e:?}");

    // Shutdown keeping switch_on, quick stop keeping enable_operation (extra bits or not).
    let text = SD2
        .replace("shutdown: 6", "shutdown: 0x87")
        .replace("quick_stop: 2", "quick_stop: 0x10F");
    let all = problems(&text);
    assert_eq!(all.len(), 2, "{all:#?}");
    assert!(
        all[0]
            .2
            .starts_with("`shutdown` 135 (0x0087) keeps every bit of `switch_on` 7"),
        "{all:#?}"
    );
    assert!(
        all[0].2.ends_with("would leave the drive switched on"),
        "{all:#?}"
    );
    assert!(
        all[1]
            .2
            .starts_with("`quick_stop` 271 (0x010F) keeps every bit of `enable_operation`"),
        "{all:#?}"
    );

    let (_, e) = sd2_problem("enable_operation: 15", "enable_operation: 0");
    assert!(
        e.message().starts_with("`enable_operation` is 0"),
        "{}",
        e.message()
    );
}

#[test]
fn a_user_profile_cannot_make_the_stops_keep_the_drive_enabled() {
    let profile = &SD2[SD2.find("profile:").unwrap()..].replace("disable_voltage: 0", "disable_voltage: 15");
    let user = parse(&format!("family: sd2\nobjects: []\n{profile}"));
    let e = user
        .expect_err("refused when read, before merging")
        .first()
        .clone();
    assert!(
        e.message()
            .starts_with("`disable_voltage` 15 (0x000F) keeps every bit"),
        "{}",
        e.message()
    );
}

#[test]
fn limits_that_are_not_finite_are_refused_as_written() {
    for (written, value) in [(".inf", ".inf"), ("1e400", "1e400"), (".nan", ".nan")] {
        let text = object(&format!("    max: {written}\n"));
        let e = problem(&text);
        assert_eq!(
            e.message(),
            format!("`max` must be a finite number, not `{value}`")
        );
        assert_eq!(at(&e), pos(&text, written));
    }
}
