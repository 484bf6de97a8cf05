//! The generic CANopen family end to end: the shipped commissioning recipe with only
//! `drive:` changed on the simulated CiA 402 node, in virtual time and through a simulated
//! SLCAN adapter on a pseudo-terminal; a node whose heartbeat stops; `decode` of NMT,
//! heartbeat and EMCY frames; an EDS as a dictionary on the command line.

use crate::support::{
    assert_has, assert_in_order, assert_lacks, cli, cli_with_dictionary, control_words, repo_root, scratch,
    scratch_file, sqlite_store, words, write_file, InProcessRun,
};
use drivescript::clock::SharedClock;
use drivescript::family::canopen::codec::NmtState;
use drivescript::family::canopen::sim::Cia402Node;
use drivescript::run::{DictionaryArgs, PrepareSimulator};
use drivescript::sim::SimulatedDrive;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Duration;

fn canopen() -> DictionaryArgs {
    DictionaryArgs {
        name: "canopen".into(),
        ..DictionaryArgs::builtin_default()
    }
}

/// A run of the recipe `text`, written to `dir`, on the simulated CiA 402 node.
fn on_cia402<'a>(dir: &Path, text: &str) -> InProcessRun<'a> {
    let mut run = InProcessRun::new(write_file(dir, "recipe.yaml", text));
    run.dictionary = canopen();
    run
}

/// A run in `dir` of a recipe `title` that turns the node at 1000 rpm for a minute, the
/// simulated node made ready by `prepare` for what the test is about.
fn turning_for_a_minute<'a>(dir: &Path, title: &str, prepare: &'a PrepareSimulator) -> InProcessRun<'a> {
    let mut run = on_cia402(
        dir,
        &format!("name: {title}\ndrive: canopen\nsteps:\n  - go_to: operation_enabled\n  - set: {{ speed_setpoint: 1000 rpm }}\n  - dwell: 1 min\n"),
    );
    run.prepare = Some(prepare);
    run
}

/// Prepares the simulated node to meet `fault` 20 s into the run (in the minute's dwell).
fn at_20_s(fault: fn(&mut Cia402Node, Duration)) -> impl Fn(&Arc<Mutex<dyn SimulatedDrive>>, &SharedClock) {
    move |sim, clock| on_node(sim, |node| fault(node, clock.now() + Duration::from_secs(20)))
}

/// What `look` makes of the simulated CiA 402 node behind `sim` (or does to it).
fn on_node<T>(sim: &Arc<Mutex<dyn SimulatedDrive>>, look: impl FnOnce(&mut Cia402Node) -> T) -> T {
    let mut sim = sim.lock().unwrap();
    look(
        sim.as_any_mut()
            .downcast_mut::<Cia402Node>()
            .expect("a CiA 402 node"),
    )
}

/// `recipes/commissioning.yaml` with only `drive:` changed.
pub fn commissioning(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repo_root().join("recipes/commissioning.yaml")).expect("recipe");
    assert!(text.contains("drive: sd2"));
    write_file(
        dir,
        "commissioning.yaml",
        &text.replace("drive: sd2", "drive: canopen"),
    )
}

