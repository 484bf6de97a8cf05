//! No signal ends the process around the safe stop: a file that reaches the file-size
//! limit (`ulimit -f`) and a closed standard output are write errors of the recorder and
//! the reporters, never a SIGXFSZ or SIGPIPE that kills the run before its drive is
//! stopped. The drive is asserted stopped by the run's own end line and exit code.
//! Unix only: these signals and `ulimit` are Unix's.
#![cfg(unix)]

use crate::support::{command, first_line_then_closed_pipe, repo_root, scratch};
use std::os::unix::process::ExitStatusExt;
use std::process::{Command, Stdio};

/// `drivescript ARGS` under a file-size limit of 1 KiB (`ulimit -f`), with its own
/// results store in `dir`.
fn limited(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    let bin = command().get_program().to_owned();
    let mut sh = Command::new("sh");
    sh.arg("-c")
        .arg("ulimit -f 2 && exec \"$0\" \"$@\"")
        .arg(bin)
        .args(args)
        .current_dir(repo_root())
        .env("DRIVESCRIPT_RESULTS", dir.join("results.sqlite"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    sh.output().expect("sh runs")
}

fn assert_ended_with_the_drive_stopped(output: &std::process::Output) {
    let out = String::from_utf8_lossy(&output.stdout);
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(
        output.status.signal(),
        None,
        "killed by a signal, beyond the safe stop:\n{out}\n{err}"
    );
    assert!(output.status.code().is_some(), "no exit code:\n{out}\n{err}");
    assert!(
        out.contains("drive left in ready to switch on at 0 rpm"),
        "the run's end line does not say the drive was stopped:\n{out}\n{err}"
    );
}

#[test]
fn a_csv_at_the_file_size_limit_is_a_write_error_and_the_drive_is_stopped() {
    let dir = scratch("ulimit-csv");
    let csv = dir.join("samples.csv");
    let output = limited(
        &dir,
        &[
            "run",
            "recipes/commissioning.yaml",
            "--fast",
            "--csv",
            &csv.to_string_lossy(),
        ],
    );
    assert_ended_with_the_drive_stopped(&output);
}

#[test]
fn a_results_store_at_the_file_size_limit_is_a_write_error_and_the_drive_is_stopped() {
    let dir = scratch("ulimit-store");
    let output = limited(&dir, &["run", "recipes/spindle-run-in.yaml", "--fast"]);
    assert_ended_with_the_drive_stopped(&output);
}

#[test]
fn a_closed_output_pipe_does_not_end_the_stop_command() {
    let (first, status) = first_line_then_closed_pipe(&["stop"]);
    assert_eq!(
        status.signal(),
        None,
        "killed by a signal during the stop: {first}"
    );
    assert_eq!(status.code(), Some(0), "{first}");
}
