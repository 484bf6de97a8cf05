//! The Lenze 931 family end to end: the dictionary template completed with the simulated
//! drive's object numbers runs the shipped commissioning recipe with only `drive:`
//! changed; limited writes warn with the stored value and later checks see it; the
//! drive's own limits refuse an out-of-range recipe before anything moves; without a
//! profile `check` refuses device control; the safe stop on a stop signal, a lost line and
//! a drive that ignores commands; and a real pseudo-terminal with `simulate --pty`.

use crate::support::{
    assert_exit, assert_has, assert_lacks, cli, control_words, drivescript, faults_before_the_run, repo_root,
    scratch, scratch_file, stderr, stdout, write_file, InProcessRun,
};
use drivescript::clock::SharedClock;
use drivescript::drive::{DeviceCommand, DeviceState};
use drivescript::family::lenze_931::LenzeSimulator;
use drivescript::run::DictionaryArgs;
use drivescript::sim::SimulatedDrive;
use drivescript::stop_request::{StopRequests, StopSignal};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// The simulated 931's object numbers (see `src/family/lenze_931/sim/sim_objects.rs`).
const SIM_NUMBERS: &[(&str, &str)] = &[
    ("rs232_stat_sum", "0x0001"),
    ("speed_setpoint", "0x0010"),
    ("speed_actual", "0x0011"),
    ("current_actual", "0x0012"),
    ("bus_voltage", "0x0013"),
    ("operating_mode", "0x0014"),
    ("control_word", "0x0020"),
    ("status_word", "0x0021"),
    ("drive_error", "0x0022"),
];

/// What a user does with the template in `dictionary/lenze-931.yaml`: copy the lines
/// between the markers, remove the `# `, fill in every `0x????`.
pub(crate) fn completed_template(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repo_root().join("dictionary/lenze-931.yaml")).expect("dictionary");
    let lines: Vec<&str> = text.lines().collect();
    let start = lines
        .iter()
        .position(|l| *l == "# --- template: copy from here ---")
        .expect("start marker");
    let end = lines
        .iter()
        .position(|l| *l == "# --- template end ---")
        .expect("end marker");
    let mut out = String::new();
    let mut name = "";
    let mut unconfirmed = 0;
    for line in &lines[start + 1..end] {
        let line = line.strip_prefix("# ").unwrap_or(line.trim_start_matches('#'));
        if let Some(n) = line.trim().strip_prefix("- name:") {
            name = SIM_NUMBERS
                .iter()
                .find(|(k, _)| *k == n.trim())
                .map(|(k, _)| *k)
                .unwrap_or_else(|| panic!("template object {n} has no simulated number"));
        }
        if line.trim().starts_with("unconfirmed:") {
            unconfirmed += 1;
        }
        let number = SIM_NUMBERS
            .iter()
            .find(|(k, _)| *k == name)
            .map_or("", |(_, v)| *v);
        out.push_str(&line.replace("\"0x????\"", &format!("\"{number}\"")));
        out.push('\n');
    }
    assert_eq!(
        unconfirmed,
        SIM_NUMBERS.len(),
        "every template entry says it is unconfirmed"
    );
    assert!(!out.contains("0x????"));
    let path = dir.join("my-931.yaml");
    std::fs::write(&path, out).expect("write the completed template");
    path
}

pub(crate) fn dictionary_args(extra: Option<PathBuf>) -> DictionaryArgs {
    DictionaryArgs {
        name: "lenze-931".into(),
        extra: extra.into_iter().collect(),
        ..DictionaryArgs::builtin_default()
    }
}

/// `recipes/commissioning.yaml` with only `drive:` changed.
/// A run of `recipe` on the simulated 931, with the dictionary template completed in `dir`.
fn on_931<'a>(recipe: impl Into<PathBuf>, dir: &Path) -> InProcessRun<'a> {
    let mut run = InProcessRun::new(recipe);
    run.dictionary = dictionary_args(Some(completed_template(dir)));
    run
}