#[test]
fn the_commissioning_recipe_runs_on_the_simulated_cia402_node_with_only_drive_changed() {
    let dir = scratch("canopen-commissioning");
    let trace = dir.join("run.log");
    let mut run = InProcessRun::new(commissioning(&dir));
    run.dictionary = canopen();
    let (result, output, trace_text) = run.run_traced(
        &trace,
        0,
        &[
            "ident = \"drivescript CiA 402 node\"",
            "bus_voltage = 325.",
            "drive left in ready to switch on at 0 rpm",
        ],
    );
    // The node boots pre-operational and enables operation only in operational: it is
    // started before the enable and put back after the verified safe stop, said on the
    // console.
    assert_in_order(
        &output,
        &[
            "node 1 is pre-operational (",
            "sent NMT start (`000#0101`) so that it is operational",
            "3  ok    go to operation_enabled",
            "finally 2  ok    shutdown  control word 6",
            "node 1 back to pre-operational (NMT enter pre-operational, `000#8001`): the state it was found in",
            "PASSED",
        ],
    );
    // Shutdown, switch on, enable operation; disable operation and shutdown in finally.
    assert_eq!(control_words(&result), vec![6, 7, 15, 7, 6]);
    // Profile velocity mode (0x6060 = 3) is written before each command; the boot-up
    // message the node sent is in the trace too.
    assert_has(
        &trace_text,
        &[
            "can0 701#00",
            "can0 601#2F60600003000000",
            "can0 601#2B4060000F000000",
        ],
    );
    // On the bus: NMT start to node 1 alone just before the enable, enter pre-operational
    // only after the last controlword of the safe stop.
    assert_in_order(
        &trace_text,
        &[
            "can0 601#2B40600007000000",
            "can0 000#0101",
            "can0 601#2B4060000F000000",
            "can0 601#2B40600006000000",
            "can0 000#8001",
        ],
    );
    assert!(
        !trace_text.contains("000#0100") && !trace_text.contains("000#8000"),
        "no broadcast"
    );
    // decode explains the trace again.
    let out = crate::support::drivescript(&["decode", &trace.to_string_lossy()], "");
    assert_eq!(out.status.code(), Some(0), "{}", crate::support::stderr(&out));
    assert_has(
        &crate::support::stdout(&out),
        &[
            "boot-up ← node 1",
            "write index 0x6060/0 modes_of_operation = 3 → node 1",
            "write index 0x6040/0 control_word = 0x000f → node 1",
            "NMT start (enter operational) → node 1",
            "NMT enter pre-operational → node 1",
        ],
    );
}

#[test]
fn a_node_whose_heartbeat_stops_is_a_lost_link_and_is_stopped() {
    let dir = scratch("canopen-heartbeat");
    let stop_heartbeat = at_20_s(Cia402Node::stop_heartbeat_at);
    let run = turning_for_a_minute(&dir, "Heartbeat lost", &stop_heartbeat);
    let (result, _) = run.run_expecting(
        3,
        &[
            "     1  ok    go to operation_enabled",
            "     3  FAIL  dwell 1m  I/O error on built-in simulated drive: the heartbeat of node 1 stopped",
            "the heartbeat of node 1 stopped: none for",
            "a heartbeat consumer gives up after 3 periods",
            "safe stop: link to node 1 on built-in simulated drive restored",
            "drive left in ready to switch on at 0 rpm",
        ],
    );
    // The node still answers SDO: the safe stop brakes and stops it, verified.
    assert_eq!(control_words(&result), vec![6, 7, 15, 7, 6]);
}

/// A node that goes silent on a healthy bus — no heartbeat and no SDO response — is named
/// for what it is: a heartbeat loss with the node and the age of its last heartbeat, not an
/// SDO no-reply. Its stop cannot be verified, so it is not sent NMT enter pre-operational,
/// and the console says why.
#[test]
fn a_node_silent_in_heartbeat_and_sdo_is_a_heartbeat_loss_and_gets_no_nmt_command() {
    let dir = scratch("canopen-silent");
    let silent = at_20_s(Cia402Node::go_silent_at);
    let mut run = turning_for_a_minute(&dir, "Node silent", &silent);
    run.safe_stop.reconnect_timeout = Some(Duration::from_secs(2));
    let (_, output) = run.run_expecting(
        3,
        &[
            "     3  FAIL  dwell 1m  I/O error on built-in simulated drive: heartbeat loss: the last heartbeat of node 1 came",
            "node 1 is left operational: NMT enter pre-operational (`000#8001`) is not sent, since the drive's stop was not verified",
            "CHECK THE DRIVE BY HAND",
            "ERROR: I/O error on built-in simulated drive: heartbeat loss",
        ],
    );
    assert_lacks(&output, &["back to pre-operational", "no reply"]);
}

