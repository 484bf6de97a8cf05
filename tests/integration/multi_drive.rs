//! Several drives in one recipe (issue 18): two simulated SD2 drives on one pseudo-terminal
//! reach their own speeds, and their telegrams never interleave on the line; a fault on one
//! stops both; a stop signal stops both, the last enabled first, each verified; two drives
//! of different families, each on its own line; `check` names unknown drives with
//! did-you-mean.

use crate::live_run::LiveRun;
use crate::support::{
    assert_has, assert_lacks, cli, drivescript, scratch, scratch_file, stderr, words, write_file,
    InProcessRun, Simulator,
};
use drivescript::clock::SharedClock;
use drivescript::drive::device_control::DeviceState;
use drivescript::sim::SimulatedDrive;
use drivescript::stop_request::{StopRequests, StopSignal};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

const TWO_AXES: &str = "name: Two axes
drives:
  left:  { drive: sd2, address: dnc:2 }
  right: { drive: sd2, address: dnc:3 }
steps:
  - shutdown
  - set: { left.speed_setpoint: 1000 rpm, right.speed_setpoint: 2000 rpm }
  - enable_operation: left
  - go_to: { drive: right, state: operation_enabled }
  - go_to: operation_enabled
  - wait_until: { left.speed_actual: { near: 1000 rpm, within: 1 % }, timeout: 30 s }
  - wait_until: { right.speed_actual: { near: 2000 rpm, within: 1 % }, timeout: 30 s }
  - sample: { objects: [left.speed_actual, right.speed_actual], every: 100 ms, for: SAMPLE_FOR }
  - expect:
      left.speed_actual: { mean: { near: 1000 rpm, within: 1 % } }
      right.speed_actual: { mean: { near: 2000 rpm, within: 1 % } }
";

/// TWO_AXES sampling for `sample_for` (`1 s`).
fn two_axes(sample_for: &str) -> String {
    TWO_AXES.replace("SAMPLE_FOR", sample_for)
}

fn state_of(sim: &Arc<Mutex<dyn SimulatedDrive>>) -> DeviceState {
    sim.lock().unwrap_or_else(PoisonError::into_inner).state()
}

/// The (TX, RX) byte rows of a trace file, in order (the lines that name the drive, and
/// other events, left out).
fn trace_rows(trace: &str) -> Vec<(String, Vec<u8>)> {
    trace
        .lines()
        .filter_map(|line| {
            let mut tokens = line.split_whitespace();
            tokens.next()?.parse::<f64>().ok()?;
            let direction = tokens.next()?.to_string();
            if direction != "TX" && direction != "RX" {
                return None;
            }
            let bytes = tokens
                .take_while(|t| *t != "#")
                .map(|t| u8::from_str_radix(t, 16))
                .collect::<Result<Vec<u8>, _>>()
                .ok()?;
            Some((direction, bytes))
        })
        .collect()
}

/// Every request is answered, by the drive it was sent to, before the next request goes
/// out: SD2 requests carry the destination in byte 2, replies the sender in byte 3.
fn assert_never_interleaved(trace: &str) {
    let rows = trace_rows(trace);
    assert!(rows.len() > 20, "too short a trace: {trace}");
    let mut asked: Option<u8> = None;
    let mut addresses = std::collections::BTreeSet::new();
    for (direction, bytes) in rows {
        match (direction.as_str(), asked) {
            ("TX", None) => {
                asked = Some(bytes[2]);
                addresses.insert(bytes[2]);
            }
            ("RX", Some(to)) => {
                assert_eq!(bytes[3], to, "a reply from another drive than the one asked");
                asked = None;
            }
            (d, a) => panic!("{d} while {a:?} was awaiting its reply: the line interleaved"),
        }
    }
    assert_eq!(
        addresses.into_iter().collect::<Vec<_>>(),
        vec![2, 3],
        "both drives were asked"
    );
}

