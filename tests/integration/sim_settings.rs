//! `--sim` settings refused where they would act on nothing: a run (and `check`) that talks
//! to a real line or a replayed capture, whose drive no setting of the built-in simulated
//! drive's physics can change; the built-in simulated drive still takes them.

use crate::support::{assert_has, assert_lacks, cli, scratch_file, words, write_file};

const REFUSED: &str = "--sim sets the built-in simulated drive's physics, but this run talks to";

#[test]
fn a_sim_setting_on_a_real_line_or_a_replay_is_refused_before_anything_is_sent() {
    // A port that does not exist: refused for the setting, before the port is opened.
    let port = ["--port", "/dev/ttyUSB-drivescript-none", "--sim", "overshoot=10%"];
    for command in ["run", "check"] {
        let mut args = vec![command, "recipes/commissioning.yaml"];
        args.extend(port);
        let out = cli(&args, 2);
        assert_has(
            &out.stderr,
            &[
                REFUSED,
                "serial /dev/ttyUSB-drivescript-none, 57600 8N1, where it would do nothing",
                "drivescript simulate --sim",
            ],
        );
        assert_lacks(&out.stderr, &["cannot open"]);
    }
    let replay = "tests/cases/replay/sd2_commissioning/capture.trace";
    let out = cli(
        &words(&format!(
            "run recipes/commissioning.yaml --replay {replay} --sim coast-rate=300rpm/s"
        )),
        2,
    );
    assert_has(
        &out.stderr,
        &[
            REFUSED,
            "a replay of tests/cases/replay/sd2_commissioning/capture.trace",
        ],
    );
    assert_lacks(&out.stdout, &["PASSED", "control word"]);
    let out = cli(
        &words("run recipes/commissioning.yaml --fast --no-results --sim overshoot=10%"),
        0,
    );
    assert_has(&out.stdout, &["PASSED"]);
}

/// Several drives each on a line of its own: no simulated drive is left for a `--sim`
/// setting to act on, so it is refused before any port is opened; where one drive is
/// still simulated, the setting is its, and an emergency is judged by the simulated
/// drives alone.
#[test]
fn a_sim_setting_where_every_named_drive_has_its_own_line_is_refused() {
    let (dir, own) = scratch_file(
        "own-lines",
        "own.yaml",
        "name: Own lines\ndrives:\n  left:  { drive: sd2, address: dnc:2, port: /dev/ttyUSB-drivescript-none-1 }\n  right: { drive: sd2, address: dnc:3, port: /dev/ttyUSB-drivescript-none-2 }\nsteps:\n  - set: { left.speed_setpoint: 0 rpm }\n",
    );
    for command in ["run", "check"] {
        let out = cli(&[command, own.to_str().unwrap(), "--sim", "overshoot=10%"], 2);
        assert_has(
            &out.stderr,
            &[
                REFUSED,
                "left: serial /dev/ttyUSB-drivescript-none-1, 57600 8N1",
                "right: serial /dev/ttyUSB-drivescript-none-2, 57600 8N1",
            ],
        );
        assert_lacks(&out.stderr, &["does not exist", "cannot open"]);
    }
    // The CANopen node is on a bus of its own: no simulated drive of the run sends an EMCY.
    let mixed = write_file(
        &dir,
        "mixed.yaml",
        "name: Mixed\ndrives:\n  left:  { drive: sd2, address: dnc:2 }\n  node:  { drive: canopen, can: slcan:/dev/ttyUSB-drivescript-none-3 }\nsteps:\n  - set: { left.speed_setpoint: 0 rpm }\n",
    );
    let out = cli(
        &[
            "check",
            mixed.to_str().unwrap(),
            "--sim",
            "emergency-at=20s:0x2310",
        ],
        2,
    );
    assert_has(
        &out.stderr,
        &["--sim emergency-at: no simulated sd2 drive sends emergency messages"],
    );
    cli(&["check", mixed.to_str().unwrap(), "--sim", "overshoot=10%"], 0);
}