/// An EMCY frame alone, while the statusword shows no fault, is a drive fault: the run
/// stops, the code's text is in the console, the JUnit file, the HTML report and the trace.
#[test]
fn an_emcy_alone_is_a_drive_fault_in_every_report() {
    let dir = scratch("canopen-emcy-alone");
    let emcy = |sim: &Arc<Mutex<dyn SimulatedDrive>>, clock: &SharedClock| {
        let at = clock.now() + Duration::from_secs(20);
        sim.lock().unwrap().faults().emergency_at(at, 0x2310);
    };
    let mut run = turning_for_a_minute(&dir, "EMCY alone", &emcy);
    let (junit, html) = run.reports_in(&dir);
    let trace = dir.join("run.log");
    run.outputs.trace = Some(trace.clone());
    let (result, output) = run.run();
    assert_eq!(result.exit_code, 3, "{output}");
    let said = "node 1 EMCY 0x2310 continuous over-current (output side) (error register 0x01)";
    assert_has(
        &output,
        &[
            &format!(
                "     3  FAIL  dwell 1m  drive fault: the drive reported {said} while in operation enabled"
            ),
            "drive left in ready to switch on at 0 rpm",
            "ERROR: drive fault",
        ],
    );
    // The default safe stop: disable operation, shutdown, each verified.
    assert_eq!(control_words(&result), vec![6, 7, 15, 7, 6]);
    for file in [&junit, &html] {
        let text = std::fs::read_to_string(file).expect("report written");
        assert_has(&text, &["EMCY 0x2310 continuous over-current (output side)"]);
    }
    let trace = std::fs::read_to_string(&trace).expect("trace");
    assert_has(&trace, &["can0 081#1023010000000000"]);
}

/// A run that leaves the drive enabled on purpose leaves its node operational: going back
/// to pre-operational could set off a drive's reaction to leaving operational (0x6007).
#[test]
fn a_node_left_enabled_stays_operational() {
    let dir = scratch("canopen-left-enabled");
    let run = on_cia402(
        &dir,
        "name: Left enabled\ndrive: canopen\nleave_enabled: true\nsteps:\n  - go_to: operation_enabled\n",
    );
    let (result, output) = run.run_expecting(0, &["sent NMT start (`000#0101`)", "PASSED"]);
    assert_lacks(&output, &["back to pre-operational"]);
    assert_eq!(control_words(&result), vec![6, 7, 15]);
    let sim = result.simulator.expect("the simulated node");
    assert_eq!(on_node(&sim, |node| node.nmt_state()), NmtState::Operational);
}

/// An EMCY the node sent before the run began is told, not a stop: the recipe decides.
#[test]
fn an_emcy_before_the_run_began_is_told_and_the_run_goes_on() {
    let dir = scratch("canopen-emcy-before");
    let emcy = |sim: &Arc<Mutex<dyn SimulatedDrive>>, clock: &SharedClock| {
        sim.lock().unwrap().faults().emergency_at(clock.now(), 0x2310);
    };
    let mut run = on_cia402(
        &dir,
        "name: EMCY before\ndrive: canopen\nsteps:\n  - go_to: operation_enabled\n  - dwell: 10 s\n",
    );
    run.prepare = Some(&emcy);
    let (result, output) = run.run();
    assert_eq!(result.exit_code, 0, "{output}");
    assert_in_order(
        &output,
        &[
            "the drive reported node 1 EMCY 0x2310 continuous over-current (output side) (error register 0x01) before the run began",
            "2  ok    dwell 10s",
            "PASSED",
        ],
    );
    assert_eq!(control_words(&result), vec![6, 7, 15, 7, 6]);
}

#[test]
fn decode_explains_nmt_heartbeat_and_emcy_frames() {
    let out = cli(
        &words("decode --protocol canopen 000#0105 705#05 085#1023010000000000 601#4041600000000000"),
        0,
    );
    assert_has(
        &out.stdout,
        &[
            "NMT start (enter operational) → node 5",
            "heartbeat operational ← node 5",
            "EMCY 0x2310 continuous over-current (output side), error register 0x01 ← node 5",
            "index 0x6041/0 status_word",
        ],
    );
}