/// Runs `recipe_text` (two drives at DNC addresses 2 and 3) through a pty served by
/// `simulate sim_args`, with a trace: both drives reach their own speeds and the requests
/// never interleave. Returns the simulator (still serving), the recipe, the output and the
/// trace.
fn two_axes_on_a_pty(
    sim_args: &[&str],
    name: &str,
    recipe_text: &str,
) -> (Simulator, std::path::PathBuf, String, String) {
    let sim = Simulator::pty(sim_args);
    let (dir, recipe) = scratch_file(name, "recipe.yaml", recipe_text);
    let trace = dir.join("run.trace");
    let text = sim
        .cli(
            &[
                "run",
                recipe.to_str().expect("utf-8 path"),
                "--trace",
                trace.to_str().expect("utf-8 path"),
            ],
            0,
        )
        .stdout;
    assert_has(
        &text,
        &[
            "PASS  left.speed_actual mean near 1000 rpm",
            "PASS  right.speed_actual mean near 2000 rpm",
        ],
    );
    let trace = std::fs::read_to_string(&trace).expect("trace");
    // Requests went to DNC addresses 2 and 3 and nowhere else, one at a time.
    assert_never_interleaved(&trace);
    (sim, recipe, text, trace)
}

#[test]
fn two_drives_on_one_pty_reach_their_own_speeds_and_never_interleave() {
    let (_sim, _, text, trace) =
        two_axes_on_a_pty(&["--address", "dnc:2,dnc:3"], "multi-pty", &two_axes("1 s"));
    assert_has(&text, &["right: drive left in ready to switch on at 0 rpm\nleft: drive left in ready to switch on at 0 rpm\n"]);
    assert!(
        trace.contains("-- drive `left`") && trace.contains("-- drive `right`"),
        "{trace}"
    );
}

/// Issue 18's spelling end to end: `simulate --dnc-address 2,3` serves drives at DNC
/// addresses 2 and 3, and a recipe naming them `dnc_address: 2` and `address: 0, axis: b`
/// (switch 0, drive B: DNC address 3) drives both on that pty; `--dnc-address 3` reaches
/// drive B alone afterwards.
#[test]
fn the_issue_spelling_of_addresses_on_a_pty_served_with_dnc_address() {
    let text = two_axes("1 s")
        .replace("{ drive: sd2, address: dnc:2 }", "{ drive: sd2, dnc_address: 2 }")
        .replace(
            "{ drive: sd2, address: dnc:3 }",
            "{ drive: sd2, address: 0, axis: b }",
        );
    assert!(
        text.contains("dnc_address: 2") && text.contains("axis: b"),
        "{text}"
    );
    let (sim, recipe, _, _) = two_axes_on_a_pty(&["--dnc-address", "2,3"], "multi-pty-dnc-address", &text);
    let state = sim.cli(&["state", "--dnc-address", "3"], 0);
    assert_has(&state.stdout, &["ready to switch on"]);
    // With a recipe of several drives, one address on the command line is refused.
    let out = sim.cli(
        &["run", recipe.to_str().expect("utf-8 path"), "--dnc-address", "2"],
        2,
    );
    assert_has(
        &out.stderr,
        &["--dnc-address 2 names one drive; with several drives each gives its own"],
    );
}

#[test]
fn dnc_address_is_refused_with_address_and_for_a_family_without_dnc_addresses() {
    let both = cli(&["simulate", "--pty", "--dnc-address", "2", "--address", "0"], 2);
    assert_has(
        &both.stderr,
        &["'--dnc-address <N,…>' cannot be used with '--address <ADDRESS>'"],
    );
    let both = cli(&["state", "--dnc-address", "2", "--address", "0"], 2);
    assert_has(&both.stderr, &["cannot be used with"]);
    let ct = cli(&words("simulate --pty --drive ct-unidrive-sp --dnc-address 2"), 2);
    assert_has(&ct.stderr, &["error: --dnc-address is for drives of the sd2 family; a ct-ansi drive has no `dnc_address`: give --address, "]);
    let ct = drivescript(&["state", "--drive", "ct-unidrive-sp", "--dnc-address", "2"], "");
    assert_ne!(ct.status.code(), Some(0));
    assert_has(&stderr(&ct), &["--dnc-address is for drives of the sd2 family"]);
    let master = cli(&["simulate", "--pty", "--dnc-address", "2,1"], 2);
    assert_has(
        &master.stderr,
        &["error: --dnc-address 1: `1` is not a drive's DNC address"],
    );
}

