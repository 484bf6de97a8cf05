//! Inverter units as engineers use them: Hz and rpm both accepted for a Modbus inverter's
//! frequency setpoint where the dictionary knows the motor's pole pairs (its own
//! `pole_pairs:`, `--link-option pole-pairs=N`, a recipe's `link: { pole_pairs: N }`), a
//! hint where it does not, and every shipped inverter dictionary's setpoint range
//! refusing what no inverter of its kind reaches. Through the binary, against the
//! built-in simulated inverter.

use crate::support::{assert_has, assert_lacks, check_file, cli, scratch, scratch_file, words, write_file};
use std::path::Path;

const AT_100_HZ: &str = "name: Spindle at 100 Hz
drive: sunfar-e500
steps:
  - set: { speed_setpoint: 100 Hz }
  - read: speed_setpoint
  - go_to: { state: operation_enabled, timeout: 2 s }
  - wait_until: { speed_actual: { near: 100 Hz, within: 1 % }, timeout: 20 s }
";

/// `check` refuses `text`, written as `file` in `dir`, with exit code 2, saying each of
/// `parts`.
#[track_caller]
fn refused_by_check(dir: &Path, file: &str, text: &str, parts: &[&str]) {
    assert_has(&check_file(dir, file, text, 2).stderr, parts);
}

#[test]
fn a_recipe_with_two_pole_pairs_in_its_link_sets_100_hz_as_3000_rpm() {
    let dir = scratch("inverter-100hz-link");
    let text = AT_100_HZ.replace("steps:", "link: { pole_pairs: 2 }\nsteps:");
    let recipe = write_file(&dir, "hz.yaml", &text);
    let out = cli(&["check", recipe.to_str().unwrap()], 0);
    assert_lacks(&out.stderr, &["pole pairs"]);
    let out = cli(&["run", recipe.to_str().unwrap(), "--fast"], 0).stdout;
    // 100 Hz × 60 / 2 = 3000 rpm: 1000 counts of 0.1 Hz, which read back as 3000 rpm.
    assert_has(
        &out,
        &[
            "set speed_setpoint = 3000 rpm  written",
            "read speed_setpoint  speed_setpoint = 3000 rpm",
            "wait until speed_actual near 3000 rpm ± 1 %",
            "PASSED",
        ],
    );
}

#[test]
fn the_link_option_overrides_the_dictionarys_pole_pairs() {
    let (dir, recipe) = scratch_file("inverter-100hz-option", "hz.yaml", AT_100_HZ);
    let path = recipe.to_str().unwrap();
    // The dictionary's own: one pole pair, 100 Hz is 6000 rpm.
    let out = cli(&["run", path, "--fast"], 0).stdout;
    assert_has(&out, &["set speed_setpoint = 6000 rpm  written", "PASSED"]);
    // Two from the command line: the same register holds 3000 rpm.
    let out = cli(&["run", path, "--fast", "--link-option", "pole-pairs=2"], 0).stdout;
    assert_has(&out, &["set speed_setpoint = 3000 rpm  written", "PASSED"]);
    // The command line wins over the recipe's link.
    let linked = write_file(
        &dir,
        "linked.yaml",
        &AT_100_HZ.replace("steps:", "link: { pole_pairs: 4 }\nsteps:"),
    );
    let args = [
        "run",
        linked.to_str().unwrap(),
        "--fast",
        "--link-option",
        "pole_pairs=2",
    ];
    assert_has(&cli(&args, 0).stdout, &["set speed_setpoint = 3000 rpm"]);
    // The limits follow: 400 Hz is 12 000 rpm for a 4-pole motor.
    let out = cli(
        &words("objects --drive sunfar-e500 --link-option pole-pairs=2"),
        0,
    )
    .stdout;
    assert_has(
        &out,
        &[
            "rpm are for a motor with 2 pole pair(s) (--link-option pole-pairs=2)",
            "0 .. 12000",
        ],
    );
    let out = cli(&["objects", "--drive", "sunfar-e500"], 0).stdout;
    assert_has(
        &out,
        &["1 pole pair(s) (the dictionary sunfar-e500)", "0 .. 24000"],
    );
}

