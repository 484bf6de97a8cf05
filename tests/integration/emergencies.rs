//! Emergency messages across the families: `--sim emergency-at` refused before anything
//! runs (exit 2, saying which drives send one) where no simulated drive of the run sends
//! one; a Lenze 9400's EMCY (no device-control profile) ending a run as a drive fault, its
//! simulated node sending an injected one in process and served.

use crate::support::{assert_has, assert_lacks, cli, scratch, scratch_file, words, write_file};

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
    // Several drives, none of which sends one: see `check_refuses_an_emergency_as_run_does`.
    // `simulate` refuses it the same, before it serves anything.
    let out = cli(
        &words("simulate --drive sd2 --pty --sim emergency-at=20s:0x2310"),
        2,
    );
    assert_has(&out.stderr, &[refusal, what_to_do]);
    assert_lacks(&out.stdout, &["/dev/pts"]);
    // The physics settings stay the simulated drive's, on every family.
    let out = cli(
        &words("run recipes/commissioning.yaml --fast --sim overshoot=10%"),
        0,
    );
    assert_has(&out.stdout, &["PASSED"]);
}

/// `check` refuses what `run` refuses: an emergency no simulated drive of the file sends
/// (one drive, and several), and takes it where a drive's simulated node sends one.
#[test]
fn check_refuses_an_emergency_as_run_does() {
    let emergency = ["--sim", "emergency-at=20s:0x2310"];
    let out = cli(
        &[&["check", "recipes/commissioning.yaml"][..], &emergency].concat(),
        2,
    );
    assert_has(
        &out.stderr,
        &["--sim emergency-at: no simulated sd2 drive sends emergency messages"],
    );
    let (dir, two) = scratch_file(
        "emergency-check",
        "two.yaml",
        "name: Two\ndrives:\n  left:  { drive: sd2, address: dnc:2 }\n  right: { drive: ct-unidrive-sp }\nsteps:\n  - dwell: 1 min\n",
    );
    for command in [&["run", "--fast"][..], &["check"]] {
        let out = cli(&[command, &[two.to_str().unwrap()], &emergency].concat(), 2);
        assert_has(
            &out.stderr,
            &["no simulated ct-ansi or sd2 drive sends emergency messages"],
        );
    }
    let node = write_file(
        &dir,
        "node.yaml",
        "name: Node\ndrive: canopen\nsteps:\n  - dwell: 1 min\n",
    );
    cli(&[&["check", node.to_str().unwrap()][..], &emergency].concat(), 0);
}

/// A Lenze 9400 has no device-control profile, so no state is watched; an EMCY with an
/// error code is a drive fault all the same: the dwell stops on it, `on_fault` runs and
/// the profile-less safe stop ends the run with exit code 3 and the CiA 301 text.
#[test]
fn a_lenze_9400_emcy_ends_the_run_as_a_drive_fault() {
    let (dir, recipe) = scratch_file(
        "lenze-9400-emcy",
        "emcy.yaml",
        "name: 9400 EMCY\ndrive: lenze-9400\nsteps:\n  - read: [ident]\n  - dwell: 1 min\n  - read: [heatsink_temperature]\non_fault:\n  - read: [heatsink_temperature]\n",
    );
    let trace = dir.join("run.log");
    let trace_arg = trace.to_str().unwrap();
    let out = cli(
        &[
            "run",
            recipe.to_str().unwrap(),
            "--fast",
            "--sim",
            "emergency-at=20s:0x4310",
            "--trace",
            trace_arg,
        ],
        3,
    );
    let fault = "drive fault: the drive reported node 1 EMCY 0x4310 drive temperature (error register 0x01)";
    crate::support::assert_in_order(
        &out.stdout,
        &[
            &format!("FAIL  dwell 1m  {fault}"),
            "on_fault 1  ok    read heatsink_temperature",
            "safe stop: the lenze-9400 dictionary has no device-control profile",
            &format!("ERROR: {fault}"),
        ],
    );
    // The dwell ended at the EMCY (sent at 20 s), not after its minute.
    assert_has(&out.stdout, &["failed, 20s "]);
    let trace = std::fs::read_to_string(&trace).expect("trace");
    assert_has(&trace, &["081#1043010000000000"]);
}

/// The served 9400 node sends an injected EMCY on its own, through a simulated SLCAN
/// adapter in real time, and the run in its dwell stops on it.
#[test]
fn a_served_lenze_9400_node_sends_an_injected_emcy() {
    // The EMCY is due this long after the simulator starts: the run must be in its dwell
    // by then, and a Windows process under Wine takes seconds to start on a busy machine.
    let emergency = if cfg!(windows) {
        "emergency-at=15s:0x2310"
    } else {
        "emergency-at=2s:0x2310"
    };
    let sim = crate::support::Simulator::start(&["--drive", "lenze-9400", "--slcan-pty", "--sim", emergency]);
    let (_, recipe) = scratch_file(
        "lenze-9400-emcy-slcan",
        "emcy.yaml",
        "name: 9400 EMCY over SLCAN\ndrive: lenze-9400\nsteps:\n  - dwell: 1 min\n",
    );
    let can = format!("slcan:{}", sim.endpoint);
    let out = cli(&["run", recipe.to_str().unwrap(), "--can", &can], 3);
    assert_has(
        &out.stdout,
        &["FAIL  dwell 1m  drive fault: the drive reported node 1 EMCY 0x2310 continuous over-current (output side)"],
    );
}
