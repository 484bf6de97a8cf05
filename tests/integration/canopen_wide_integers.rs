//! Integers wider than a float's 53 bits end to end on the simulated CiA 402 node, through
//! the binary: its 64- and 56-bit vendor objects read, written with their exact SDO bytes,
//! compared with `equals`, refused one count beyond their type, backed up, diffed and
//! restored, a DCF of them diffed and restored, and `decode` of their segments.

use crate::canopen_types::{dcf_diffed_and_restored, on_node};
use crate::support::{assert_has, assert_in_order, assert_lacks, cli, scratch, scratch_file, write_file};

/// 2^63 − 1, 2^53 + 1, −2^55 and 2^56 − 1 written by a recipe, with the exact bytes on the
/// bus, read back and compared exactly; `decode` of the trace shows each whole value.
#[test]
fn wide_integers_are_written_and_read_back_to_the_unit() {
    let (dir, recipe) = scratch_file(
        "canopen-wide-integers",
        "wide.yaml",
        r#"name: Wide integers
drive: canopen
steps:
  - read: [lifetime_revolutions, position_counter, energy_counter]
  - set: { lifetime_revolutions: 9223372036854775807, position_counter: 9007199254740993 }
  - set: { encoder_offset: -36028797018963968, energy_counter: 72057594037927935 }
  - read: [lifetime_revolutions, position_counter, encoder_offset, energy_counter]
  - expect: { lifetime_revolutions: { equals: 9223372036854775807 } }
  - expect: { position_counter: { equals: 9007199254740993 } }
  - expect: { encoder_offset: { equals: -36028797018963968 } }
  - expect: { energy_counter: { equals: 72057594037927935 } }
"#,
    );
    let trace = dir.join("run.log");
    let junit = dir.join("junit.xml");
    let out = on_node(
        &[
            "run",
            recipe.to_str().unwrap(),
            "--fast",
            "--trace",
            trace.to_str().unwrap(),
            "--junit",
            junit.to_str().unwrap(),
        ],
        0,
    );
    assert_in_order(
        &out.stdout,
        &[
            // The node's defaults, beyond 2^53.
            "lifetime_revolutions = 81985529216486895, position_counter = -9007199254740993, energy_counter = 71737338064426034",
            "set lifetime_revolutions = 9223372036854775807, position_counter = 9007199254740993",
            "set encoder_offset = -36028797018963968, energy_counter = 72057594037927935",
            "lifetime_revolutions = 9223372036854775807, position_counter = 9007199254740993, encoder_offset = -36028797018963968, energy_counter = 72057594037927935",
            "PASS  lifetime_revolutions equals 9223372036854775807: lifetime_revolutions = 9223372036854775807",
            "PASS  position_counter equals 9007199254740993: position_counter = 9007199254740993",
            "PASS  encoder_offset equals -36028797018963968",
            "PASS  energy_counter equals 72057594037927935",
            "PASSED",
        ],
    );
    // No float near the value is shown as what was expected or measured.
    assert_lacks(
        &out.stdout,
        &["9223372036854775808", "9007199254740992", "72057594037927936"],
    );
    let junit = std::fs::read_to_string(&junit).expect("junit");
    assert_has(
        &junit,
        &["measured: 9223372036854775807", "measured: 9007199254740993"],
    );
    assert_lacks(&junit, &["9223372036854775808", "9007199254740992"]);
    let log = std::fs::read_to_string(&trace).expect("trace");
    assert_in_order(
        &log,
        &[
            // 2^63 − 1 as UNSIGNED64: 8 bytes announced, then 7 and 1 in segments.
            "601#2107210008000000",
            "601#00FFFFFFFFFFFFFF",
            "601#1D7F000000000000",
            // 2^53 + 1 as INTEGER64: 01 00 00 00 00 00 20 00.
            "601#2108210008000000",
            "601#0001000000000020",
            "601#1D00000000000000",
            // −2^55 as INTEGER56: 7 bytes, the last segment at once.
            "601#2109210007000000",
            "601#0100000000000080",
            // 2^56 − 1 as UNSIGNED56.
            "601#210A210007000000",
            "601#01FFFFFFFFFFFFFF",
            // Read back: the node's segments carry the same bytes.
            "601#4007210000000000",
            "581#00FFFFFFFFFFFFFF",
            "581#1D7F000000000000",
        ],
    );
    let decoded = cli(&["decode", trace.to_str().unwrap()], 0).stdout;
    assert_has(
        &decoded,
        &[
            "last of index 0x2107/0 lifetime_revolutions = 9223372036854775807 → node 1",
            "last of index 0x2108/0 position_counter = 9007199254740993 → node 1",
            "last of index 0x2109/0 encoder_offset = -36028797018963968 → node 1",
            "last of index 0x210A/0 energy_counter = 72057594037927935 → node 1",
            "last of index 0x2107/0 lifetime_revolutions = 9223372036854775807 ← node 1",
        ],
    );
}

