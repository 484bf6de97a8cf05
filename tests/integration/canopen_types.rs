//! The wider CiA 301 data types end to end on the simulated CiA 402 node in virtual time:
//! a REAL32, a 24-bit and a 48-bit integer and an OCTET_STRING read, written with the
//! exact bytes on the bus and read back; a float the node holds as NaN; a DOMAIN bigger
//! than a transfer refused; a DCF of such values diffed and restored; `decode` of an SDO
//! telegram carrying a REAL32.

use crate::support::{assert_has, assert_lacks, cli, repo_root, scratch_file, write_file, Ran};

/// drivescript's subcommand `args[0]` on `--drive canopen` with the simulated node's own
/// EDS as the dictionary, then the rest of `args` (a negative value after `--`), exiting
/// `code`.
pub fn on_node(args: &[&str], code: i32) -> Ran {
    let eds = repo_root().join("src/family/canopen/sim/cia402_node.eds");
    on_dictionary(&eds.to_string_lossy(), args, code)
}

/// [`on_node`] with the DCF `file` (under `tests/eds/`) as the dictionary and as the
/// parameter set the subcommand (`diff`, `restore`) takes.
pub fn on_dcf(file: &str, args: &[&str], code: i32) -> Ran {
    let dcf = repo_root().join("tests/eds").join(file);
    let dcf = dcf.to_string_lossy();
    let mut all = vec![args[0], &dcf];
    all.extend(&args[1..]);
    on_dictionary(&dcf, &all, code)
}

/// `diff` of the DCF `file` with the node finds differences (exit code 1) and shows every
/// one of `differences`; `restore --apply` then succeeds showing every one of `restored`
/// and none of `untouched` (what the node already holds as the DCF says).
pub fn dcf_diffed_and_restored(file: &str, differences: &[&str], restored: &[&str], untouched: &[&str]) {
    assert_has(&on_dcf(file, &["diff"], 1).stdout, differences);
    let out = on_dcf(file, &["restore", "--apply"], 0);
    assert_has(&out.stdout, restored);
    assert_lacks(&out.stdout, untouched);
}

fn on_dictionary(dictionary: &str, args: &[&str], code: i32) -> Ran {
    let mut all = vec![args[0], "--drive", "canopen", "--dictionary", dictionary];
    all.extend(&args[1..]);
    cli(&all, code)
}

#[test]
fn floats_odd_width_integers_and_octets_are_read_and_written_with_their_exact_bytes() {
    let (dir, recipe) = scratch_file(
        "canopen-types",
        "types.yaml",
        r#"name: Wider types
drive: canopen
steps:
  - read: [velocity_loop_gain, encoder_scale, position_offset, operating_time, option_key, motor_label, event_log]
  - set: { velocity_loop_gain: 2.75, encoder_scale: 0.125, position_offset: -99999, operating_time: 281474976710655 }
  - set: { option_key: "00 11 22 33 44 55 66 77 88" }
  - expect: { velocity_loop_gain: { equals: 2.75 } }
  - expect: { encoder_scale: { equals: 0.125 } }
  - expect: { position_offset: { equals: -99999 } }
  - expect: { operating_time: { equals: 281474976710655 } }
  - expect: { option_key: { equals: "00 11 22 33 44 55 66 77 88" } }
  # The same bytes however they are written, as `set` takes them: as a DCF writes them.
  - set: { option_key: "ca fe" }
  - expect: { option_key: { equals: "CAFE" } }
"#,
    );
    let trace = dir.join("run.log");
    let trace_arg = trace.to_string_lossy().to_string();
    let out = on_node(
        &["run", &recipe.to_string_lossy(), "--fast", "--trace", &trace_arg],
        0,
    );
    assert_has(
        &out.stdout,
        &[
            "velocity_loop_gain = 1.5",
            "encoder_scale = 0.1",
            "position_offset = -2",
            "operating_time = 20015998343868",
            "option_key = 01 02 a0 ff",
            "motor_label = \"Motor A\"",
            "event_log = de ad be ef 00 01 02 03",
            "PASSED",
        ],
    );
    let trace = std::fs::read_to_string(&trace).expect("trace");
    assert_has(
        &trace,
        &[
            // 2.75 as a REAL32: 0x40300000, little-endian, expedited with 4 bytes.
            "601#2300210000003040",
            // 0.125 as a REAL64 goes in segments: 8 bytes, then 7 and 1.
            "601#2101210008000000",
            "601#00000000000000C0",
            "601#1D3F000000000000",
            // -99999 in 24 bits: 61 79 fe, expedited with 3 bytes.
            "601#270221006179FE00",
            // 2^48 − 1 in 48 bits: 6 bytes in one last segment.
            "601#2103210006000000",
            "601#03FFFFFFFFFFFF00",
            // Nine bytes of the key: 7, then 2.
            "601#2104210009000000",
        ],
    );
}

#[test]
fn a_nan_is_shown_as_such_and_a_domain_beyond_a_transfer_is_refused() {
    let out = on_node(&["read", "torque_constant"], 0);
    assert_has(&out.stdout, &["torque_constant", "NaN", "0x2106"]);
    let (dir, recipe) = scratch_file(
        "canopen-nan",
        "nan.yaml",
        "name: NaN\ndrive: canopen\nsteps:\n  - expect: { torque_constant: { below: 1000 } }\n",
    );
    let out = on_node(&["run", &recipe.to_string_lossy(), "--fast"], 1);
    assert_has(&out.stdout, &["NaN", "FAILED"]);
    let out = on_node(&["read", "trace_buffer"], 3);
    assert_has(
        &out.stderr,
        &["the node announces 4096 bytes; drivescript takes at most 256"],
    );
    // The node's answer, not noise on the line: refused at once, not tried again.
    assert_lacks(&out.stderr, &["noise", "attempt(s)"]);
    // Never written, saying why.
    let out = on_node(&["write", "event_log", "00"], 2);
    assert_has(&out.stderr, &["event_log is read-only"]);
    // Bytes to compare with are hex, checked before anything is sent.
    let recipe = write_file(
        &dir,
        "octets.yaml",
        "name: Octets\ndrive: canopen\nsteps:\n  - expect: { option_key: { equals: \"ca fz\" } }\n",
    );
    let out = on_node(&["check", &recipe.to_string_lossy()], 2);
    assert_has(&out.stderr, &["option_key holds bytes", "octets.yaml:4:"]);
}

#[test]
fn a_dcf_of_floats_and_wide_integers_is_diffed_and_restored() {
    dcf_diffed_and_restored(
        "cia402-wide-types.dcf",
        &[
            "velocity_loop_gain",
            "27",
            "1.5",
            "operating_time",
            "281474976710655",
            "option_key",
            "ca fe",
            "3 difference(s)",
        ],
        &["velocity_loop_gain", "operating_time", "option_key"],
        &["encoder_scale", "position_offset"],
    );
}

#[test]
fn decode_shows_a_real32_telegram_as_its_float() {
    let out = on_node(&["decode", "601#2300210000002040", "601#27022100FEFFFF00"], 0);
    assert_has(
        &out.stdout,
        &[
            "write index 0x2100/0 velocity_loop_gain = 2.5 → node 1",
            "write index 0x2102/0 position_offset = -2 → node 1",
        ],
    );
}