/// `f` with the simulated 931 behind `sim`.
pub(crate) fn with_lenze<T>(
    sim: &Arc<Mutex<dyn SimulatedDrive>>,
    f: impl FnOnce(&mut LenzeSimulator) -> T,
) -> T {
    let mut sim = sim.lock().unwrap_or_else(PoisonError::into_inner);
    f(sim
        .as_any_mut()
        .downcast_mut::<LenzeSimulator>()
        .expect("a simulated 931"))
}

fn commissioning_for_931(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repo_root().join("recipes/commissioning.yaml")).expect("recipe");
    assert!(text.contains("drive: sd2"));
    let path = dir.join("commissioning-931.yaml");
    std::fs::write(&path, text.replace("drive: sd2", "drive: lenze-931")).expect("write recipe");
    path
}

#[test]
fn the_commissioning_recipe_runs_on_the_simulated_931_with_only_drive_changed() {
    let dir = scratch("commissioning");
    let recipe = commissioning_for_931(&dir);
    let trace = dir.join("run.trace");
    let mut run = on_931(recipe, &dir);
    let (result, output, trace_text) = run.run_traced(&trace, 0, &[]);
    // The trace shows each line as text with its meaning, and decode reads it back.
    assert_has(
        &trace_text,
        &["# OW:0020:0000000F write object 0x0020 control_word; 15 (0x0000000F)"],
    );
    let out = drivescript(&["decode", "--protocol", "lenze-931"], &trace_text);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_has(
        &stdout(&out),
        &["request   write object 0x0020\n  value     15 (0x0000000F)"],
    );
    // With the user's dictionary, decode names the objects and the status bits.
    let extra = completed_template(&dir).to_string_lossy().to_string();
    let text = cli(
        &[
            "decode",
            "--drive",
            "lenze-931",
            "--dictionary",
            &extra,
            "OR:0001",
            "0001:0000A000",
        ],
        0,
    )
    .stdout;
    assert_has(
        &text,
        &[
            "request   read object 0x0001 rs232_stat_sum",
            "status    13 speed = 0 ± hysteresis, 15 ready for operation",
        ],
    );
    assert_has(
        &output,
        &[
            "using the built-in simulated",
            "ident = \"0931\"",
            "drive left in ready to switch on at 0 rpm",
        ],
    );
    assert_eq!(control_words(&result), vec![6, 7, 15, 7, 6]);
}

#[test]
fn a_limited_write_warns_with_the_stored_value_and_expect_sees_it() {
    // A literal beyond the drive's limits is refused before the run (see below), so the
    // limited write is reached with a value the script computes.
    let script = "//! drive: lenze-931\nlet d = drive();\nlet high = 4000.0 * 2.0;\nd.set(\"speed_setpoint\", high, \"rpm\");\nlet stored = d.read(\"speed_setpoint\");\nexpect(\"speed_setpoint equals 6000 rpm\", stored == 6000.0, stored);\nd.set(\"speed_setpoint\", 0.0, \"rpm\");\n";
    let output = assert_exit(
        script_on_931("limited", script),
        0,
        &[
            "warning: speed_setpoint = 8000 rpm was limited by the drive, which stored 6000 rpm (read back)",
            "PASS  speed_setpoint equals 6000 rpm",
        ],
    );
    assert_lacks(&output, &["FAIL"]);
}

#[test]
fn a_value_the_drive_refuses_names_the_drives_limit() {
    let script =
        "//! drive: lenze-931\nlet d = drive();\nlet mode = 3 + 4;\nd.set(\"operating_mode\", mode);\n";
    assert_exit(
        script_on_931("refused", script),
        3,
        &["0x00000003 value too high, not written; the drive's maximum is 3 (0x00000003, read with OX:0014)"],
    );
}

