//! What `write` and `read` promise about sending, through the real command line against
//! the simulated Unidrive SP on a pseudo-terminal: a value beyond the documented range is
//! refused before anything is sent (exit 2), a value the dictionary gives no range for is
//! said to be unchecked, a read to a group address is an invalid request (exit 2, nothing
//! sent), and a group write says it was sent and not confirmed.

use crate::support::{assert_has, assert_lacks, cli, Simulator};

fn ct<'a>(args: &[&'a str], port: &'a str) -> Vec<&'a str> {
    [args, &["--drive", "ct-unidrive-sp", "--port", port]].concat()
}

#[test]
fn a_speed_beyond_the_documented_range_is_refused_before_sending() {
    let sim = Simulator::start(&["--drive", "ct-unidrive-sp", "--pty"]);
    let port = sim.endpoint.as_str();
    cli(&ct(&["write", "speed_setpoint", "12.5", "rpm"], port), 0);
    let out = cli(&ct(&["write", "speed_setpoint", "99999999", "rpm"], port), 2);
    assert_has(
        &out.stderr,
        &["above the maximum of speed_setpoint, 40000 rpm; nothing was sent"],
    );
    assert!(
        !out.stdout.contains("note:"),
        "a checked value has no note: {}",
        out.stdout
    );
    let out = cli(&ct(&["write", "speed_setpoint", "-40000.1", "rpm"], port), 2);
    assert_has(&out.stderr, &["nothing was sent"]);
    // The drive still holds the earlier value: nothing reached it.
    let out = cli(&ct(&["read", "speed_setpoint"], port), 0);
    assert_has(&out.stdout, &["12.5 rpm"]);
}

#[test]
fn a_value_without_a_documented_range_is_said_to_be_unchecked() {
    let sim = Simulator::start(&["--drive", "ct-unidrive-sp", "--pty"]);
    let port = sim.endpoint.as_str();
    let out = cli(&ct(&["write", "control_word", "128"], port), 0);
    assert_has(&out.stdout, &["note: control_word: the dictionary gives no range for it, so the value was checked against its type (u16) only"]);
    let out = cli(&ct(&["write", "max_speed", "3000", "rpm"], port), 0);
    assert_has(
        &out.stdout,
        &["note: max_speed: the dictionary gives its maximum (40000 rpm) but no minimum"],
    );
    // A raw parameter has no range at all; the note stands before the drive's refusal
    // (the simulated drive has no #1.22).
    let out = cli(&ct(&["write", "#1.22", "10"], port), 3);
    assert_has(&out.stdout, &["note: #1.22: the dictionary gives no range"]);
    assert_has(&out.stderr, &["the drive answered NAK"]);
}

#[test]
fn a_group_read_is_invalid_and_a_group_write_is_not_confirmed() {
    let sim = Simulator::start(&["--drive", "ct-unidrive-sp", "--pty"]);
    let port = sim.endpoint.as_str();
    for command in [&["read", "speed_setpoint"][..], &["state"]] {
        let out = cli(&ct(&[command, &["--address", "1.0"]].concat(), port), 2);
        assert!(
            out.stderr.contains("takes writes only") && out.stderr.contains("nothing was sent"),
            "{}",
            out.stderr
        );
    }
    let out = cli(
        &ct(
            &["write", "speed_setpoint", "12.5", "rpm", "--address", "1.0"],
            port,
        ),
        0,
    );
    assert_has(&out.stdout, &["speed_setpoint = 12.5 rpm (raw 12.5) sent to every drive of group 1 (group address 1.0), not confirmed"]);
    assert_lacks(&out.stdout, &["written"]);
    // It did reach the drive of group 1.
    let out = cli(&ct(&["read", "speed_setpoint"], port), 0);
    assert_has(&out.stdout, &["12.5 rpm"]);
}
