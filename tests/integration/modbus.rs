//! The Modbus families end to end: the commissioning recipe with only `drive:` changed
//! through a pseudo-terminal (and its trace read back by `decode`), two inverters on one
//! RS485 line, Ctrl-C with the stop code asserted, backup/diff/restore, Modbus TCP, and
//! `decode` of the frames printed in the Sunfar E500 manual. The endings in virtual time
//! (lost line, disobedient drive, fault) are recipe cases under tests/cases/ (`modbus_*`).

use crate::live_run::ctrl_c_during_a_dwell;
use crate::support::{assert_has, check_file, cli, drivescript, repo_root, scratch, write_file, Simulator};
use std::path::PathBuf;
use std::time::Duration;

/// recipes/commissioning.yaml with only `drive:` changed, in `dir`.
fn commissioning(dir: &std::path::Path, drive: &str) -> PathBuf {
    let text = std::fs::read_to_string(repo_root().join("recipes/commissioning.yaml")).unwrap();
    assert!(text.contains("\ndrive: sd2\n"));
    write_file(
        dir,
        "commissioning.yaml",
        &text.replace("\ndrive: sd2\n", &format!("\ndrive: {drive}\n")),
    )
}

/// The commissioning recipe on the simulated Modbus inverter served by `simulate --pty`
/// with `sim_args`, run with `--set speed=SPEED` and a trace, which must pass: its output,
/// the trace file and the simulator's port.
fn commissioning_on_a_pty(name: &str, sim_args: &[&str], speed: &str) -> (String, PathBuf, String) {
    let dir = scratch(name);
    let sim = Simulator::pty(&[&["--drive", "modbus-inverter"], sim_args].concat());
    let recipe = commissioning(&dir, "modbus-inverter");
    let trace = dir.join("run.trace");
    let text = sim
        .cli(
            &[
                "run",
                recipe.to_str().unwrap(),
                "--set",
                &format!("speed={speed}"),
                "--trace",
                trace.to_str().unwrap(),
            ],
            0,
        )
        .stdout;
    (text, trace, sim.endpoint.clone())
}

#[test]
fn the_commissioning_recipe_runs_through_a_pseudo_terminal_and_its_trace_decodes() {
    let (text, trace, port) = commissioning_on_a_pty("modbus-commissioning", &[], "1200rpm");
    assert_has(
        &text,
        &[
            &format!("slave 1 on {port} at 19200 8E1"),
            "ok    go to operation_enabled  enable operation → operation enabled",
            "finally 1  ok    disable_operation  control word 3",
            "drive left in switched on at 0 rpm",
            "PASSED",
        ],
    );
    // 1200 rpm is 20.0 Hz, 200 counts of 0.1 Hz: 06 10 02 00 C8 to slave 1.
    let traced = std::fs::read_to_string(&trace).unwrap();
    assert_has(
        &traced,
        &[
            "01 06 10 02 00 c8",
            "slave 1 write single register: speed_setpoint = 1200 rpm",
        ],
    );
    let decoded = cli(&["decode", trace.to_str().unwrap()], 0).stdout;
    assert_has(
        &decoded,
        &[
            "slave 1 write single register: run_command = 0x0001",
            "slave 1 reply to read holding registers: status_word = 0x0003 (switched on)",
        ],
    );
}

