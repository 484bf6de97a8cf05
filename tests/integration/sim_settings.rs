//! `--sim` settings refused where they would act on nothing: a run (and `check`) that talks
//! to a real line or a replayed capture, whose drive no setting of the built-in simulated
//! drive's physics can change; the built-in simulated drive still takes them.

use crate::support::{assert_has, assert_lacks, cli};

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
    let out = cli(
        &[
            "run",
            "recipes/commissioning.yaml",
            "--replay",
            "tests/cases/replay/sd2_commissioning/capture.trace",
            "--sim",
            "coast-rate=300rpm/s",
        ],
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
        &[
            "run",
            "recipes/commissioning.yaml",
            "--fast",
            "--no-results",
            "--sim",
            "overshoot=10%",
        ],
        0,
    );
    assert_has(&out.stdout, &["PASSED"]);
}
