//! Data-driven recipe cases: every folder `tests/cases/<group>/<case>/` holds `recipe.yaml`
//! (and any files it includes), or a Rhai script `script.rhai` in its place, and `case.yaml`:
//!
//! ```yaml
//! exit: 0                      # expected exit code
//! args: [speed=4000rpm]        # --set overrides (optional)
//! physics: [response-time=200ms] # the simulated drive's `--sim` settings (optional)
//! sim: { trip_at: 12 s, drive_error: 4660, drop_replies: 1, fault_reset_blocked: true,
//!        ignore_commands: [disable_operation, shutdown], line_down: [10 s, 12 s],
//!        panic_at: 12 s, emergency_at: 12 s,   # emergency_at: an EMCY with drive_error,
//!                              # nothing trips
//!        replies_from: 12 s, garbage: 2, delay_replies: 1, delay_by: 2 s, # reply faults from
//!                              # a time on (garbage: line noise before the reply)
//!        silent: [12 s, 14 s] }  # the drive answers nothing (no heartbeat) while the line is up
//! stop_on_failure: true       # run -x (optional)
//! interrupt_at: 30 s           # a stop signal arrives at this (virtual) time (optional)
//! second_interrupt_at: 31 s    # and again (optional)
//! signal: TERM                 # which signal (default INT, i.e. Ctrl-C)
//! safe_stop: { stop_timeout: 5 s, reconnect_timeout: 3 s, fault_poll: 1 min }   # the run's --stop-timeout…
//! output: |                    # lines that must appear, in this order (substring of a line)
//!   PASSED
//! control_words: [0, 6, 7, 15, 7, 6]   # exactly the control words the drive received
//! control_words_end: [7, 6]            # or only the last ones (the safe stop)
//! control_word_changes: [6, 7, 15, 7, 6] # the same with repeats in a row counted once
//! unit: [serial=SP-104233]     # --unit (optional)
//! answers: [quiet=yes]         # --answer (optional)
//! answers_file: answers.yaml   # --answers, a file of the case (optional)
//! terminal: { lines: ["", yes], closes: true }  # a terminal the operator types these
//!                              # lines at, one per question; then end of input (closes)
//!                              # or nothing more (optional; without it, no terminal)
//! ```
//!
//! Every case runs in-process against the simulated drive in virtual time.

use crate::support::{control_words, InProcessRun};
use drivescript::clock::SharedClock;
use drivescript::drive::device_control::DeviceCommand;
use drivescript::run::SafeStopArgs;
use drivescript::sim::SimulatedDrive;
use drivescript::stop_request::{StopRequests, StopSignal};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Duration;

#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    exit: i32,
    #[serde(default)]
    args: Vec<String>,
    #[serde(default)]
    physics: Vec<String>,
    #[serde(default)]
    sim: Option<SimSetup>,
    /// `run -x`.
    #[serde(default)]
    stop_on_failure: bool,
    #[serde(default)]
    interrupt_at: Option<String>,
    /// A second Ctrl-C at this time.
    #[serde(default)]
    second_interrupt_at: Option<String>,
    #[serde(default)]
    signal: Option<String>,
    #[serde(default)]
    safe_stop: Option<SafeStopSetup>,
    #[serde(default)]
    output: String,
    #[serde(default)]
    control_words: Option<Vec<u16>>,
    #[serde(default)]
    control_words_end: Option<Vec<u16>>,
    /// Like `control_words`, with repeats of the same word in a row counted once: the
    /// cyclic channel sends the control word in every telegram.
    #[serde(default)]
    control_word_changes: Option<Vec<u16>>,
    #[serde(default)]
    control_word_changes_end: Option<Vec<u16>>,
    #[serde(default)]
    unit: Vec<String>,
    #[serde(default)]
    answers: Vec<String>,
    #[serde(default)]
    answers_file: Option<String>,
    #[serde(default)]
    terminal: Option<TerminalSetup>,
}

#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct TerminalSetup {
    lines: Vec<String>,
    closes: bool,
}

/// `NAME=VALUE` as a pair.
fn pair(text: &str) -> (String, String) {
    let (k, v) = text.split_once('=').expect("NAME=VALUE");
    (k.to_string(), v.to_string())
}