#[test]
fn an_eds_adds_its_objects_by_readable_name_index_and_eds_name() {
    let eds = "tests/eds/every-type.dcf";
    let out = cli_with_dictionary(&["objects", "gains"], "canopen", eds, 0);
    assert_has(&out.stdout, &["gains_proportional", "gains_integral"]);
    // The simulated node's own EDS: its objects are read by their EDS names.
    let out = cli_with_dictionary(
        &["read", "vendor_id", "Quick stop option code", "0x1018/0"],
        "canopen",
        "src/family/canopen/sim/cia402_node.eds",
        0,
    );
    let row = |name: &str| {
        let line = out
            .stdout
            .lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_default();
        line.split_whitespace().map(str::to_string).collect::<Vec<_>>()
    };
    // 0x1018/1 keeps the built-in dictionary's name (`vendor_id`), as every object at an
    // address the dictionary has.
    assert_eq!(row("vendor_id"), ["vendor_id", "0x00000000", "0", "0x1018/1"]);
    assert_eq!(
        row("quick_stop_option"),
        ["quick_stop_option", "2", "2", "0x605A"]
    );
    // An EDS is for a CANopen family's dictionary, not the SD2's.
    let out = cli(&["objects", "--dictionary", eds], 2);
    assert_has(
        &out.stderr,
        &[
            "is a CANopen EDS/DCF, but the sd2 dictionary is for the sd2 family",
            "give --drive canopen",
        ],
    );
    // A malformed EDS: located, nothing read.
    let (_, bad) = scratch_file(
        "canopen-bad-eds",
        "bad.eds",
        "[FileInfo]\n[2000]\nParameterName=X\nDataType=0x0006\nAccessType=maybe\n",
    );
    let out = cli(
        &[
            "objects",
            "--drive",
            "canopen",
            "--dictionary",
            &bad.to_string_lossy(),
        ],
        2,
    );
    assert_has(&out.stderr, &["`maybe` is not an access type", "bad.eds:5"]);
}

#[test]
fn the_commissioning_recipe_runs_through_an_slcan_pseudo_terminal() {
    let sim = crate::support::Simulator::start(&["--drive", "canopen", "--address", "3", "--slcan-pty"]);
    let dir = scratch("canopen-slcan");
    let recipe = commissioning(&dir);
    let can = format!("slcan:{}", sim.endpoint);
    let out = cli(
        &["run", recipe.to_str().unwrap(), "--address", "3", "--can", &can],
        0,
    );
    assert_has(
        &out.stdout,
        &[
            "ident = \"drivescript CiA 402 node\"",
            "drive left in ready to switch on at 0 rpm",
            "PASSED",
        ],
    );
}

