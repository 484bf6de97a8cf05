//! The binary end to end: `simulate --pty` with `state`/`read`/`write --port` through a real
//! pseudo-terminal, `simulate --tcp` on loopback, and Ctrl-C (SIGINT) during a real-time
//! run, which must still run `finally` and exit with 130.

use crate::support::{drivescript, repo_root, stderr, stdout};
use std::io::{BufRead, BufReader, Read};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A `drivescript simulate` in the background, stopped when dropped.
pub struct Simulator {
    child: Child,
    /// The first line it printed: the pty path or the TCP address.
    pub endpoint: String,
}

impl Simulator {
    pub fn start(args: &[&str]) -> Simulator {
        let mut child = Command::new(env!("CARGO_BIN_EXE_drivescript"))
            .arg("simulate")
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("simulate starts");
        let out = child.stdout.take().expect("stdout is piped");
        let mut line = String::new();
        BufReader::new(out)
            .read_line(&mut line)
            .expect("simulate prints its endpoint");
        Simulator {
            child,
            endpoint: line.trim().to_string(),
        }
    }
}

impl Drop for Simulator {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[cfg(unix)]
#[test]
fn a_pseudo_terminal_serves_the_simulated_drive() {
    let sim = Simulator::start(&["--pty"]);
    assert!(sim.endpoint.starts_with("/dev/"), "endpoint {:?}", sim.endpoint);
    let port = sim.endpoint.as_str();

    let out = drivescript(&["state", "--port", port], "");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("status word 0x0240: switch on disabled"),
        "{}",
        stdout(&out)
    );

    let out = drivescript(&["write", "speed_setpoint", "6000rpm", "--port", port], "");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("speed_setpoint = 6000 rpm written (raw 6000000)"),
        "{}",
        stdout(&out)
    );

    // The simulated drive keeps its state between connections, like a real one.
    let out = drivescript(&["read", "speed_setpoint", "ident", "--port", port, "--json"], "");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("json");
    assert_eq!(json[0]["value"], 6000.0);
    assert_eq!(json[0]["unit"], "rpm");
    assert_eq!(json[1]["value"], "Test Motor");
}

#[test]
fn tcp_on_loopback_serves_the_simulated_drive() {
    let sim = Simulator::start(&["--tcp", "127.0.0.1:0"]);
    assert!(
        sim.endpoint.starts_with("127.0.0.1:"),
        "endpoint {:?}",
        sim.endpoint
    );
    let out = drivescript(&["state", "--tcp", &sim.endpoint], "");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("switch on disabled"), "{}", stdout(&out));
}

#[test]
fn a_missing_port_says_which_and_what_to_do() {
    let out = drivescript(&["state", "--port", "/dev/does-not-exist-ds"], "");
    assert_eq!(out.status.code(), Some(3));
    let err = stderr(&out);
    assert!(err.contains("/dev/does-not-exist-ds does not exist"), "{err}");
    assert!(err.contains("drivescript ports"), "{err}");
}

#[test]
fn a_drive_that_does_not_answer_is_exit_code_3_naming_the_telegram() {
    // A loopback listener that accepts and never answers.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = listener.local_addr().expect("addr").to_string();
    let out = drivescript(
        &["state", "--tcp", &addr, "--timeout", "50ms", "--retries", "1"],
        "",
    );
    assert_eq!(out.status.code(), Some(3));
    let err = stderr(&out);
    assert!(err.contains("no reply from drive 2 on tcp"), "{err}");
    assert!(err.contains("00 09 02 01 0d 43 00 00 00 00 00 a3"), "{err}");
    drop(listener);
}

#[cfg(unix)]
#[test]
fn ctrl_c_during_a_run_stops_safely_and_exits_130() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_drivescript"))
        .args(["run", "tests/cases/interrupted/ctrl_c_during_run_in/recipe.yaml"])
        .current_dir(repo_root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run starts");
    let mut out = child.stdout.take().expect("stdout");
    // Wait until the dwell has begun (the second step's line is printed), then press Ctrl-C.
    let mut seen = String::new();
    let start = Instant::now();
    let mut buf = [0u8; 256];
    while !seen.contains("set speed_setpoint") && start.elapsed() < Duration::from_secs(20) {
        let n = out.read(&mut buf).expect("read");
        if n == 0 {
            break;
        }
        seen.push_str(&String::from_utf8_lossy(&buf[..n]));
    }
    assert!(seen.contains("set speed_setpoint"), "{seen}");
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success());
    let mut rest = String::new();
    out.read_to_string(&mut rest).expect("read rest");
    let code = child.wait().expect("run ends").code();
    let all = format!("{seen}{rest}");
    assert_eq!(code, Some(130), "{all}");
    // The press lands in the dwell or just before it starts; either way the steps stop.
    assert!(!all.contains("ok    dwell"), "{all}");
    assert!(all.contains("finally 3  ok    shutdown"), "{all}");
    assert!(all.contains("drive left in ready to switch on"), "{all}");
    assert!(all.contains("INTERRUPTED"), "{all}");
}

#[cfg(unix)]
#[test]
fn a_closed_output_pipe_does_not_stop_a_run_before_its_safe_stop() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_drivescript"))
        .args(["run", "recipes/commissioning.yaml", "--fast"])
        .current_dir(repo_root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run starts");
    // Like `| head -1`: read one line, then close the pipe.
    let mut out = BufReader::new(child.stdout.take().expect("stdout"));
    let mut first = String::new();
    out.read_line(&mut first).expect("first line");
    drop(out);
    let status = child.wait().expect("run ends");
    // Killed by SIGPIPE would be no exit code at all; the run must finish (and stop the
    // drive) and report its verdict through the exit code.
    assert_eq!(status.code(), Some(0), "{first}");
}

#[cfg(unix)]
#[test]
fn other_commands_end_quietly_on_a_closed_pipe() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_drivescript"))
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