#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SimSetup {
    trip_at: Option<String>,
    drive_error: Option<u16>,
    drop_replies: Option<u32>,
    corrupt_checksum: Option<u32>,
    wrong_address: Option<u32>,
    fault_reset_blocked: Option<bool>,
    ignore_commands: Option<Vec<String>>,
    line_down: Option<[String; 2]>,
    panic_at: Option<String>,
    emergency_at: Option<String>,
    replies_from: Option<String>,
    garbage: Option<u32>,
    delay_replies: Option<u32>,
    delay_by: Option<String>,
    silent: Option<[String; 2]>,
}

#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SafeStopSetup {
    stop_timeout: Option<String>,
    reconnect_timeout: Option<String>,
    fault_poll: Option<String>,
}

fn duration(text: &str) -> Duration {
    humantime::parse_duration(text).unwrap_or_else(|e| panic!("bad duration {text}: {e}"))
}

fn cases() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/cases");
    let mut out = Vec::new();
    for group in std::fs::read_dir(&root).expect("tests/cases exists") {
        let group = group.expect("readable").path();
        if !group.is_dir() {
            continue;
        }
        for case in std::fs::read_dir(&group).expect("readable") {
            let case = case.expect("readable").path();
            if case.join("case.yaml").exists() {
                out.push(case);
            }
        }
    }
    out.sort();
    out
}

/// Runs one case; returns what was wrong with it, if anything.
fn run_case(dir: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(dir.join("case.yaml")).map_err(|e| e.to_string())?;
    let case: Case = serde_saphyr::from_str(&text).map_err(|e| format!("case.yaml: {e}"))?;
    let set: Vec<(String, String)> = case
        .args
        .iter()
        .map(|a| {
            let (k, v) = a.split_once('=').expect("args are NAME=VALUE");
            (k.to_string(), v.to_string())
        })
        .collect();
    let signal = match &case.signal {
        Some(name) => StopSignal::from_name(name).ok_or_else(|| format!("unknown signal {name}"))?,
        None => StopSignal::INT,
    };
    let stop = Arc::new(StopRequests::new());
    for at in [&case.interrupt_at, &case.second_interrupt_at]
        .into_iter()
        .flatten()
    {
        stop.schedule(duration(at), signal);
    }
    let mut safe_stop = SafeStopArgs::default();
    if let Some(s) = &case.safe_stop {
        safe_stop.stop_timeout = s.stop_timeout.as_deref().map(duration);
        safe_stop.reconnect_timeout = s.reconnect_timeout.as_deref().map(duration);
        safe_stop.fault_poll = s.fault_poll.as_deref().map(duration);
    }
    safe_stop.stop_on_failure = case.stop_on_failure;
    let sim_setup = case.sim.unwrap_or_default();
    let prepare = move |sim: &Arc<Mutex<dyn SimulatedDrive>>, _clock: &SharedClock| {
        let mut sim = sim.lock().expect("simulator lock");
        let f = sim.faults();
        if let Some(at) = &sim_setup.trip_at {
            f.trip_at(duration(at), sim_setup.drive_error.unwrap_or(1));
        }
        if let Some(n) = sim_setup.drop_replies {
            f.drop_replies(n);
        }
        if let Some(n) = sim_setup.corrupt_checksum {
            f.corrupt_checksum(n);
        }
        if let Some(n) = sim_setup.wrong_address {
            f.wrong_address(n);
        }
        if let Some(b) = sim_setup.fault_reset_blocked {
            f.fault_reset_blocked(b);
        }
        if let Some(names) = &sim_setup.ignore_commands {
            let commands: Vec<DeviceCommand> = names
                .iter()
                .map(|n| DeviceCommand::from_id(n).unwrap_or_else(|| panic!("unknown command {n}")))
                .collect();
            f.ignore_commands(&commands);
        }
        if let Some([from, until]) = &sim_setup.line_down {
            f.line_down(duration(from), duration(until));
        }
        if let Some(at) = &sim_setup.panic_at {
            f.panic_at(duration(at));
        }
        if let Some(at) = &sim_setup.emergency_at {
            f.emergency_at(duration(at), sim_setup.drive_error.unwrap_or(1));
        }
        if let Some(at) = &sim_setup.replies_from {
            f.replies_from(duration(at));
        }
        if let Some(n) = sim_setup.garbage {
            f.garbage(n);
        }
        if let Some(n) = sim_setup.delay_replies {
            f.delay_replies(
                n,
                sim_setup
                    .delay_by
                    .as_deref()
                    .map_or(Duration::from_secs(1), duration),
            );
        }
        if let Some([from, until]) = &sim_setup.silent {
            f.silent(duration(from), duration(until));
        }
    };
    let output_dir = std::env::temp_dir().join(format!(
        "drivescript-case-{}",
        dir.file_name().and_then(|n| n.to_str()).unwrap_or("x")
    ));
    // A script case runs the same way and is held to the same expectations.
    let file = match dir.join("script.rhai") {
        script if script.exists() => script,
        _ => dir.join("recipe.yaml"),
    };
    let mut run = InProcessRun::new(file);
    run.operator.unit = case.unit.iter().map(|u| pair(u)).collect();
    run.operator.answer = case.answers.iter().map(|a| pair(a)).collect();
    run.operator.answers = case.answers_file.as_ref().map(|f| dir.join(f));
    // The typing end stays open until the run is over unless the terminal closes.
    let mut _typing = None;
    if let Some(t) = &case.terminal {
        use std::io::Write;
        let (reader, mut writer) = std::io::pipe().map_err(|e| e.to_string())?;
        for line in &t.lines {
            writeln!(writer, "{line}").map_err(|e| e.to_string())?;
        }
        run.input = Some(drivescript::run::TerminalInput::of(reader));
        if !t.closes {
            _typing = Some(writer);
        }
    }
    run.connection.sim = case
        .physics
        .iter()
        .map(|p| drivescript::sim::SimSetting::parse(p).map_err(|e| format!("physics: {e}")))
        .collect::<Result<_, _>>()?;
    run.set = set;
    run.output_dir = output_dir;
    run.prepare = Some(&prepare);
    run.stop = stop.clone();
    run.safe_stop = safe_stop;
    let (result, output) = run.run();
    let mut problems = Vec::new();
    if result.exit_code != case.exit {
        problems.push(format!("exit code {} (expected {})", result.exit_code, case.exit));
    }
    // Expected lines must appear in order.
    let mut lines = output.lines();
    for want in case.output.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if !lines.any(|l| l.contains(want)) {
            problems.push(format!("missing (in order): {want}"));
            break;
        }
    }
    let words = control_words(&result);
    if let Some(want) = &case.control_words {
        if &words != want {
            problems.push(format!("control words {words:?} (expected {want:?})"));
        }
    }
    if let Some(want) = &case.control_words_end {
        if !words.ends_with(want) {
            problems.push(format!("control words {words:?} do not end with {want:?}"));
        }
    }
    let mut changes = words.clone();
    changes.dedup();
    if let Some(want) = &case.control_word_changes {
        if &changes != want {
            problems.push(format!("control word changes {changes:?} (expected {want:?})"));
        }
    }
    if let Some(want) = &case.control_word_changes_end {
        if !changes.ends_with(want) {
            problems.push(format!(
                "control word changes {changes:?} do not end with {want:?}"
            ));
        }
    }
    if let Some(problem) = step_count_problem(&output) {
        problems.push(problem);
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{}\n--- output ---\n{output}--- end ---",
            problems.join("\n")
        ))
    }
}