/// The EMCY alone, through a real SLCAN pseudo-terminal in real time: the simulator sends
/// it 8 s after it started (`--sim emergency-at`), the run in its dwell stops on it and the
/// trace holds the EMCY, then the safe stop's controlwords, then NMT pre-operational.
#[test]
fn an_emcy_alone_stops_a_run_through_an_slcan_pseudo_terminal() {
    let sim = crate::support::Simulator::start(&[
        "--drive",
        "canopen",
        "--slcan-pty",
        "--sim",
        "emergency-at=8s:0x2310",
    ]);
    let (dir, recipe) = scratch_file(
        "canopen-slcan-emcy",
        "recipe.yaml",
        "name: EMCY alone over SLCAN\ndrive: canopen\nsteps:\n  - go_to: operation_enabled\n  - set: { speed_setpoint: 500 rpm }\n  - dwell: 2 min\n",
    );
    let trace = dir.join("run.log");
    let store = &sqlite_store(&dir);
    let can = format!("slcan:{}", sim.endpoint);
    let out = cli(
        &[
            "run",
            recipe.to_str().unwrap(),
            "--can",
            &can,
            "--trace",
            trace.to_str().unwrap(),
            "--results",
            store,
        ],
        3,
    );
    assert_in_order(
        &out.stdout,
        &[
            "FAIL  dwell 2m  drive fault: the drive reported node 1 EMCY 0x2310 continuous over-current (output side) (error register 0x01) while in operation enabled",
            "control word 7",
            "control word 6",
            "node 1 back to pre-operational",
            "drive left in ready to switch on at 0 rpm",
            "ERROR: drive fault",
        ],
    );
    let trace = std::fs::read_to_string(&trace).expect("trace");
    assert_in_order(
        &trace,
        &[
            "601#2B4060000F000000",
            "081#1023010000000000",
            "601#2B40600007000000",
            "601#2B40600006000000",
            "000#8001",
        ],
    );
    // The results store keeps the fault with its code and text.
    let id = [&out.stdout, &out.stderr]
        .into_iter()
        .flat_map(|text| text.lines())
        .find_map(|l| l.strip_prefix("results: run "))
        .and_then(|l| l.split_whitespace().next())
        .expect("the run's id");
    let shown = cli(&["results", "show", id, "--results", store], 0);
    assert_has(
        &shown.stdout,
        &["EMCY 0x2310 continuous over-current (output side)"],
    );
    // So does the run's page made from the store: why it ended is the fault.
    let page = dir.join("run.html");
    cli(
        &[
            "results",
            "report",
            id,
            "--results",
            store,
            "-o",
            page.to_str().unwrap(),
        ],
        0,
    );
    let page = std::fs::read_to_string(&page).expect("the run's page");
    assert_has(&page, &["EMCY 0x2310 continuous over-current (output side)"]);
}

/// A DCF's ParameterValues are a parameter set: `diff` compares them with the node,
/// `restore` writes them back behind the restore interlock (never while it is enabled).
#[test]
fn a_dcf_is_diffed_against_the_node_and_restored_behind_the_interlock() {
    use crate::support::{drivescript, stderr, stdout};
    let sim = crate::support::Simulator::start(&["--drive", "canopen", "--slcan-pty"]);
    let dcf = repo_root().join("tests/eds/cia402-node.dcf");
    let dcf = dcf.to_string_lossy().to_string();
    let can = format!("slcan:{}", sim.endpoint);
    let with = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend(["--drive", "canopen", "--dictionary", &dcf, "--can", &can]);
        drivescript(&all, "")
    };
    let out = with(&["diff", &dcf]);
    assert_eq!(out.status.code(), Some(1), "{}{}", stdout(&out), stderr(&out));
    assert_has(
        &stdout(&out),
        &["heartbeat_time", "250", "100", "1 difference(s)"],
    );
    // The objects the built-in dictionary has are found by their index without the DCF.
    let out = drivescript(&["diff", &dcf, "--drive", "canopen", "--can", &can], "");
    assert_eq!(out.status.code(), Some(1), "{}{}", stdout(&out), stderr(&out));
    assert_has(&stdout(&out), &["heartbeat_time", "1 difference(s)"]);
    // Enabled, the node is not restored.
    for word in ["6", "7", "15"] {
        let out = with(&["write", "control_word", word]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    }
    let out = with(&["restore", &dcf, "--apply"]);
    assert_ne!(out.status.code(), Some(0), "{}", stdout(&out));
    assert_has(&stderr(&out), &["nothing was written"]);
    for word in ["7", "6"] {
        with(&["write", "control_word", word]);
    }
    let out = with(&["restore", &dcf, "--apply"]);
    assert_eq!(out.status.code(), Some(0), "{}{}", stdout(&out), stderr(&out));
    assert_has(&stdout(&out), &["heartbeat_time"]);
    let out = with(&["diff", &dcf]);
    assert_eq!(out.status.code(), Some(0), "{}{}", stdout(&out), stderr(&out));
    assert_has(&stdout(&out), &["no differences"]);
}
