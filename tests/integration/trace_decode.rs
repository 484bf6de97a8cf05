//! A `--trace` of every family read back: `decode FILE` and `decode < FILE` explain it
//! with no flag (the trace names its drive), an explicit flag still wins and the
//! contradiction is said; a CAN trace is a candump log that python-can's reader and a
//! can-utils style parse both read as it is.

use crate::support::{assert_has, cli, drivescript, scratch, stderr, stdout, write_file};
use drivescript::bus::CanFrame;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs a small reading recipe for `drive` on its simulated drive with `--trace`; the
/// trace's path.
fn traced_run(dir: &Path, drive: &str, objects: &str) -> PathBuf {
    let recipe = write_file(
        dir,
        &format!("{drive}.yaml"),
        &format!("name: Reading\ndrive: {drive}\nsteps:\n  - read: [{objects}]\nfinally: []\n"),
    );
    let trace = dir.join(format!("{drive}.trace"));
    cli(
        &[
            "run",
            recipe.to_str().unwrap(),
            "--drive",
            drive,
            "--fast",
            "--trace",
            trace.to_str().unwrap(),
        ],
        0,
    );
    trace
}

#[test]
fn decode_explains_a_trace_of_every_family_without_a_flag() {
    let dir = scratch("families");
    let families = [
        ("sd2", "ident", "read wide object (cmd 0x0d), PC (1) → drive 2"),
        (
            "ct-unidrive-sp",
            "ident",
            "request   read #11.29 ident of drive 1.1",
        ),
        ("lenze-931", "ident", "reply     device type 0931"),
        ("lenze-9400", "ident", "reply C00099 ident: segmented, 11 bytes"),
    ];
    for (drive, objects, explained) in families {
        let trace = traced_run(&dir, drive, objects);
        let by_name = drivescript(&["decode", trace.to_str().unwrap()], "");
        assert_eq!(by_name.status.code(), Some(0), "{drive}: {}", stderr(&by_name));
        assert_has(&stdout(&by_name), &[explained]);
        let text = std::fs::read_to_string(&trace).unwrap();
        let piped = drivescript(&["decode"], &text);
        assert_eq!(piped.status.code(), Some(0), "{drive}: {}", stderr(&piped));
        assert_eq!(stdout(&piped), stdout(&by_name), "{drive}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_explicit_protocol_wins_over_the_trace_and_the_contradiction_is_said() {
    let dir = scratch("contradiction");
    let trace = traced_run(&dir, "ct-unidrive-sp", "ident");
    let out = drivescript(&["decode", "--protocol", "sd2", trace.to_str().unwrap()], "");
    assert_eq!(
        out.status.code(),
        Some(1),
        "CT telegrams are not SD2: {}",
        stdout(&out)
    );
    assert_has(
        &stderr(&out),
        &[&format!(
            "{} is a trace of --drive ct-unidrive-sp, but its telegrams are explained as sd2",
            trace.display()
        )],
    );
    let agreeing = drivescript(&["decode", "--protocol", "ct-ansi", trace.to_str().unwrap()], "");
    assert_eq!(agreeing.status.code(), Some(0));
    assert_eq!(stderr(&agreeing), "");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Prints `ID#DATA` for each message python-can's candump-log reader finds in the file.
const PYTHON_CAN: &str = r#"
import sys, can
for m in can.CanutilsLogReader(sys.argv[1]):
    print("%03X#%s %s %.6f" % (m.arbitration_id, m.data.hex().upper(), m.channel, m.timestamp))
"#;

#[test]
fn a_can_trace_is_read_as_it_is_by_python_can_and_a_can_utils_parse() {
    let dir = scratch("python-can");
    let trace = traced_run(&dir, "lenze-9400", "ident, heatsink_temperature");
    let text = std::fs::read_to_string(&trace).unwrap();
    // As can-utils reads a log: `(seconds) interface frame`, `#` lines skipped.
    let mut frames = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let [stamp, interface, frame] = fields[..] else {
            panic!("not a candump log line: {line}");
        };
        let seconds = stamp.strip_prefix('(').and_then(|s| s.strip_suffix(')'));
        let seconds: f64 = seconds.and_then(|s| s.parse().ok()).expect(line);
        assert!(CanFrame::parse_text(frame).is_ok(), "{line}");
        frames.push(format!("{frame} {interface} {seconds:.6}"));
    }
    assert!(frames.len() >= 8, "{text}");
    if crate::support::python_imports(
        "can",
        "python-can is not installed (python3 -m pip install python-can)",
    ) {
        let read = Command::new("python3")
            .args(["-c", PYTHON_CAN, trace.to_str().unwrap()])
            .output()
            .expect("python3 runs");
        let err = String::from_utf8_lossy(&read.stderr);
        assert!(read.status.success(), "python-can: {err}");
        let read = String::from_utf8_lossy(&read.stdout);
        assert_eq!(read.lines().collect::<Vec<_>>(), frames, "{text}");
    }
    // The settings and the link events went next to it.
    let notes = std::fs::read_to_string(dir.join("lenze-9400.trace.meta")).unwrap();
    assert_has(&notes, &["# drive: lenze-9400", "# address: CAN node 1"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