/// The summary's `N step(s)` counts the step lines printed above it (nested steps, each
/// pass of a repeat and `finally` included); `None` when they agree or there is no summary.
fn step_count_problem(output: &str) -> Option<String> {
    let said: u64 = output
        .lines()
        .find_map(|l| l.split_once(" step(s), ")?.0.rsplit(' ').next()?.parse().ok())?;
    let is_number = |w: &str| !w.is_empty() && w.chars().all(|c| c.is_ascii_digit() || c == '.');
    let printed = output
        .lines()
        .filter(|l| {
            let words: Vec<&str> = l.split_whitespace().take(3).collect();
            let mark = |w: &&str| *w == "ok" || *w == "FAIL";
            match words.as_slice() {
                [n, m, ..] if is_number(n) && mark(m) => true,
                [phase, n, m] => {
                    phase.chars().all(|c| c.is_ascii_lowercase() || c == '_') && is_number(n) && mark(m)
                }
                _ => false,
            }
        })
        .count() as u64;
    (said != printed).then(|| format!("the summary says {said} step(s); {printed} step lines were printed"))
}

#[test]
fn recipe_cases() {
    let all = cases();
    assert!(
        all.len() >= 10,
        "expected the recipe cases under tests/cases, found {}",
        all.len()
    );
    let mut failures = Vec::new();
    for dir in &all {
        if let Err(e) = run_case(dir) {
            failures.push(format!("== {}\n{e}", dir.display()));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        all.len(),
        failures.join("\n\n")
    );
}