/// Ctrl-C during the sample of a run on a real pseudo-terminal: both drives stopped, the
/// last enabled first, each read back; and afterwards each reports it by itself.
#[test]
fn ctrl_c_on_a_pty_stops_both_drives_each_verified() {
    let sim = Simulator::pty(&["--address", "dnc:2,dnc:3"]);
    let (_, recipe) = scratch_file("multi-pty-ctrl-c", "recipe.yaml", &two_axes("10 min"));
    let recipe = recipe.to_string_lossy().to_string();
    let run = LiveRun::start(["run", recipe.as_str(), "--port", &sim.endpoint]);
    let (_, code, seen) = run.interrupt_after("wait until right.speed_actual", Duration::from_millis(500));
    assert_eq!(code, Some(130), "{seen}");
    assert_lacks(&seen, &["CHECK THE DRIVE BY HAND"]);
    // The last enabled (right) is stopped first.
    let right = seen
        .find("right: set speed_setpoint = 0 rpm")
        .expect("right stopped");
    let left = seen
        .find("left: set speed_setpoint = 0 rpm")
        .expect("left stopped");
    assert!(right < left, "{seen}");
    assert_has(&seen, &["right: drive left in ready to switch on at 0 rpm\nleft: drive left in ready to switch on at 0 rpm\n"]);
    for address in ["dnc:2", "dnc:3"] {
        let state = sim.cli(&["state", "--address", address], 0).stdout;
        assert!(state.contains("ready to switch on"), "{address}: {state}");
    }
}

/// Runs `recipe` in-process in virtual time; `prepare` sees each simulated drive in the
/// order declared.
fn run_in_process(
    recipe: &Path,
    stop: Arc<StopRequests>,
    prepare: &drivescript::run::PrepareSimulator,
) -> (drivescript::run::RunResult, String) {
    let mut run = InProcessRun::new(recipe);
    run.stop = stop;
    run.prepare = Some(prepare);
    run.run()
}

#[test]
fn a_fault_on_one_drive_runs_on_fault_and_stops_both() {
    let (_, recipe) = scratch_file(
        "multi-fault",
        "recipe.yaml",
        "name: Fault on the left
drives:
  left:  { drive: sd2, address: dnc:2 }
  right: { drive: sd2, address: dnc:3 }
steps:
  - set: { left.speed_setpoint: 1000 rpm, right.speed_setpoint: 2000 rpm }
  - go_to: operation_enabled
  - dwell: 1 min
on_fault:
  - print: the left drive tripped
",
    );
    let calls = AtomicUsize::new(0);
    let prepare = move |sim: &Arc<Mutex<dyn SimulatedDrive>>, _: &SharedClock| {
        if calls.fetch_add(1, Ordering::SeqCst) == 0 {
            let mut sim = sim.lock().unwrap_or_else(PoisonError::into_inner);
            sim.faults().trip_at(Duration::from_secs(10), 4660);
        }
    };
    let (result, output) = run_in_process(&recipe, Arc::new(StopRequests::new()), &prepare);
    assert_eq!(result.exit_code, 3, "{output}");
    assert_has(
        &output,
        &["drive fault: drive `left` went to", "the left drive tripped"],
    );
    let report = result.report.expect("a report");
    assert_eq!(report.drive_ends.len(), 2, "{output}");
    // The right drive was stopped and read back at standstill; the left one is left in
    // fault, which is no confirmed stop (the run's verdict rule).
    let confirmed: Vec<(&str, bool)> = report
        .drive_ends
        .iter()
        .map(|e| (e.name.as_str(), e.end.stop_confirmed))
        .collect();
    assert_eq!(confirmed, [("right", true), ("left", false)], "{output}");
    assert_eq!(result.simulators.len(), 2);
    for (name, sim) in &result.simulators {
        let state = state_of(sim);
        assert!(
            !matches!(
                state,
                DeviceState::OperationEnabled | DeviceState::QuickStopActive
            ),
            "{name} still {state}: {output}"
        );
    }
    // The right drive, not faulted, was stopped the normal way.
    assert_has(&output, &["right: disable_operation (default finally)"]);
}

