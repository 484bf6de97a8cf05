//! Record on the machine, replay at the desk: for every family a run recorded with
//! `--trace` against its simulated drive replays with `--replay` to the same checks; a
//! recipe changed to another setpoint fails naming the first telegram the capture never
//! answered, decoded; a wait_until polling at another period still passes; a candump log
//! written by hand in can-utils' format replays for the Lenze 9400; and `--replay` never
//! goes together with a real port.

use crate::support::{assert_has, cli, scratch, write_file};
use std::path::{Path, PathBuf};

/// A recipe for `drive` that enables, runs to `speed`, waits polling `every`, checks and
/// ends through the default safe stop.
fn spindle_recipe(dir: &Path, drive: &str, speed: u32, every: &str) -> PathBuf {
    let text = format!(
        "name: Replay check\ndrive: {drive}\nsteps:\n  - read: [status_word]\n  - set: {{ speed_setpoint: 0 rpm }}\n  - go_to: {{ state: operation_enabled, timeout: 2 s }}\n  - set: {{ speed_setpoint: {speed} rpm }}\n  - wait_until: {{ speed_actual: {{ near: {speed} rpm, within: 1 % }}, timeout: 10 s, every: {every} }}\n  - dwell: 1 s\n  - expect: {{ speed_actual: {{ near: {speed} rpm, within: 1 % }} }}\n"
    );
    write_file(dir, &format!("{drive}-{speed}-{every}.yaml"), &text)
}

/// The Lenze 9400's parameter recipe: `current` is its setpoint.
fn lenze_9400_recipe(dir: &Path, current: &str, every: &str) -> PathBuf {
    let text = format!(
        "name: Replay check\ndrive: lenze-9400\nsteps:\n  - read: [ident, product_type]\n  - set: {{ rated_motor_current: {current} A }}\n  - wait_until: {{ heatsink_temperature: {{ below: 80 }}, timeout: 5 s, every: {every} }}\n  - dwell: 300 ms\n  - expect: {{ rated_motor_current: {{ near: {current} A, within: 0.5 % }} }}\n"
    );
    write_file(dir, &format!("lenze-9400-{current}-{every}.yaml"), &text)
}

/// The check lines (`PASS …`, `FAIL …`) of a run's output.
fn checks(output: &str) -> Vec<String> {
    output
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("PASS") || l.starts_with("FAIL"))
        .map(str::to_string)
        .collect()
}