type SharedSim = Arc<Mutex<dyn SimulatedDrive>>;

/// Writes `text` to the file `file` of a fresh scratch folder `name` and runs it as
/// [`run_and_record`] does.
#[track_caller]
fn file_on_931(name: &str, file: &str, text: &str) -> (i32, String, Vec<String>) {
    let (dir, path) = scratch_file(name, file, text);
    run_and_record(&dir, path)
}

/// Runs the script `text` (as `NAME.rhai`) on the simulated 931: its exit code and output.
#[track_caller]
fn script_on_931(name: &str, text: &str) -> (i32, String) {
    let (code, output, _) = file_on_931(name, &format!("{name}.rhai"), text);
    (code, output)
}

/// [`file_on_931`] of a file refused before anything moves (exit 2): the output and the
/// requests the drive received.
#[track_caller]
pub(crate) fn refused_on_931(name: &str, file: &str, text: &str) -> (String, Vec<String>) {
    let (code, output, requests) = file_on_931(name, file, text);
    assert_eq!(code, 2, "{output}");
    (output, requests)
}

/// Runs `path` on the simulated 931 (with the completed template) and returns the exit
/// code, the output and every request line the drive received, in order.
pub(crate) fn run_and_record(dir: &Path, path: PathBuf) -> (i32, String, Vec<String>) {
    let captured: Arc<Mutex<Option<SharedSim>>> = Arc::new(Mutex::new(None));
    let keep = captured.clone();
    let prepare = move |sim: &Arc<Mutex<dyn SimulatedDrive>>, _: &SharedClock| {
        *keep.lock().unwrap_or_else(PoisonError::into_inner) = Some(sim.clone());
    };
    let mut run = on_931(path, dir);
    run.prepare = Some(&prepare);
    let (result, output) = run.run();
    let sim = captured
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .clone()
        .expect("the drive was opened");
    let requests = with_lenze(&sim, |lenze| lenze.requests().to_vec());
    (result.exit_code, output, requests)
}

#[test]
fn a_run_outside_the_drives_limits_is_refused_before_any_write_telegram() {
    let (output, requests) = refused_on_931(
        "run-limits",
        "outside.yaml",
        "name: Outside\ndrive: lenze-931\nsteps:\n  - read: [ident]\n  - set: { operating_mode: 2 }\n  - set: { speed_setpoint: 8000 rpm }\n  - ramp: { object: speed_setpoint, from: -7000 rpm, to: 0 rpm, rate: 1000 rpm/s }\nfinally:\n  - set: { speed_setpoint: 0 rpm }\n",
    );
    // Each object written is asked for its limits once, and nothing else is sent.
    assert_eq!(requests, ["ON:0014", "OX:0014", "ON:0010", "OX:0010"], "{output}");
    assert_has(&output, &["drive limits of speed_setpoint: -6000 rpm .. 6000 rpm (read from the 931 on", "outside.yaml:6:5: set speed_setpoint = 8000 rpm is above the maximum the drive reports, 6000 rpm", "outside.yaml:7:5: ramp speed_setpoint = -7000 rpm is below the minimum the drive reports, -6000 rpm", "error: 2 value(s) of ", "nothing was sent to move the drive. Lower the value, or change the drive's limit first"]);
    assert_lacks(&output, &["PASSED"]);

    // A script's literal values are compared the same way, at their place.
    let (output, requests) = refused_on_931(
        "run-limits-script",
        "outside.rhai",
        "//! drive: lenze-931\nlet d = drive();\nd.set(\"operating_mode\", 9);\nd.set(\"speed_setpoint\", 100.0, \"rpm\");\n",
    );
    assert_eq!(requests, ["ON:0014", "OX:0014", "ON:0010", "OX:0010"], "{output}");
    assert_has(
        &output,
        &["outside.rhai:3:25: set operating_mode = 9 is above the maximum the drive reports, 3"],
    );
}

