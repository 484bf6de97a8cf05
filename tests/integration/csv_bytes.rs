//! The samples CSV of a run, long and wide, `--csv` and a step's own `csv:`, compared byte
//! for byte with files the same run wrote before the samples' text was made without the
//! formatting machinery (tests/csv/). Only the `utc` column differs from run to run; it is
//! compared as a time that moves with the `time [s]` column.

use crate::support::{cli, repo_root, scratch};
use std::path::Path;
use std::time::{Duration, SystemTime};

/// Each line with its `utc` cell (the second) left out, and the utc times.
fn without_utc(text: &str) -> (Vec<String>, Vec<SystemTime>) {
    let mut lines = Vec::new();
    let mut times = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut cells: Vec<&str> = line.split(',').collect();
        let utc = cells.remove(1);
        if i > 0 {
            times.push(humantime::parse_rfc3339(utc).unwrap_or_else(|e| panic!("{utc}: {e}")));
        }
        lines.push(cells.join(","));
    }
    (lines, times)
}

fn assert_same_bytes(written: &Path, kept: &str) {
    let text = std::fs::read_to_string(written).expect("written");
    let expected = std::fs::read_to_string(repo_root().join("tests/csv").join(kept)).expect("kept");
    assert!(
        text.ends_with('\n') && text.lines().count() == expected.lines().count(),
        "{kept}"
    );
    let (lines, times) = without_utc(&text);
    let (expected_lines, _) = without_utc(&expected);
    for (n, (line, want)) in lines.iter().zip(&expected_lines).enumerate() {
        assert_eq!(line, want, "{kept}, line {}", n + 1);
    }
    // The utc column: the run's wall time at its start plus `time [s]`, to the millisecond.
    let seconds: Vec<f64> = lines[1..]
        .iter()
        .map(|l| l.split(',').next().and_then(|t| t.parse().ok()).expect("time"))
        .collect();
    let start = |i: usize| times[i] - Duration::from_secs_f64(seconds[i]);
    for i in 1..times.len() {
        let apart = start(i).duration_since(start(0)).unwrap_or_else(|e| e.duration());
        assert!(apart <= Duration::from_millis(1), "{kept}, row {i}: {apart:?}");
    }
}

#[test]
fn samples_are_written_byte_for_byte_as_before_long_and_wide() {
    let recipe = repo_root().join("tests/csv/samples.yaml");
    let recipe = recipe.to_str().expect("utf-8");
    for (layout, csv, own, extra) in [
        ("long", "long.csv", "own.csv", None),
        ("wide", "wide.csv", "own-wide.csv", Some("--csv-wide")),
    ] {
        let dir = scratch(layout);
        let out = dir.to_str().expect("utf-8");
        let path = dir.join("run.csv");
        let mut args = vec![
            "run",
            recipe,
            "--fast",
            "--no-results",
            "--output-dir",
            out,
            "--csv",
            path.to_str().expect("utf-8"),
        ];
        args.extend(extra);
        cli(&args, 0);
        assert_same_bytes(&path, csv);
        assert_same_bytes(&dir.join("own.csv"), own);
    }
}