#[test]
fn bad_pole_pairs_are_refused_before_anything_is_sent() {
    let (_, recipe) = scratch_file("inverter-bad-pole-pairs", "hz.yaml", AT_100_HZ);
    let path = recipe.to_str().unwrap();
    let out = cli(&["check", path, "--link-option", "pole-pairs=0"], 2);
    assert_has(
        &out.stderr,
        &["--link-option pole-pairs=0", "not a number of pole pairs"],
    );
    // A servo's dictionary has no output frequency the pole pairs could rescale.
    let out = cli(&["objects", "--drive", "sd2", "--link-option", "pole-pairs=2"], 2);
    assert_has(&out.stderr, &["the sd2 dictionary gives no `pole_pairs`"]);
}

#[test]
fn hz_where_the_pole_pairs_are_unknown_gets_a_hint() {
    let dir = scratch("inverter-hz-hint");
    refused_by_check(
        &dir,
        "sd2.yaml",
        "name: Hz on a servo\ndrive: sd2\nsteps:\n  - set: { speed_setpoint: 100 Hz }\n",
        &[
            "the dictionary does not say the motor's pole pairs",
            "give `pole_pairs: N` in the",
            "rpm = Hz × 60 / pole pairs",
        ],
    );
    refused_by_check(
        &dir,
        "sd2.rhai",
        "//! drive: sd2\nlet d = drive();\nd.set(\"speed_setpoint\", 50.0, \"Hz\");\nlet f = d.read_as(\"speed_actual\", \"Hz\");\n",
        &["does not say the motor's pole pairs", "2 problems found"],
    );
    let out = cli(&["write", "speed_setpoint", "100", "Hz"], 2);
    assert_has(
        &out.stderr,
        &["does not say the motor's pole pairs", "nothing was sent"],
    );
    let out = cli(&["read", "speed_actual", "--in", "Hz"], 2);
    assert_has(
        &out.stderr,
        &["--in: Hz is not a unit of speed_actual", "pole pairs"],
    );
}

#[test]
fn every_shipped_inverter_dictionary_refuses_300_000_rpm_in_check() {
    let dir = scratch("inverter-too-fast");
    for drive in ["sunfar-e500", "modbus-inverter", "modbus-tcp-inverter"] {
        refused_by_check(
            &dir,
            &format!("{drive}.yaml"),
            &format!("name: Too fast\ndrive: {drive}\nsteps:\n  - set: {{ speed_setpoint: 300000 rpm }}\n"),
            &["300000 rpm is above the maximum of speed_setpoint, 24000 rpm"],
        );
        // In Hz too: 5000 Hz is beyond the same 400 Hz.
        refused_by_check(
            &dir,
            &format!("{drive}-hz.yaml"),
            &format!("name: Too fast\ndrive: {drive}\nsteps:\n  - set: {{ speed_setpoint: 5000 Hz }}\n"),
            &["5000 Hz (300000 rpm) is above the maximum"],
        );
    }
}