/// Records `recipe` against the simulated drive, replays it, and compares the checks.
fn record_and_replay(recipe: &Path, trace: &Path, extra: &[&str]) {
    let mut args = vec![
        "run",
        recipe.to_str().unwrap(),
        "--fast",
        "--trace",
        trace.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let recorded = cli(&args, 0).stdout;
    let replayed = replay(recipe, trace, extra, 0).stdout;
    let trace = trace.display();
    assert_has(
        &replayed,
        &[
            &format!("using a replay of {trace}"),
            "nothing is sent to any drive",
            "PASSED",
        ],
    );
    assert!(!checks(&recorded).is_empty(), "{recorded}");
    assert_eq!(checks(&recorded), checks(&replayed), "{recorded}\n{replayed}");
}

/// `drivescript run RECIPE --replay TRACE EXTRA…`, which must exit with `code`.
fn replay(recipe: &Path, trace: &Path, extra: &[&str], code: i32) -> crate::support::Ran {
    let mut args = vec![
        "run",
        recipe.to_str().unwrap(),
        "--replay",
        trace.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    cli(&args, code)
}

/// Replays `recipe` against `trace` and expects it to fail on `sent`, saying what the
/// capture had there (`had`).
fn replay_refuses(recipe: &Path, trace: &Path, extra: &[&str], sent: &str, had: &str) {
    let out = replay(recipe, trace, extra, 3).stdout;
    let refusal = out
        .lines()
        .find(|l| l.contains("never answered"))
        .unwrap_or_else(|| panic!("no refusal in\n{out}"));
    assert!(refusal.contains(sent), "{refusal}");
    assert!(
        refusal.contains(&format!("the capture had there {}", trace.display())),
        "{refusal}"
    );
    assert!(refusal.contains(had), "{refusal}");
}

/// The same recipe passes in replay, another poll period too; another setpoint fails.
fn spindle_family(drive: &str, extra: &[&str], sent: &str, had: &str) {
    let dir = scratch(drive);
    let trace = dir.join(format!("{drive}.trace"));
    record_and_replay(&spindle_recipe(&dir, drive, 3000, "100ms"), &trace, extra);
    for every in ["40ms", "300ms"] {
        let recipe = spindle_recipe(&dir, drive, 3000, every);
        assert_has(&replay(&recipe, &trace, extra, 0).stdout, &["PASSED"]);
    }
    replay_refuses(
        &spindle_recipe(&dir, drive, 4000, "100ms"),
        &trace,
        extra,
        sent,
        had,
    );
}

#[test]
fn sd2_records_and_replays() {
    spindle_family(
        "sd2",
        &[],
        "(write object 395 speed_setpoint = 4000 rpm)",
        "(write object 395 speed_setpoint = 3000 rpm)",
    );
}

#[test]
fn ct_unidrive_sp_records_and_replays() {
    spindle_family(
        "ct-unidrive-sp",
        &[],
        "speed_setpoint = 4000.0 rpm",
        "speed_setpoint = 3000.0 rpm",
    );
}

#[test]
fn lenze_931_records_and_replays() {
    let dir = scratch("lenze-931-dictionary");
    let dictionary = crate::lenze_931::completed_template(&dir);
    let dictionary = dictionary.to_str().unwrap();
    spindle_family(
        "lenze-931",
        &["--dictionary", dictionary],
        "speed_setpoint",
        "speed_setpoint",
    );
}

#[test]
fn lenze_9400_records_and_replays() {
    let dir = scratch("lenze-9400");
    let trace = dir.join("lenze-9400.log");
    record_and_replay(&lenze_9400_recipe(&dir, "10.2", "100ms"), &trace, &[]);
    // A CAN trace is a pure candump log.
    let log = std::fs::read_to_string(&trace).unwrap();
    assert!(
        log.lines().all(|l| l.starts_with('(') && l.contains(" can0 ")),
        "{log}"
    );
    for every in ["30ms", "1s"] {
        let recipe = lenze_9400_recipe(&dir, "10.2", every);
        assert_has(&replay(&recipe, &trace, &[], 0).stdout, &["PASSED"]);
    }
    replay_refuses(
        &lenze_9400_recipe(&dir, "8.5", "100ms"),
        &trace,
        &[],
        "rated_motor_current",
        "rated_motor_current",
    );
}

/// One case under `tests/cases/replay/<case>/`: `recipe.yaml`, a capture, and
/// `replay.yaml` with what the replay must give.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ReplayCase {
    /// The capture, relative to the case [default: the case's `capture.trace` or
    /// `capture.log`].
    #[serde(default)]
    capture: Option<String>,
    exit: i32,
    /// More command-line arguments (`--set speed=4000rpm`).
    #[serde(default)]
    args: Vec<String>,
    /// Lines that must appear, in this order (each a substring of a line).
    output: String,
}

/// Every case folder under `tests/cases/replay/`: replayed with `run --replay`, its exit
/// code and its output lines in order as `replay.yaml` says.
#[test]
fn replay_cases() {
    let root = crate::support::repo_root().join("tests/cases/replay");
    let mut cases: Vec<PathBuf> = std::fs::read_dir(&root)
        .expect("tests/cases/replay exists")
        .map(|e| e.expect("readable").path())
        .filter(|p| p.join("replay.yaml").exists())
        .collect();
    cases.sort();
    assert!(
        cases.len() >= 5,
        "expected the replay cases, found {}",
        cases.len()
    );
    let failures: Vec<String> = cases.iter().filter_map(|dir| replay_case(dir).err()).collect();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

fn replay_case(dir: &Path) -> Result<(), String> {
    let name = dir.display();
    let text = std::fs::read_to_string(dir.join("replay.yaml")).map_err(|e| format!("{name}: {e}"))?;
    let case: ReplayCase = serde_saphyr::from_str(&text).map_err(|e| format!("{name}/replay.yaml: {e}"))?;
    let capture = match &case.capture {
        Some(c) => dir.join(c),
        None => ["capture.trace", "capture.log"]
            .iter()
            .map(|f| dir.join(f))
            .find(|p| p.exists())
            .ok_or_else(|| format!("{name}: no capture.trace or capture.log"))?,
    };
    let recipe = dir.join("recipe.yaml");
    let mut args = vec![
        "run",
        recipe.to_str().unwrap_or(""),
        "--replay",
        capture.to_str().unwrap_or(""),
    ];
    args.extend(case.args.iter().map(String::as_str));
    let out = crate::support::drivescript(&args, "");
    let text = format!("{}{}", crate::support::stdout(&out), crate::support::stderr(&out));
    if out.status.code() != Some(case.exit) {
        return Err(format!(
            "{name}: exit {:?}, expected {}\n{text}",
            out.status.code(),
            case.exit
        ));
    }
    // Several wanted parts may stand on one line, in order.
    let lines: Vec<&str> = text.lines().collect();
    let mut at = 0;
    for wanted in case.output.lines().map(str::trim).filter(|l| !l.is_empty()) {
        match lines[at..].iter().position(|l| l.contains(wanted)) {
            Some(i) => at += i,
            None => return Err(format!("{name}: `{wanted}` missing (or out of order) in\n{text}")),
        }
    }
    Ok(())
}

/// Records `recipe` against its simulated drive into `trace`.
fn record(recipe: &Path, trace: &Path) {
    cli(
        &[
            "run",
            recipe.to_str().unwrap(),
            "--fast",
            "--trace",
            trace.to_str().unwrap(),
        ],
        0,
    );
}

/// A short SD2 recipe, recorded against the simulated drive; the recipe and its trace.
fn recorded_identity(dir: &Path) -> (PathBuf, PathBuf) {
    let recipe = write_file(
        dir,
        "identity.yaml",
        "name: Identity\ndrive: sd2\nsteps:\n  - read: [ident, status_word, bus_voltage]\n  - expect: { bus_voltage: { between: [300 V, 350 V] } }\n",
    );
    let trace = dir.join("identity.trace");
    record(&recipe, &trace);
    (recipe, trace)
}

#[test]
fn a_capture_served_on_a_pty_and_tcp_answers_like_the_drive() {
    let dir = scratch("served");
    let (recipe, trace) = recorded_identity(&dir);
    let (recipe, trace) = (recipe.to_str().unwrap(), trace.to_str().unwrap());
    let pty = crate::support::Simulator::pty(&["--replay", trace]);
    assert_has(
        &pty.cli(&["run", recipe], 0).stdout,
        &["ident = \"Test Motor\"", "PASSED"],
    );
    // What the capture never answered gets no reply.
    let other = write_file(
        &dir,
        "other.yaml",
        "name: Other\ndrive: sd2\nsteps:\n  - read: [speed_setpoint]\n",
    );
    let out = pty.cli(&["run", other.to_str().unwrap(), "--timeout", "200ms"], 3);
    assert_has(&format!("{}{}", out.stdout, out.stderr), &["no reply"]);
    let tcp = crate::support::Simulator::start(&["--replay", trace, "--tcp", "127.0.0.1:0"]);
    assert_has(
        &cli(&["run", recipe, "--tcp", &tcp.endpoint], 0).stdout,
        &["PASSED"],
    );
}

#[test]
fn a_hand_written_candump_log_is_served_behind_an_slcan_pty() {
    let case = crate::support::repo_root().join("tests/cases/replay/lenze_9400_candump_by_hand");
    let log = case.join("capture.log");
    let sim = crate::support::Simulator::start(&[
        "--replay",
        log.to_str().unwrap(),
        "--drive",
        "lenze-9400",
        "--slcan-pty",
    ]);
    let recipe = case.join("recipe.yaml");
    let can = format!("slcan:{}", sim.endpoint);
    let out = cli(&["run", recipe.to_str().unwrap(), "--can", &can], 0).stdout;
    assert_has(&out, &["heatsink_temperature = 41", "PASSED"]);
}

#[test]
fn replay_refuses_a_real_port_a_bad_capture_and_another_familys_capture() {
    let dir = scratch("refusals");
    let (recipe, trace) = recorded_identity(&dir);
    let (recipe_path, trace) = (recipe.to_str().unwrap(), trace.to_str().unwrap());
    for port in [
        ["--port", "/dev/null"],
        ["--tcp", "127.0.0.1:9"],
        ["--can", "slcan:/dev/null"],
    ] {
        let err = cli(&["run", recipe_path, "--replay", trace, port[0], port[1]], 2).stderr;
        assert_has(&err, &["'--replay <CAPTURE>' cannot be used with"]);
    }
    let bad = write_file(
        &dir,
        "bad.trace",
        "# drive: sd2\n    0.000000 TX 00 09 02 01 0d 16 00 00 00 00 00 d0\n    0.0001 RX 00 zz\n",
    );
    let err = cli(&["run", recipe_path, "--replay", bad.to_str().unwrap()], 2).stderr;
    assert_has(&err, &["bad.trace:3: the telegram `00 zz`"]);
    let can = crate::support::repo_root().join("tests/cases/replay/lenze_9400_candump_by_hand/capture.log");
    let err = cli(&["run", recipe_path, "--replay", can.to_str().unwrap()], 2).stderr;
    assert_has(&err, &["holds no request to replay"]);
    let dir9400 = scratch("refusals-9400");
    let recipe9400 = lenze_9400_recipe(&dir9400, "10.2", "100ms");
    let log = dir9400.join("run.log");
    record(&recipe9400, &log);
    let err = cli(&["run", recipe_path, "--replay", log.to_str().unwrap()], 2).stderr;
    assert_has(
        &err,
        &["is a capture of --drive lenze-9400 (the lenze-9400 family), not of the sd2 family"],
    );
}

#[test]
fn an_anonymised_capture_masks_the_drives_strings_and_still_replays() {
    let dir = scratch("anonymised");
    let case = crate::support::repo_root().join("tests/cases/replay/sd2_commissioning");
    let copy = dir.join("shared.trace");
    let (capture, copy_text) = (case.join("capture.trace"), copy.to_str().unwrap());
    assert_has(
        &cli(&["anonymise", capture.to_str().unwrap(), "-o", copy_text], 0).stdout,
        &["2 reply(ies) masked"],
    );
    let text = std::fs::read_to_string(&copy).unwrap();
    assert!(
        !text.contains("Test Motor") && !text.contains("54 65 73 74"),
        "{text}"
    );
    let recipe = case.join("recipe.yaml");
    let out = cli(&["run", recipe.to_str().unwrap(), "--replay", copy_text], 0).stdout;
    assert_has(&out, &["ident = \"XXXX XXXXX\"", "PASSED"]);
    // A CAN trace: its frames and its notes file, the strings spread over SDO segments.
    let recipe = lenze_9400_recipe(&dir, "10.2", "100ms");
    let (log, shared) = (dir.join("run.log"), dir.join("shared.log"));
    record(&recipe, &log);
    cli(
        &["anonymise", log.to_str().unwrap(), "-o", shared.to_str().unwrap()],
        0,
    );
    assert!(dir.join("shared.log.meta").is_file());
    let out = replay(&recipe, &shared, &[], 0).stdout;
    assert_has(
        &out,
        &["product_type = \"XXXXXXXXX 0000 XXXXXXXX XXX\"", "PASSED"],
    );
    let err = cli(&["anonymise", copy_text, "-o", copy_text], 2).stderr;
    assert_has(&err, &["is the capture itself"]);
}

/// The hand-written candump log is in can-utils' exact format: python-can's reader of
/// candump logs takes every line of it.
#[test]
fn the_hand_written_candump_log_is_read_by_python_can() {
    let log = crate::support::repo_root().join("tests/cases/replay/lenze_9400_candump_by_hand/capture.log");
    let text = std::fs::read_to_string(&log).unwrap();
    let script = "import sys, can\nfor m in can.CanutilsLogReader(sys.argv[1]):\n    print('%03X#%s' % (m.arbitration_id, 'R' if m.is_remote_frame else m.data.hex().upper()))\n";
    let read = std::process::Command::new("python3")
        .args(["-c", script, log.to_str().unwrap()])
        .output();
    match read {
        Ok(out) if out.status.success() => {
            let frames: Vec<&str> = text.lines().filter_map(|l| l.split_whitespace().nth(2)).collect();
            let stdout = String::from_utf8_lossy(&out.stdout);
            assert_eq!(stdout.lines().collect::<Vec<_>>(), frames);
        }
        _ => crate::support::tool_missing("python-can is not installed (python3 -m pip install python-can)"),
    }
}

/// One run, one truth: a link reopened during the safe stop does not tell the drive's
/// state (a replay answers it from wherever the capture stood); the state is told once,
/// by the end line, from what the stop read back at its end.
#[test]
fn a_replay_tells_the_drive_state_once_from_what_the_stop_read_back() {
    let dir = crate::support::repo_root().join("tests/cases/replay/sd2_capture_ends_before_the_stop");
    let ran = replay(&dir.join("recipe.yaml"), &dir.join("capture.trace"), &[], 3);
    let text = format!("{}{}", ran.stdout, ran.stderr);
    assert_has(
        &text,
        &["restored at attempt 1", "drive left in operation enabled"],
    );
    assert!(!text.contains("; the drive reports "), "{text}");
}
