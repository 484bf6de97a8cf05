//! `--sim emergency-at` across the families: refused before anything runs (exit 2, saying
//! which drives send one) where no simulated drive of the run sends an emergency message.

use crate::support::{assert_has, assert_lacks, cli, scratch, write_file};

#[test]
fn an_emergency_no_simulated_drive_can_send_is_refused_before_anything_runs() {
    let dir = scratch("emergency-refused");
    let trace = dir.join("run.trace");
    let trace = trace.to_str().unwrap();
    let refusal = "--sim emergency-at: no simulated sd2 drive sends emergency messages";
    let what_to_do = "give it with --drive";
    let out = cli(
        &[
            "run",
            "recipes/commissioning.yaml",
            "--fast",
            "--sim",
            "emergency-at=20s:0x2310",
            "--trace",
            trace,
        ],
        2,
    );
    assert_has(&out.stderr, &[refusal, what_to_do, "canopen", "or leave it out"]);
    assert_lacks(&out.stdout, &["PASSED", "control word"]);
    assert!(!std::path::Path::new(trace).exists(), "nothing was sent");
    // Several drives, none of which sends one.
    let recipe = write_file(
        &dir,
        "two.yaml",
        "name: Two\ndrives:\n  left:  { drive: sd2, address: dnc:2 }\n  right: { drive: ct-unidrive-sp }\nsteps:\n  - dwell: 1 min\n",
    );
    let out = cli(
        &[
            "run",
            recipe.to_str().unwrap(),
            "--fast",
            "--sim",
            "emergency-at=20s:0x2310",
        ],
        2,
    );
    assert_has(
        &out.stderr,
        &["no simulated ct-ansi or sd2 drive sends emergency messages"],
    );
    // `simulate` refuses it the same, before it serves anything.
    let out = cli(
        &[
            "simulate",
            "--drive",
            "sd2",
            "--pty",
            "--sim",
            "emergency-at=20s:0x2310",
        ],
        2,
    );
    assert_has(&out.stderr, &[refusal, what_to_do]);
    assert_lacks(&out.stdout, &["/dev/pts"]);
    // The physics settings stay the simulated drive's, on every family.
    let out = cli(
        &[
            "run",
            "recipes/commissioning.yaml",
            "--fast",
            "--sim",
            "overshoot=10%",
        ],
        0,
    );
    assert_has(&out.stdout, &["PASSED"]);
}