#[test]
fn a_script_and_read_give_a_value_in_hz_where_the_pole_pairs_are_known() {
    let (_, script) = scratch_file(
        "inverter-hz-script",
        "hz.rhai",
        "//! drive: sunfar-e500
let d = drive();
d.set(\"speed_setpoint\", 50.0, \"Hz\");
d.go_to(\"operation_enabled\");
d.wait_until(\"speed_actual\", |v| v >= 1500.0, \"20 s\");
print(`at ${d.read_as(\"speed_actual\", \"Hz\")} Hz`);
",
    );
    let args = [
        "run",
        script.to_str().unwrap(),
        "--fast",
        "--drive",
        "sunfar-e500",
        "--link-option",
        "pole-pairs=2",
    ];
    let out = cli(&args, 0).stdout;
    // 50 Hz with two pole pairs is 1500 rpm, read back as 50 Hz.
    assert_has(&out, &["set speed_setpoint = 1500 rpm", "at 50.0 Hz", "PASSED"]);
    let out = cli(
        &words("read speed_setpoint --drive sunfar-e500 --in Hz --json"),
        0,
    )
    .stdout;
    assert_has(&out, &[r#""in":{"value":0.0,"unit":"Hz"}"#]);
}

/// The editor's schema lists Hz among an inverter's speed units (its dictionary knows the
/// pole pairs), and only rpm and krpm for a servo's.
#[test]
fn the_schema_offers_hz_for_an_inverters_speed_only() {
    let pattern = |drive: &str| {
        let out = cli(&["schema", "--drive", drive], 0).stdout;
        let schema: serde_json::Value = serde_json::from_str(&out).expect("JSON");
        let set = &schema["$defs"]["step"]["else"]["oneOf"][1]["properties"]["set"]["properties"];
        let key = set["speed_setpoint"]["$ref"].as_str().expect("$ref").to_string();
        let def = key.trim_start_matches("#/$defs/");
        (
            def.to_string(),
            schema["$defs"][def]["pattern"]
                .as_str()
                .unwrap_or_default()
                .to_string(),
        )
    };
    for drive in ["sunfar-e500", "modbus-inverter", "modbus-tcp-inverter"] {
        let (def, pattern) = pattern(drive);
        assert_eq!(def, "value_speed_or_frequency", "{drive}");
        assert_has(&pattern, &["[rR][pP][mM]", "[hH][zZ]"]);
    }
    let (def, pattern) = pattern("sd2");
    assert_eq!(def, "value_speed");
    assert_lacks(&pattern, &["[hH][zZ]"]);
}

/// A named drive's own `pole_pairs:` (its `drives:` declaration) sets that inverter's
/// motor alone; `--link-option pole-pairs=N` wins over it; a bad one is refused.
#[test]
fn a_drive_declaration_gives_its_own_motors_pole_pairs() {
    let dir = scratch("inverter-drive-decl");
    let text = "name: Two spindles
drives:
  a: { drive: sunfar-e500, address: 1 }
  b: { drive: sunfar-e500, address: 2, pole_pairs: 2 }
steps:
  - set: { a.speed_setpoint: 100 Hz, b.speed_setpoint: 100 Hz }
  - read: [a.speed_setpoint, b.speed_setpoint]
";
    let recipe = write_file(&dir, "two.yaml", text);
    let path = recipe.to_str().unwrap();
    let out = cli(&["run", path, "--fast"], 0).stdout;
    assert_has(
        &out,
        &[
            "a.speed_setpoint = 6000 rpm, b.speed_setpoint = 3000 rpm",
            "PASSED",
        ],
    );
    let out = cli(&["run", path, "--fast", "--link-option", "pole-pairs=4"], 0).stdout;
    assert_has(
        &out,
        &["a.speed_setpoint = 1500 rpm, b.speed_setpoint = 1500 rpm"],
    );
    let out = check_file(
        &dir,
        "bad.yaml",
        &text.replace("pole_pairs: 2", "pole_pairs: zero"),
        2,
    );
    assert_has(
        &out.stderr,
        &["drive `b`", "`zero` is not a number of pole pairs"],
    );
}

/// A trace records the pole pairs the run's rpm were shown for, so `decode` of it shows
/// the same rpm as the run did, and it replays to the same verdict.
#[test]
fn a_trace_keeps_the_pole_pairs_for_decode_and_replay() {
    let (dir, recipe) = scratch_file("inverter-trace", "hz.yaml", AT_100_HZ);
    let trace = dir.join("run.log");
    let (path, log) = (recipe.to_str().unwrap(), trace.to_str().unwrap());
    let args = [
        "run",
        path,
        "--fast",
        "--link-option",
        "pole-pairs=2",
        "--trace",
        log,
    ];
    cli(&args, 0);
    let text = std::fs::read_to_string(&trace).unwrap();
    assert_has(&text, &["# pole pairs: 2", "speed_setpoint = 3000 rpm"]);
    let out = cli(&["decode", log], 0).stdout;
    assert_has(&out, &["write single register: speed_setpoint = 3000 rpm"]);
    assert_lacks(&out, &["6000 rpm"]);
    let out = cli(
        &["run", path, "--replay", log, "--link-option", "pole-pairs=2"],
        0,
    )
    .stdout;
    assert_has(&out, &["set speed_setpoint = 3000 rpm", "PASSED"]);
}
