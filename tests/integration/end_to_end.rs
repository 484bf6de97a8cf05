//! The binary end to end: `simulate --pty` with `state`/`read`/`write --port` through a real
//! pseudo-terminal, `simulate --tcp` on loopback, and Ctrl-C (SIGINT) during a real-time
//! run, which must still run `finally` and exit with 130.

use crate::live_run::LiveRun;
use crate::support::{assert_has, assert_lacks, cli, first_line_then_closed_pipe, repo_root, Simulator};
use std::process::Stdio;

/// Under Wine the pty is a COM port and the commands go through Windows' serial API.
#[test]
fn a_pseudo_terminal_serves_the_simulated_drive() {
    let sim = Simulator::start(&["--pty"]);
    let prefix = if cfg!(windows) { "COM" } else { "/dev/" };
    assert!(sim.endpoint.starts_with(prefix), "endpoint {:?}", sim.endpoint);
    let port = sim.endpoint.as_str();

    let out = cli(&["state", "--port", port], 0);
    assert_has(&out.stdout, &["status word 0x0240: switch on disabled"]);

    let out = cli(&["write", "speed_setpoint", "6000rpm", "--port", port], 0);
    assert_has(&out.stdout, &["speed_setpoint = 6000 rpm written (raw 6000000)"]);

    // The simulated drive keeps its state between connections, like a real one.
    let out = cli(&["read", "speed_setpoint", "ident", "--port", port, "--json"], 0);
    let json: serde_json::Value = serde_json::from_str(out.stdout.trim()).expect("json");
    assert_eq!(json[0]["value"], 6000.0);
    assert_eq!(json[0]["unit"], "rpm");
    assert_eq!(json[1]["value"], "Test Motor");

    // An object by its index, as the family writes it, reads the same raw count.
    let out = cli(&["read", "395", "--type", "i32", "--port", port, "--json"], 0);
    let json: serde_json::Value = serde_json::from_str(out.stdout.trim()).expect("json");
    assert_eq!(json[0]["object"], "395");
    assert_eq!(json[0]["raw"], "6000000");

    // Without a type nothing is sent and the message says what to add.
    let out = cli(&["read", "0x18b", "--port", port], 2);
    assert_has(&out.stderr, &["--type"]);
}

#[test]
fn tcp_on_loopback_serves_the_simulated_drive() {
    let sim = Simulator::start(&["--tcp", "127.0.0.1:0"]);
    assert!(
        sim.endpoint.starts_with("127.0.0.1:"),
        "endpoint {:?}",
        sim.endpoint
    );
    let out = cli(&["state", "--tcp", &sim.endpoint], 0);
    assert_has(&out.stdout, &["switch on disabled"]);
}

#[test]
fn a_missing_port_says_which_and_what_to_do() {
    let err = cli(&["state", "--port", "/dev/does-not-exist-ds"], 3).stderr;
    assert_has(
        &err,
        &["/dev/does-not-exist-ds does not exist", "drivescript ports"],
    );
}

#[test]
fn a_drive_that_does_not_answer_is_exit_code_3_naming_the_telegram() {
    // A loopback listener that accepts and never answers.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = listener.local_addr().expect("addr").to_string();
    let err = cli(
        &["state", "--tcp", &addr, "--timeout", "50ms", "--retries", "1"],
        3,
    )
    .stderr;
    assert_has(
        &err,
        &[
            "no reply from drive 2 on tcp",
            "00 09 02 01 0d 43 00 00 00 00 00 a3",
        ],
    );
    drop(listener);
}

/// Under Wine the Ctrl-C is the console's CTRL_C_EVENT (see `LiveRun::signal`), which the
/// run's console handler turns into the same safe stop.
#[test]
fn ctrl_c_during_a_run_stops_safely_and_exits_130() {
    let run = LiveRun::start(["run", "tests/cases/interrupted/ctrl_c_during_run_in/recipe.yaml"]);
    // Wait until the dwell has begun (the second step's line is printed), then press Ctrl-C.
    let (_, code, all) = run.interrupt_after("set speed_setpoint", std::time::Duration::ZERO);
    assert_eq!(code, Some(130), "{all}");
    // The press lands in the dwell or just before it starts; either way the steps stop.
    assert_lacks(&all, &["ok    dwell"]);
    assert_has(
        &all,
        &[
            "finally 3  ok    shutdown",
            "drive left in ready to switch on",
            "INTERRUPTED",
        ],
    );
}

#[test]
fn a_closed_output_pipe_does_not_stop_a_run_before_its_safe_stop() {
    let (first, status) = first_line_then_closed_pipe(&["run", "recipes/commissioning.yaml", "--fast"]);
    // Killed by SIGPIPE would be no exit code at all; the run must finish (and stop the
    // drive) and report its verdict through the exit code.
    assert_eq!(status.code(), Some(0), "{first}");
}

#[test]
fn other_commands_end_quietly_on_a_closed_pipe() {
    let mut child = crate::support::command()
        .args(["completions", "bash"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    drop(child.stdout.take());
    let output = child.wait_with_output().expect("ends");
    assert!(
        !String::from_utf8_lossy(&output.stderr).contains("panicked"),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The shipped commissioning recipe gives the same verdict over both SD2 channels through
/// a real pseudo-terminal (a COM port under Wine), in real time, and the cyclic run's
/// telegrams are cyclic ones.
#[test]
fn the_cyclic_channel_runs_the_commissioning_recipe_through_a_pty() {
    let recipe = repo_root().join("recipes/commissioning.yaml");
    let recipe = recipe.to_string_lossy();
    let trace = std::env::temp_dir().join(format!("drivescript-cyclic-{}.trace", std::process::id()));
    let trace_arg = trace.to_string_lossy();
    for channel in [
        &[][..],
        &[
            "--channel",
            "cyclic",
            "--velocity-scaling",
            "24000rpm",
            "--trace",
            &trace_arg,
        ][..],
    ] {
        let sim = Simulator::start(&["--pty"]);
        let mut args = vec!["run", recipe.as_ref(), "--port", sim.endpoint.as_str()];
        args.extend_from_slice(channel);
        let text = cli(&args, 0).stdout;
        assert_has(
            &text,
            &[
                "PASS  speed_actual near 3000 rpm ± 1 %",
                "drive left in ready to switch on at 0 rpm",
            ],
        );
    }
    let trace_text = std::fs::read_to_string(&trace).expect("trace written");
    let _ = std::fs::remove_file(&trace);
    assert!(
        trace_text.contains("02 01 10 01 00 0f 00"),
        "no cyclic enable telegram in the trace"
    );
    assert!(
        !trace_text.contains(" 0e 44 00 "),
        "a control word went by object access:\n{trace_text}"
    );
}