/// `equals` tells 2^53 + 1 from 2^53, which a float cannot.
#[test]
fn equals_tells_apart_what_a_float_cannot() {
    let (dir, recipe) = scratch_file(
        "canopen-wide-equals",
        "equals.yaml",
        "name: One count\ndrive: canopen\nsteps:\n  - set: { position_counter: 9007199254740993 }\n  - expect: { position_counter: { equals: 9007199254740992 } }\n",
    );
    let out = on_node(&["run", recipe.to_str().unwrap(), "--fast"], 1);
    assert_has(
        &out.stdout,
        &["FAIL  position_counter equals 9007199254740992: position_counter = 9007199254740993, expected equals 9007199254740992"],
    );
    // A value beyond the type is refused where it is written, before anything is sent.
    let recipe = write_file(
        &dir,
        "beyond.yaml",
        "name: Beyond\ndrive: canopen\nsteps:\n  - set: { position_counter: -9223372036854775809, energy_counter: 72057594037927936 }\n",
    );
    let out = on_node(&["check", recipe.to_str().unwrap()], 2);
    assert_has(
        &out.stderr,
        &[
            "-9223372036854775809 is -9223372036854775809 counts, outside the range of position_counter's type i64: -9223372036854775808..=9223372036854775807",
            "72057594037927936 is 72057594037927936 counts, outside the range of energy_counter's type u56: 0..=72057594037927935",
        ],
    );
}

/// One-off `write` and `read` at both ends of each type, and one count beyond refused
/// before anything is sent.
#[test]
fn one_off_writes_are_exact_at_both_ends() {
    for (name, value) in [
        ("lifetime_revolutions", "9223372036854775807"),
        ("lifetime_revolutions", "9007199254740993"),
        ("position_counter", "-9223372036854775808"),
        ("encoder_offset", "-36028797018963968"),
        ("energy_counter", "72057594037927935"),
    ] {
        let out = on_node(&["write", name, "--", value], 0);
        assert_has(&out.stdout, &[&format!("{name} = {value} written (raw {value})")]);
    }
    for (name, value, range) in [
        (
            "lifetime_revolutions",
            "9223372036854775808",
            "u64: 0..=9223372036854775807",
        ),
        (
            "position_counter",
            "-9223372036854775809",
            "i64: -9223372036854775808..=9223372036854775807",
        ),
        (
            "encoder_offset",
            "-36028797018963969",
            "i56: -36028797018963968..=36028797018963967",
        ),
        (
            "energy_counter",
            "72057594037927936",
            "u56: 0..=72057594037927935",
        ),
    ] {
        let out = on_node(&["write", name, "--", value], 2);
        assert_has(
            &out.stderr,
            &[&format!(
                "{value} is {value} counts, outside the range of {name}'s type {range}; nothing was sent"
            )],
        );
    }
    let out = on_node(&["read", "lifetime_revolutions", "energy_counter", "--json"], 0);
    let json: serde_json::Value = serde_json::from_str(out.stdout.trim()).expect("json");
    assert_eq!(json[0]["value"].as_i64(), Some(81_985_529_216_486_895));
    assert_eq!(json[1]["value"].as_i64(), Some(71_737_338_064_426_034));
    assert_eq!(json[0]["raw"], "81985529216486895");
}

/// A backup keeps each count exactly: one count apart is a difference, and the restore
/// writes that count and reads it back.
#[test]
fn backups_of_wide_integers_differ_and_restore_by_one_count() {
    let dir = scratch("canopen-wide-backup");
    let backup = dir.join("node.yaml");
    let backup_arg = backup.to_str().unwrap();
    on_node(&["backup", "-o", backup_arg], 0);
    let text = std::fs::read_to_string(&backup).expect("backup");
    assert_has(
        &text,
        &[
            "\"81985529216486895\"",
            "\"-9007199254740993\"",
            "\"71737338064426034\"",
        ],
    );
    std::fs::write(&backup, text.replace("81985529216486895", "81985529216486894")).expect("edited");
    let out = on_node(&["diff", backup_arg], 1);
    assert_has(
        &out.stdout,
        &[
            "lifetime_revolutions",
            "81985529216486894",
            "81985529216486895",
            "1 difference(s)",
        ],
    );
    let out = on_node(&["restore", backup_arg, "--apply"], 0);
    assert_has(
        &out.stdout,
        &[
            "lifetime_revolutions: 81985529216486895 → 81985529216486894",
            "wrote lifetime_revolutions = 81985529216486894",
            "restored 1 parameter(s)",
        ],
    );
}

/// A DCF's ParameterValues of wide integers (decimal and hex) are compared with the node
/// to the unit and restored.
#[test]
fn a_dcf_of_wide_integers_is_diffed_and_restored_exactly() {
    dcf_diffed_and_restored(
        "cia402-wide-integers.dcf",
        &[
            "lifetime_revolutions",
            "81985529216486894",
            "position_counter",
            "-9223372036854775808",
            "encoder_offset",
            "-36028797018963968",
            "energy_counter",
            "72057594037927935",
            "4 difference(s)",
        ],
        &[
            "wrote lifetime_revolutions = 81985529216486894",
            "wrote position_counter = -9223372036854775808",
            "wrote encoder_offset = -36028797018963968",
            "wrote energy_counter = 72057594037927935",
            "restored 4 parameter(s)",
        ],
        &[],
    );
}