#[test]
fn two_inverters_on_one_line_reach_their_own_speeds_and_a_broadcast_reaches_both() {
    let dir = scratch("modbus-two");
    let sim = Simulator::pty(&["--drive", "modbus-inverter", "--address", "1,2"]);
    let recipe = write_file(
        &dir,
        "two.yaml",
        "name: Two inverters
drives:
  a: { drive: modbus-inverter, address: 1 }
  b: { drive: modbus-inverter, address: 2 }
steps:
  - set: { a.speed_setpoint: 600 rpm, b.speed_setpoint: 1200 rpm }
  - go_to: operation_enabled
  - wait_until: { a.speed_actual: { near: 600 rpm, within: 1 % }, timeout: 10 s }
  - wait_until: { b.speed_actual: { near: 1200 rpm, within: 1 % }, timeout: 10 s }
",
    );
    let text = cli(&["run", recipe.to_str().unwrap(), "--port", &sim.endpoint], 0).stdout;
    assert_has(
        &text,
        &[
            &format!(
                "a: slave 1 on {0} at 19200 8E1, b: slave 2 on {0} at 19200 8E1",
                sim.endpoint
            ),
            "wait until a.speed_actual near 600 rpm ± 1 % (timeout 10s)  600 rpm",
            "wait until b.speed_actual near 1200 rpm ± 1 % (timeout 10s)  1200 rpm",
            "b: disable_operation (default finally)  control word 3",
            "a: disable_operation (default finally)  control word 3",
            "PASSED",
        ],
    );
    for address in ["1", "2"] {
        let out = sim.cli(
            &[
                "read",
                "run_command",
                "--drive",
                "modbus-inverter",
                "--address",
                address,
            ],
            0,
        );
        assert_has(&out.stdout, &["0x0003"]);
    }
    // A broadcast write reaches both, unanswered; a broadcast read is refused unsent.
    let on = ["--drive", "modbus-inverter", "--port", sim.endpoint.as_str()];
    let out = cli(
        &[
            &["write", "speed_setpoint", "300rpm", "--address", "0"][..],
            &on[..],
        ]
        .concat(),
        0,
    )
    .stdout;
    assert_has(
        &out,
        &["sent to every slave on the line (broadcast), not confirmed"],
    );
    for address in ["1", "2"] {
        let out = cli(
            &[&["read", "speed_setpoint", "--address", address][..], &on[..]].concat(),
            0,
        )
        .stdout;
        assert_has(&out, &["300 rpm"]);
    }
    let out = drivescript(
        &[&["read", "speed_setpoint", "--address", "0"][..], &on[..]].concat(),
        "",
    );
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn ctrl_c_through_a_pseudo_terminal_writes_the_stop_code_and_leaves_the_inverter_stopped() {
    let sim = ctrl_c_during_a_dwell(
        ("sunfar-e500", "600 rpm"),
        Duration::from_millis(300),
        ("slave 1", "8O1"),
        &[
            "set speed_setpoint = 0 rpm (default finally)",
            "disable_operation (default finally)  control word 3",
            "shutdown (default finally)  control word 3",
            "drive left in switched on",
        ],
    );
    let out = sim.cli(
        &["read", "run_command", "inverter_status", "--drive", "sunfar-e500"],
        0,
    );
    assert_has(
        &out.stdout,
        &["run_command      0x0003", "inverter_status  0x0003"],
    );
}

#[test]
fn backup_diff_and_restore_of_an_inverters_parameters() {
    let dir = scratch("modbus-backup");
    let sim = Simulator::pty(&["--drive", "sunfar-e500"]);
    let file = dir.join("backup.yaml").to_string_lossy().to_string();
    let on = ["--drive", "sunfar-e500", "--port", sim.endpoint.as_str()];
    cli(&[&["backup", "-o", file.as_str()][..], &on[..]].concat(), 0);
    let saved = std::fs::read_to_string(&file).unwrap();
    assert_has(&saved, &["name: \"carrier_frequency\"", "raw: \"80\""]);
    cli(&[&["write", "carrier_frequency", "12"][..], &on[..]].concat(), 0);
    let out = cli(&[&["diff", file.as_str()][..], &on[..]].concat(), 1).stdout;
    assert_has(&out, &["carrier_frequency", "1 difference(s)"]);
    let out = cli(&[&["restore", file.as_str(), "--apply"][..], &on[..]].concat(), 0).stdout;
    assert_has(&out, &["restored 1 parameter(s)"]);
    cli(&[&["diff", file.as_str()][..], &on[..]].concat(), 0);
}

#[test]
fn modbus_tcp_reads_each_unit_behind_one_address() {
    let sim = Simulator::start(&[
        "--drive",
        "modbus-tcp-inverter",
        "--tcp",
        "127.0.0.1:0",
        "--address",
        "1,2",
    ]);
    for unit in ["1", "2"] {
        let at_unit = |command: &[&str]| {
            let connection = [
                "--drive",
                "modbus-tcp-inverter",
                "--tcp",
                &sim.endpoint,
                "--address",
                unit,
            ];
            cli(&[command, &connection[..]].concat(), 0)
        };
        at_unit(&["write", "speed_setpoint", "300rpm"]);
        let out = at_unit(&["read", "speed_setpoint", "status_word"]);
        assert_has(&out.stdout, &["300 rpm", "0x0003"]);
    }
}

/// The RTU frames of the Sunfar E500 manual's examples (Appendix II, 1.2, pp. 90-91)
/// explained through the dictionary, and a frame with a bad CRC rejected.
#[test]
fn decode_explains_the_frames_of_the_manual_and_rejects_a_bad_crc() {
    let out = cli(
        &[
            "decode",
            "--protocol",
            "modbus-rtu",
            "--drive",
            "sunfar-e500",
            "01 03 D0 00 00 02 FC CB",
            "01 03 04 01 F4 00 0B FB FA",
            "01 10 10 01 00 02 04 00 01 01 90 AF 9F",
            "01 03 D0 00 00 02 FC CC",
        ],
        1,
    )
    .stdout;
    assert_has(
        &out,
        &[
            "slave 1 read holding registers: holding 0xD000 (453249) speed_actual ×2",
            "slave 1 reply to read holding registers: speed_actual = 3000 rpm, current_actual = 1.1 A",
            "CRC FB FA correct",
            "slave 1 write multiple registers from holding 0x1001 (44098) run_command: run_command = 0x0001, speed_setpoint = 2400 rpm",
            "rejected: no Modbus RTU frame: bad CRC: the frame ends FC CC, its bytes give FC CB",
        ],
    );
    let tcp = cli(
        &["decode", "--protocol", "modbus-tcp", "00 07 00 00 00 03 01 83 02"],
        0,
    )
    .stdout;
    assert_has(
        &tcp,
        &["unit 1 transaction 7 reply to function 03: exception 02 ILLEGAL DATA ADDRESS"],
    );
}

/// Behind a half-duplex adapter that hands every request back: the echo is skipped (a
/// write single register's lone copy is its reply; the reply after an echo is dropped as
/// stale before the next request).
#[test]
fn the_commissioning_recipe_runs_behind_an_adapter_that_echoes() {
    let (text, trace, _) = commissioning_on_a_pty("modbus-echo", &["--echo"], "600rpm");
    assert_has(&text, &["drive left in switched on at 0 rpm", "PASSED"]);
    assert_has(
        &std::fs::read_to_string(&trace).unwrap(),
        &["skipped the echo of the request"],
    );
}

/// A write says what the inverter will hold: 0.1 Hz counts are 6 rpm, so 3003 rpm is sent
/// as 501 counts, which is 3006 rpm (it used to say "3003 rpm written (raw 501)").
#[test]
fn a_write_reports_the_value_the_wire_quantised_it_to() {
    let written = |value: &str| {
        cli(
            &["write", "--drive", "modbus-inverter", "speed_setpoint", value],
            0,
        )
        .stdout
    };
    let text = written("3003rpm");
    assert!(
        text.contains("speed_setpoint = 3006 rpm written (raw 501; 3003 rpm given, the nearest the object's resolution holds)"),
        "{text}"
    );
    let text = written("3000rpm");
    assert!(
        text.contains("speed_setpoint = 3000 rpm written (raw 500)\n"),
        "{text}"
    );
}

/// The manual's Modbus `decode` example prints what the manual says it prints (it used to
/// give the reply alone, which decodes as raw registers `[500, 11]`).
#[test]
fn the_manuals_decode_example_prints_what_it_says() {
    let readme = std::fs::read_to_string(repo_root().join("docs/src/families/modbus.md"))
        .expect("docs/src/families/modbus.md");
    let flat = readme.split_whitespace().collect::<Vec<_>>().join(" ");
    let start = flat
        .find("`drivescript decode --protocol modbus-rtu")
        .expect("the manual's Modbus decode example");
    let rest = &flat[start + 1..];
    let command = &rest[..rest.find('`').expect("the example's closing backquote")];
    let after = &rest[command.len()..];
    // Words, and "quoted" telegrams as one argument each.
    let mut args = Vec::new();
    for (i, part) in command.split('"').enumerate() {
        if i % 2 == 1 {
            args.push(part.to_string());
        } else {
            args.extend(part.split_whitespace().map(str::to_string));
        }
    }
    assert_eq!(args.first().map(String::as_str), Some("drivescript"), "{command}");
    let args: Vec<&str> = args[1..].iter().map(String::as_str).collect();
    let out = cli(&args, 0).stdout;
    for claimed in [
        "slave 1 reply to read holding registers: speed_actual = 3000 rpm, current_actual = 1.1 A",
        "CRC FB FA correct",
    ] {
        assert!(after.contains(claimed), "the manual no longer claims {claimed:?}");
        assert!(
            out.contains(claimed),
            "`{command}` does not print {claimed:?}:\n{out}"
        );
    }
}

/// `check` notes where the wire's whole counts change a recipe's value (0.1 Hz counts of
/// 6 rpm: 3003 rpm is sent as 3006 rpm), and only there; the recipe is still valid.
#[test]
fn check_notes_a_value_the_wire_quantises() {
    let out = check_file(
        &scratch("quantised"),
        "recipe.yaml",
        "name: quantised\ndrive: modbus-inverter\nsteps:\n  - set: { speed_setpoint: 3003 rpm }\n  - set: { speed_setpoint: 3000 rpm }\n",
        0,
    );
    assert_has(
        &out.stderr,
        &["recipe.yaml:4:5: set speed_setpoint = 3003 rpm: the drive holds whole counts of 6 rpm, so it gets 3006 rpm"],
    );
    assert_eq!(out.stderr.matches("note:").count(), 1, "{}", out.stderr);
}