#[test]
fn a_run_within_the_drives_limits_reads_them_first_and_passes() {
    let (code, output, requests) = file_on_931(
        "run-within",
        "within.yaml",
        "name: Within\ndrive: lenze-931\nsteps:\n  - set: { speed_setpoint: 5000 rpm }\n  - ramp: { object: speed_setpoint, from: 5000 rpm, to: -6000 rpm, rate: 10000 rpm/s }\n  - expect: { speed_setpoint: { equals: -6000 rpm } }\nfinally:\n  - set: { speed_setpoint: 0 rpm }\n",
    );
    assert_eq!(code, 0, "{output}");
    // The limits are read first, before the run's own reads (the identity) and writes.
    assert_eq!(requests[..2], ["ON:0010", "OX:0010"], "{output}");
    let first_write = requests
        .iter()
        .position(|r| r.starts_with("OW:"))
        .expect("a write");
    assert_eq!(requests[first_write], "OW:0010:00001388", "{requests:?}");
    assert!(!requests[2..]
        .iter()
        .any(|r| r.starts_with("ON:") || r.starts_with("OX:")));
    assert_lacks(&output, &["warning"]);
    assert_has(
        &output,
        &["drive limits of speed_setpoint: -6000 rpm .. 6000 rpm", "PASSED"],
    );
}

#[test]
fn without_a_profile_check_refuses_device_commands_and_states_saying_what_to_add() {
    let (dir, recipe) = scratch_file(
        "no-profile",
        "control.yaml",
        "name: Needs control\ndrive: lenze-931\nsteps:\n  - read: [ident]\n  - shutdown\n  - go_to: operation_enabled\n  - wait_until: { state: switched_on, timeout: 1 s }\nfinally: []\n",
    );
    let path = recipe.to_string_lossy().to_string();
    let err = cli(&["check", &path, "--drive", "lenze-931"], 2).stderr;
    assert_has(
        &err,
        &[
            "`shutdown` needs device control, but the lenze-931 dictionary has no `profile:`",
            "the state `operation_enabled` needs device control",
            "the state `switched_on` needs device control",
            "add a `profile:` to a dictionary file given with --dictionary FILE",
            "3 problems found",
        ],
    );
    // The same recipe with the completed template (which has a profile) passes.
    let extra = completed_template(&dir).to_string_lossy().to_string();
    cli(
        &["check", &path, "--drive", "lenze-931", "--dictionary", &extra],
        0,
    );
}

/// Runs the commissioning recipe in `dir` on the simulated 931 with `prepare` and a stop
/// request.
fn run_with(
    dir: &Path,
    prepare: &drivescript::run::PrepareSimulator,
    stop: Arc<StopRequests>,
) -> (i32, String, Arc<Mutex<dyn SimulatedDrive>>) {
    let mut run = on_931(commissioning_for_931(dir), dir);
    run.prepare = Some(prepare);
    run.stop = stop;
    let (result, output) = run.run();
    let sim = result
        .simulator
        .unwrap_or_else(|| panic!("the run did not start: {output}"));
    (result.exit_code, output, sim)
}

#[test]
fn sigint_during_a_run_stops_the_simulated_931_and_verifies_it() {
    let dir = scratch("sigint");
    let stop = Arc::new(StopRequests::new());
    stop.schedule(Duration::from_secs(4), StopSignal::INT);
    let (code, output, sim) = run_with(&dir, &|_, _: &SharedClock| {}, stop);
    assert_eq!(code, 130, "{output}");
    assert_has(
        &output,
        &[
            "INTERRUPTED: interrupted by Ctrl-C (SIGINT)",
            "FAIL  dwell 5s  interrupted",
        ],
    );
    // The safe stop brakes the spindle before the recipe's own finally disables it.
    assert_has(
        &output,
        &[
            "brake 2  ok    wait for standstill: speed_actual within ±10 rpm",
            "drive left in ready to switch on at 0 rpm",
        ],
    );
    assert_lacks(&output, &["STILL COASTING"]);
    let sim = sim.lock().unwrap_or_else(PoisonError::into_inner);
    assert_eq!(sim.state(), DeviceState::ReadyToSwitchOn);
    assert_eq!(sim.control_words_written(), vec![6, 7, 15, 7, 6]);
}