#[test]
fn a_stop_signal_stops_both_drives_last_enabled_first() {
    let (_, recipe) = scratch_file("multi-signal", "recipe.yaml", &two_axes("1 h"));
    let stop = Arc::new(StopRequests::new());
    stop.schedule(Duration::from_secs(30), StopSignal::INT);
    let (result, output) = run_in_process(&recipe, stop, &|_, _| {});
    assert_eq!(result.exit_code, 130, "{output}");
    let report = result.report.expect("a report");
    let names: Vec<&str> = report.drive_ends.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, vec!["right", "left"], "{output}");
    for drive in &report.drive_ends {
        assert!(drive.end.stop_confirmed, "{output}");
        assert_eq!(
            drive.end.final_state,
            Some(DeviceState::ReadyToSwitchOn),
            "{output}"
        );
        assert!(drive.end.final_speed.is_some_and(|v| v.abs() < 10.0), "{output}");
    }
    for (name, sim) in &result.simulators {
        assert_eq!(state_of(sim), DeviceState::ReadyToSwitchOn, "{name}: {output}");
    }
}

#[test]
fn drives_of_two_families_each_on_its_own_line_reach_their_speeds() {
    let (dir, recipe) = scratch_file(
        "multi-families",
        "recipe.yaml",
        "name: Spindle and feed
drives:
  spindle: { drive: sd2, address: dnc:2 }
  feed:    { drive: ct-unidrive-sp, address: \"1.2\" }
steps:
  - go_to: operation_enabled
  - set: { spindle.speed_setpoint: 3000 rpm, feed.speed_setpoint: 500 rpm }
  - wait_until: { spindle.speed_actual: { near: 3000 rpm, within: 1 % }, timeout: 30 s }
  - wait_until: { feed.speed_actual: { near: 500 rpm, within: 1 % }, timeout: 30 s }
  - sample: { objects: [spindle.speed_actual, feed.speed_actual], every: 100 ms, for: 2 s }
  - expect:
      spindle.speed_actual: { mean: { near: 3000 rpm, within: 1 % } }
      feed.speed_actual: { mean: { near: 500 rpm, within: 1 % } }
",
    );
    let csv = dir.join("run.csv");
    let mut run = InProcessRun::new(&recipe);
    run.outputs.csv = Some(csv.clone());
    let (result, output) = run.run_expecting(0, &["spindle SD2 (DNC address 2)"]);
    // The long CSV layout names the drive in a column of its own.
    let rows = std::fs::read_to_string(&csv).expect("csv");
    let mut lines = rows.lines();
    assert_eq!(lines.next(), Some("time [s],utc,step,drive,object,value,unit"));
    let first: Vec<&str> = lines.next().expect("a row").split(',').collect();
    assert_eq!(first[2..5], ["5", "spindle", "speed_actual"], "{rows}");
    assert!(
        rows.lines().any(|l| l.contains(",5,feed,speed_actual,")),
        "{rows}"
    );
    assert_has(&output, &["feed CT-ANSI (drive 1.2)"]);
    let report = result.report.expect("a report");
    assert_eq!(report.drive_ends.len(), 2);
    assert!(report.drive_ends.iter().all(|e| e.end.stop_confirmed));
    let series: Vec<&str> = report.series.iter().map(|s| s.object.as_str()).collect();
    assert_eq!(series, vec!["spindle.speed_actual", "feed.speed_actual"]);
}

#[test]
fn check_names_unknown_drives_and_objects_without_a_drive() {
    let (_, recipe) = scratch_file(
        "multi-check",
        "recipe.yaml",
        "name: Typos
drives:
  left:  { drive: sd2, address: dnc:2 }
  right: { drive: ct-unidrive-sp }
steps:
  - set: { lfet.speed_setpoint: 1000 rpm, right.sped_setpoint: 2000 rpm }
  - enable_operation: rihgt
  - read: [speed_actual]
",
    );
    let out = cli(&["check", recipe.to_str().expect("utf-8 path")], 2);
    assert_has(
        &out.stderr,
        &[
            "unknown drive `lfet`",
            "did you mean `left`?",
            "unknown object `sped_setpoint` in the ct-unidrive-sp dictionary",
            "unknown drive `rihgt`",
            "did you mean `right`?",
            "`speed_actual` does not say which drive it is on",
            "4 problems",
        ],
    );
}

#[test]
fn two_drives_at_one_address_on_one_line_are_refused_before_anything_is_sent() {
    let (_, recipe) = scratch_file(
        "multi-same-address",
        "recipe.yaml",
        "name: Same address
drives:
  left:  { drive: sd2, address: dnc:2 }
  right: { drive: sd2, address: dnc:2 }
steps:
  - shutdown
",
    );
    let (result, output) = run_in_process(&recipe, Arc::new(StopRequests::new()), &|_, _| {});
    assert_eq!(result.exit_code, 2, "{output}");
    assert_has(&output, &["drives `left` and `right` are both at"]);
    assert!(result.report.is_none());
}

const TWO_AXES_SCRIPT: &str = r#"//! name: Two axes from a script
//! drives: left = sd2 @ dnc:2, right = sd2 @ dnc:3
let left = drive("left");
let right = drive("right");
drive().shutdown();
left.set("speed_setpoint", 1000.0, "rpm");
right.set("speed_setpoint", 2000.0, "rpm");
left.go_to("operation_enabled");
right.go_to("operation_enabled");
dwell("2 s");
let w = left.sample(["speed_actual"], "100 ms", "1 s");
expect_near("left speed", w.mean("speed_actual"), 1000.0, 10.0);
expect_near("right speed", right.read("speed_actual"), 2000.0, 20.0);
print(`right is ${right.state()}`);
DRIVE_CALL
"#;

#[test]
fn a_script_drives_each_named_drive_and_stops_both() {
    let (_, script) = scratch_file(
        "multi-script",
        "script.rhai",
        &TWO_AXES_SCRIPT.replace("DRIVE_CALL", ""),
    );
    let (result, output) = run_in_process(&script, Arc::new(StopRequests::new()), &|_, _| {});
    assert_eq!(result.exit_code, 0, "{output}");
    assert_has(
        &output,
        &[
            "PASS  left speed: measured 1000",
            "PASS  right speed: measured 1999.9",
            "right is operation_enabled",
            "shutdown  left: control word 6; right: control word 6",
        ],
    );
    for (name, sim) in &result.simulators {
        assert_eq!(state_of(sim), DeviceState::ReadyToSwitchOn, "{name}: {output}");
    }
}

#[test]
fn a_script_naming_an_unknown_drive_or_no_drive_is_told_which_there_are() {
    let dir = scratch("multi-script-typo");
    let calls = [
        (
            "drive(\"rigth\").read(\"speed_actual\");",
            "no drive called `rigth` in this script; did you mean `right`?",
        ),
        (
            "drive().read(\"speed_actual\");",
            "this script has several drives (left, right): name the drive",
        ),
    ];
    for (call, said) in calls {
        let script = write_file(&dir, "script.rhai", &TWO_AXES_SCRIPT.replace("DRIVE_CALL", call));
        let (result, output) = run_in_process(&script, Arc::new(StopRequests::new()), &|_, _| {});
        assert_ne!(result.exit_code, 0, "{output}");
        assert_has(&output, &[said]);
        // Either way both drives are stopped.
        for (name, sim) in &result.simulators {
            assert_eq!(state_of(sim), DeviceState::ReadyToSwitchOn, "{name}: {output}");
        }
    }
}

/// A fresh scratch folder `name` with the two-axes recipe and a limits file capping the
/// speed at `max_speed`: the folder, the recipe and the limits file.
fn two_axes_under_limits(name: &str, max_speed: &str) -> (PathBuf, PathBuf, String) {
    let (dir, limits) = scratch_file(name, "limits.yaml", &format!("max_speed: {max_speed}\n"));
    let recipe = write_file(&dir, "recipe.yaml", &two_axes("1 s"));
    let limits = limits.to_str().expect("utf-8 path").to_string();
    (dir, recipe, limits)
}

#[test]
fn the_bench_limits_cap_every_drive_of_a_recipe_and_of_a_script() {
    let (dir, recipe, limits) = two_axes_under_limits("multi-limits", "1500 rpm");
    let script = write_file(&dir, "script.rhai", &TWO_AXES_SCRIPT.replace("DRIVE_CALL", ""));
    for file in [&recipe, &script] {
        let file = file.to_str().expect("utf-8 path");
        let out = cli(&["check", file, "--limits", &limits], 2);
        assert_has(
            &out.stderr,
            &[
                "2000 rpm exceeds the bench limit 1500 rpm of speed_setpoint",
                "1 problem",
            ],
        );
    }
}

/// `check` names the bench limits it checked a recipe with `drives:` against, as it does
/// for one drive and for a script: every drive of the file is capped by the same file.
#[test]
fn check_names_the_bench_limits_of_a_recipe_with_drives() {
    let (_, recipe, limits) = two_axes_under_limits("multi-limits-named", "2500 rpm");
    let out = cli(
        &["check", recipe.to_str().expect("utf-8 path"), "--limits", &limits],
        0,
    );
    assert_has(
        &out.stdout,
        &[
            "drives left: sd2, right: sd2",
            &format!("bench limits max_speed 2500 rpm (limits file {limits})"),
        ],
    );
}

/// A drive on its own line that cannot be reached again does not hold up the stop of the
/// drive stopped before it: the spindle (enabled last, so stopped first) is brought to
/// standstill and shut down before the feed's reconnect attempts run out.
#[test]
fn an_unreachable_drive_does_not_hold_up_the_others_stop() {
    let (_, recipe) = scratch_file(
        "multi-unreachable",
        "recipe.yaml",
        "name: Feed line lost for good
drives:
  spindle: { drive: sd2, address: dnc:2 }
  feed:    { drive: ct-unidrive-sp, address: \"1.2\" }
steps:
  - go_to: { drive: feed, state: operation_enabled }
  - go_to: { drive: spindle, state: operation_enabled }
  - set: { spindle.speed_setpoint: 3000 rpm, feed.speed_setpoint: 500 rpm }
  - dwell: 1 h
",
    );
    // The hook is called once per simulated drive, in declared order: the second is the feed.
    let calls = AtomicUsize::new(0);
    let prepare = move |sim: &Arc<Mutex<dyn SimulatedDrive>>, _clock: &SharedClock| {
        if calls.fetch_add(1, Ordering::SeqCst) == 1 {
            let mut sim = sim.lock().unwrap_or_else(PoisonError::into_inner);
            sim.faults()
                .line_down(Duration::from_secs(20), Duration::from_secs(100_000));
        }
    };
    let (result, output) = run_in_process(&recipe, Arc::new(StopRequests::new()), &prepare);
    assert_eq!(result.exit_code, 3, "{output}");
    let spindle_stopped = output
        .find("spindle: shutdown (default finally)")
        .unwrap_or_else(|| panic!("the spindle is stopped: {output}"));
    let feed_given_up = output
        .find("drive `feed` could not be reached to stop it")
        .unwrap_or_else(|| panic!("the feed is reported unreachable: {output}"));
    assert!(spindle_stopped < feed_given_up, "{output}");
    assert_has(&output, &["CHECK THE DRIVE BY HAND"]);
}