#[test]
fn a_931_that_ignores_the_stop_commands_is_escalated_and_reported() {
    let dir = scratch("disobeys");
    let prepare = faults_before_the_run(|f| {
        f.ignore_commands(&[
            DeviceCommand::DisableOperation,
            DeviceCommand::Shutdown,
            DeviceCommand::QuickStop,
            DeviceCommand::DisableVoltage,
        ])
    });
    let (code, output, _) = run_with(&dir, &prepare, Arc::new(StopRequests::new()));
    assert_eq!(code, 3, "{output}");
    assert_has(
        &output,
        &[
            "it did not obey; escalating to quick stop",
            "CHECK THE DRIVE BY HAND",
        ],
    );
}

#[test]
fn a_lost_line_to_the_931_ends_in_the_truth() {
    let dir = scratch("line-lost");
    let recipe = commissioning_for_931(&dir);
    let prepare = faults_before_the_run(|f| f.line_down(Duration::from_secs(4), Duration::from_secs(36_000)));
    let mut run = on_931(&recipe, &dir);
    run.prepare = Some(&prepare);
    run.safe_stop.reconnect_timeout = Some(Duration::from_secs(2));
    run.run_expecting(3, &["CHECK THE DRIVE BY HAND", "drive left in an unknown state"]);
}

/// Under Wine the pseudo-terminal is a COM port (served by the Linux side).
#[test]
fn through_a_pseudo_terminal_raw_access_drive_limits_and_a_run() {
    let sim = crate::support::Simulator::start(&["--drive", "lenze-931", "--pty"]);
    let port = sim.endpoint.as_str();
    assert!(
        port.starts_with(if cfg!(windows) { "COM" } else { "/dev/" }),
        "{port}"
    );
    let dir = scratch("pty");
    let dictionary = completed_template(&dir).to_string_lossy().to_string();

    // Raw access without a dictionary entry: signed 32-bit and hex.
    cli(
        &["write", "0x0010", "-3000", "--drive", "lenze-931", "--port", port],
        0,
    );
    let text = cli(
        &["read", "0x0010", "TYPE?", "--drive", "lenze-931", "--port", port],
        0,
    )
    .stdout;
    assert_has(&text, &["0xfffff448", "-3000", "\"0931\""]);
    // A CANopen object through the SDO simulation: the status word, little-endian bytes.
    let out = drivescript(
        &[
            "read",
            "sdo:0x6041/0",
            "--type",
            "u16",
            "--drive",
            "lenze-931",
            "--port",
            port,
            "--json",
        ],
        "",
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("json");
    assert_eq!(json[0]["raw"], "576", "0x0240: switch on disabled");

    // The drive's limits refuse an out-of-range recipe before anything moves.
    let recipe = commissioning_for_931(&dir).to_string_lossy().to_string();
    let base = [
        "--drive",
        "lenze-931",
        "--dictionary",
        dictionary.as_str(),
        "--port",
        port,
    ];
    let mut args = vec!["check", recipe.as_str(), "--set", "speed=8000rpm"];
    args.extend(base);
    let out = cli(&args, 2);
    let err = out.stderr;
    assert_has(
        &err,
        &[
            "set speed_setpoint = 8000 rpm is above the maximum the drive reports, 6000 rpm",
            "nothing was sent to move the drive",
        ],
    );
    assert_has(
        &out.stdout,
        &["drive limits of speed_setpoint: -6000 rpm .. 6000 rpm"],
    );
    // `run` compares the same way before anything moves, and so does `check` for a
    // script's literal values.
    let mut args = vec!["run", recipe.as_str(), "--set", "speed=8000rpm"];
    args.extend(base);
    let out = cli(&args, 2);
    assert_has(
        &out.stderr,
        &["set speed_setpoint = 8000 rpm is above the maximum the drive reports, 6000 rpm"],
    );
    assert_lacks(&out.stdout, &["recipe  "]);
    let refused_by_check = |file: PathBuf| {
        let file = file.to_string_lossy().to_string();
        let mut args = vec!["check", file.as_str()];
        args.extend(base);
        cli(&args, 2).stderr
    };
    let script = write_file(
        &dir,
        "fast.rhai",
        "//! drive: lenze-931\nlet d = drive();\nd.set(\"speed_setpoint\", 6500.0, \"rpm\");\n",
    );
    assert_has(
        &refused_by_check(script),
        &["fast.rhai:3:25: set speed_setpoint = 6500 rpm is above the maximum the drive reports, 6000 rpm"],
    );
    // Ramp points are checked too, at the step's place.
    let ramp = write_file(
        &dir,
        "ramp.yaml",
        "name: Ramp\ndrive: lenze-931\nsteps:\n  - ramp: { object: speed_setpoint, from: -7000 rpm, to: 0 rpm, rate: 1000 rpm/s }\nfinally: []\n",
    );
    assert_has(&refused_by_check(ramp), &["ramp.yaml:4:5: ramp speed_setpoint = -7000 rpm is below the minimum the drive reports, -6000 rpm"]);
    // Nothing moved: the setpoint is what the raw write left.
    let out = drivescript(
        &["read", "0x0010", "--drive", "lenze-931", "--port", port, "--json"],
        "",
    );
    let json: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("json");
    assert_eq!(json[0]["raw"], "-3000");
    let out = drivescript(&[&["state"][..], &base].concat(), "");
    assert_has(&stdout(&out), &["switch on disabled"]);

    // Within the limits, check passes and the recipe runs through the pty.
    let mut args = vec!["check", recipe.as_str()];
    args.extend(base);
    cli(&args, 0);
    let mut args = vec!["objects", "speed", "--from-drive"];
    args.extend(base);
    let out = cli(&args, 0);
    assert_has(&out.stdout, &["drive limits: -6000 rpm .. 6000 rpm"]);
    let mut args = vec!["run", recipe.as_str(), "--stop-timeout", "20s"];
    args.extend(base);
    let out = cli(&args, 0);
    assert_has(&out.stdout, &["PASSED"]);

    // Captured lines explain themselves.
    let out = cli(&["decode", "--protocol", "lenze-931", "OW:0000 0005"], 0);
    assert_has(&out.stdout, &["0x00000005 value too high, written but limited"]);
}

#[test]
fn a_silent_drive_leaves_check_unable_to_read_limits_with_exit_code_3() {
    let dir = scratch("silent");
    let recipe = commissioning_for_931(&dir).to_string_lossy().to_string();
    let dictionary = completed_template(&dir).to_string_lossy().to_string();
    // A loopback listener that accepts and never answers.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = listener.local_addr().expect("addr").to_string();
    let err = cli(
        &[
            "check",
            &recipe,
            "--drive",
            "lenze-931",
            "--dictionary",
            &dictionary,
            "--tcp",
            &addr,
            "--timeout",
            "50ms",
            "--retries",
            "1",
        ],
        3,
    )
    .stderr;
    assert_has(
        &err,
        &[
            "`ON:0010` (read the minimum of object 0x0010)",
            "2 attempt(s), 50 ms each",
            "the drive's limits could not be read",
        ],
    );
    drop(listener);
}

/// Backup, diff and restore on the simulated 931: the drive's own limits (`ON`/`OX`) refuse
/// a value before any write, and `--store` sends `SAVE!`.
#[test]
fn parameters_round_trip_with_the_drives_limits_and_save() {
    let sim = crate::support::Simulator::start(&["--drive", "lenze-931", "--pty"]);
    let port = sim.endpoint.as_str();
    let dir = scratch("parameters");
    let dictionary = completed_template(&dir).to_string_lossy().to_string();
    let file = dir.join("backup.yaml").to_string_lossy().to_string();
    let with = |args: &[&str]| {
        let mut all: Vec<&str> = args.to_vec();
        all.extend([
            "--drive",
            "lenze-931",
            "--dictionary",
            &dictionary,
            "--port",
            port,
        ]);
        let out = drivescript(&all, "");
        (out.status.code(), format!("{}{}", stdout(&out), stderr(&out)))
    };
    let (code, out) = with(&["write", "operating_mode", "1"]);
    assert_eq!(code, Some(0), "{out}");
    let (code, out) = with(&["backup", "-o", &file]);
    assert_eq!(code, Some(0), "{out}");
    let (code, out) = with(&["write", "operating_mode", "2"]);
    assert_eq!(code, Some(0), "{out}");
    let (code, out) = with(&["diff", &file]);
    assert_eq!(code, Some(1), "{out}");

    // A value beyond the drive's maximum (3) is refused before anything is written.
    let beyond = dir.join("beyond.yaml");
    let saved = std::fs::read_to_string(&file).expect("backup");
    std::fs::write(&beyond, saved.replace("raw: \"1\"", "raw: \"7\"")).expect("edited");
    let beyond = beyond.to_string_lossy().to_string();
    let (code, out) = with(&["restore", &beyond, "--apply"]);
    assert_eq!(code, Some(2), "{out}");
    assert_has(&out, &["outside the drive's limits"]);
    let (code, out) = with(&["read", "operating_mode", "--json"]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("\"value\":2"), "nothing was written: {out}");

    let (code, out) = with(&["restore", &file, "--apply", "--store"]);
    assert_eq!(code, Some(0), "{out}");
    assert_has(&out, &["parameters stored in the drive's non-volatile memory"]);
    let (code, out) = with(&["diff", &file]);
    assert_eq!(code, Some(0), "{out}");
}

#[test]
fn an_sd2_run_asks_nothing_about_drive_limits() {
    // SD2 drives report no limits: the run's comparison sends nothing and says nothing.
    // 84 requests is what the commissioning recipe sent before `run` compared limits, 87
    // since the safe stop reads state, speed and setpoint to know whether to brake first,
    // 91 since it reads the speed once more after the stop to know the spindle stands still,
    // the state before each stop command of finally (never to move the drive up) and the
    // state once more after the speed, so the end is told from the last reads.
    let dir = scratch("sd2-count");
    let trace = dir.join("sd2.trace");
    let mut run = InProcessRun::new(repo_root().join("recipes/commissioning.yaml"));
    let (_, output, text) = run.run_traced(&trace, 0, &[]);
    assert_eq!(text.lines().filter(|l| l.contains(" TX ")).count(), 91, "{text}");
    assert_lacks(&output, &["drive limits"]);
}

#[test]
fn ctrl_c_while_the_drives_limits_are_read_ends_with_130_and_nothing_moved() {
    let (dir, recipe) = scratch_file(
        "run-limits-ctrl-c",
        "silent.yaml",
        "name: Silent\ndrive: lenze-931\nsteps:\n  - set: { speed_setpoint: 100 rpm }\n",
    );
    let prepare = faults_before_the_run(|f| f.drop_replies(100));
    let mut run = on_931(recipe, &dir);
    run.prepare = Some(&prepare);
    run.stop.schedule(
        Duration::from_millis(300),
        drivescript::stop_request::StopSignal::INT,
    );
    run.run_expecting(
        130,
        &["stopped by Ctrl-C (SIGINT) while the drive's limits were read; nothing was sent to move the drive"],
    );
}
