//! The Lenze 9400 family end to end in-process: the golden SDO frames of the 9400 manuals
//! through the explainer, the shipped recipe on the simulated node, and the endings of a
//! run on a dictionary without a device-control profile: a stop signal, a lost adapter
//! that comes back, one that does not, and one lost in the middle of a segmented transfer.

use crate::support::{
    assert_exit, assert_has, assert_lacks, cli, cli_with_dictionary, faults_before_the_run,
    load_frame_vectors, repo_root, words, InProcessRun, Simulator,
};
use drivescript::bus::CanFrame;
use drivescript::clock::SharedClock;
use drivescript::dictionary::Dictionary;
use drivescript::family::{Family, Registry};
use drivescript::run::{DictionaryArgs, PrepareSimulator};
use drivescript::sim::SimulatedDrive;
use drivescript::stop_request::{StopRequests, StopSignal};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Duration;

fn lenze() -> DictionaryArgs {
    DictionaryArgs {
        name: "lenze-9400".into(),
        ..DictionaryArgs::builtin_default()
    }
}

fn recipe(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("drivescript-lenze-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let path = dir.join("recipe.yaml");
    std::fs::write(&path, text).expect("recipe written");
    path
}

#[test]
fn the_copy_matches_the_shared_vectors() {
    let shared = repo_root().join("../shared/vectors/lenze-9400-sdo.yaml");
    if shared.exists() {
        let copy = std::fs::read_to_string(repo_root().join("tests/vectors/lenze-9400-sdo.yaml")).unwrap();
        assert_eq!(copy, std::fs::read_to_string(shared).unwrap());
    }
}

#[test]
fn every_golden_frame_explains_to_its_vector() {
    let vectors = load_frame_vectors(&repo_root().join("tests/vectors/lenze-9400-sdo.yaml"));
    assert_eq!(vectors.len(), 9);
    let registry = Registry::builtin();
    let family = registry.family("lenze-9400").unwrap();
    let dictionary = Arc::new(registry.load_dictionary("lenze-9400").unwrap());
    for v in &vectors {
        let frame = CanFrame::parse_text(&format!("{} {}", v.id, v.data)).unwrap();
        let mut explainer = family.explainer(dictionary.clone());
        let (json, valid) = explainer.json(&frame.to_bytes());
        assert!(valid, "{}: {json}", v.name);
        assert_eq!(json, v.frame, "{}", v.name);
    }
}

#[test]
fn the_printed_write_example_is_explained_as_what_it_really_sends() {
    let registry = Registry::builtin();
    let family = registry.family("lenze-9400").unwrap();
    let dictionary: Arc<Dictionary> = Arc::new(registry.load_dictionary("lenze-9400").unwrap());
    let mut explainer = family.explainer(dictionary);
    let printed = CanFrame::parse_text("602#23A75F0066000300").unwrap();
    let text = explainer.explain(&printed.to_bytes()).unwrap();
    assert_has(&text, &["C00088 rated_motor_current"]);
    // 0x00030066 = 196710 counts = 19671 A: not the 10.2 A the manual's text means.
    assert_has(&text, &["196710 = 19671 A"]);
    let corrected = CanFrame::parse_text("602#23A75F0066000000").unwrap();
    let text = explainer.explain(&corrected.to_bytes()).unwrap();
    assert_has(&text, &["102 = 10.2 A"]);
}

#[test]
fn the_shipped_recipe_passes_on_the_simulated_node_and_says_there_is_no_device_control() {
    let mut run = InProcessRun::new(repo_root().join("recipes/lenze-9400-identity.yaml"));
    run.dictionary = lenze();
    let (result, output) = run.run();
    assert_eq!(result.exit_code, 0, "{output}");
    assert!(output.contains(r#"ident = "05.00.12.07""#), "{output}");
    assert_has(
        &output,
        &[
            "rated_motor_current = 10.2 A",
            "safe stop: the lenze-9400 dictionary has no device-control profile",
            "drive state not known: the dictionary has no device-control profile",
        ],
    );
    assert_lacks(&output, &["CHECK THE DRIVE BY HAND"]);
}

const READ_FOR_A_MINUTE: &str = "name: Reading for a minute
drive: lenze-9400
steps:
  - repeat:
      for: 1 min
      steps:
        - read: [ident, heatsink_temperature]
        - dwell: 1 s
";

fn with_faults(text: &str, name: &str, stop: Arc<StopRequests>, faults: &PrepareSimulator) -> (i32, String) {
    let path = recipe(name, text);
    let mut run = InProcessRun::new(path);
    run.dictionary = lenze();
    run.stop = stop;
    run.prepare = Some(faults);
    let (result, output) = run.run();
    (result.exit_code, output)
}

#[test]
fn a_stop_signal_ends_the_run_with_the_truth_about_device_control() {
    let stop = Arc::new(StopRequests::new());
    stop.schedule(Duration::from_millis(10_500), StopSignal::INT);
    let nothing = |_: &Arc<Mutex<dyn SimulatedDrive>>, _: &SharedClock| {};
    let output = assert_exit(
        with_faults(READ_FOR_A_MINUTE, "sigint", stop, &nothing),
        130,
        &["no device-control profile"],
    );
    assert_lacks(
        &output,
        &["CHECK THE DRIVE BY HAND", "failed: the lenze-9400 dictionary"],
    );
}

#[test]
fn an_adapter_that_comes_back_is_reopened_and_the_node_checked_by_its_identity() {
    let down =
        faults_before_the_run(|f| f.line_down(Duration::from_millis(5_500), Duration::from_millis(6_500)));
    let output = assert_exit(
        with_faults(
            READ_FOR_A_MINUTE,
            "comes-back",
            Arc::new(StopRequests::new()),
            &down,
        ),
        3,
        &["the CAN adapter went away"],
    );
    assert!(
        output.contains("restored at attempt") && output.contains("the drive answers"),
        "{output}"
    );
    assert_has(&output, &["no device-control profile"]);
    assert_lacks(&output, &["CHECK THE DRIVE BY HAND"]);
}

#[test]
fn an_adapter_lost_in_the_middle_of_a_segmented_read_ends_in_check_by_hand() {
    // The identity read at the start and each loop read C00099 in three frames 100 µs
    // apart; the adapter goes away between the initiate response and the first segment.
    let down = |sim: &Arc<Mutex<dyn SimulatedDrive>>, clock: &SharedClock| {
        let start = clock.now();
        let mut sim = sim.lock().unwrap();
        sim.faults().line_down(
            start + Duration::from_micros(150),
            start + Duration::from_secs(3600),
        );
    };
    let (code, output) = with_faults(
        READ_FOR_A_MINUTE,
        "mid-transfer",
        Arc::new(StopRequests::new()),
        &down,
    );
    assert_eq!(code, 3, "{output}");
    assert_has(
        &output,
        &[
            "the CAN adapter went away",
            "CHECK THE DRIVE BY HAND",
            "could not be reached to stop it",
            "drive left in an unknown state",
        ],
    );
}

#[test]
fn the_family_reads_codes_in_dictionaries() {
    let registry = Registry::builtin();
    let family = registry.family("lenze-9400").unwrap();
    let parse = family.address_parser();
    assert_eq!(
        parse("C00002/16"),
        Ok(drivescript::dictionary::Address::indexed(0x5FFD, 16))
    );
    let d = registry.load_dictionary("lenze-9400").unwrap();
    let current = d.get("rated_motor_current").unwrap();
    assert_eq!(current.scale, 0.1, "factor 10 is 0.1 A per count");
    let _: &dyn Family = family.as_ref();
}

/// The SLCAN pseudo-terminal tests run one at a time: the one that loses its adapter
/// reopens the freed pseudo-terminal path for a while, which the other's simulator may
/// have been given meanwhile.
static SLCAN_PTY_TESTS: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// The arguments that name a 9400 as node `node` on the CAN bus `can` (`slcan:PATH`,
/// `socketcan:IF`).
pub fn node_9400<'a>(node: &'a str, can: &'a str) -> [&'a str; 6] {
    ["--drive", "lenze-9400", "--address", node, "--can", can]
}

/// `drivescript simulate` of a 9400 node `node` behind a simulated SLCAN adapter on a pty.
fn slcan_simulator(node: &str) -> Simulator {
    Simulator::start(&["--drive", "lenze-9400", "--address", node, "--slcan-pty"])
}

#[test]
fn an_slcan_pseudo_terminal_serves_the_simulated_node() {
    use crate::support::{drivescript, stderr, stdout};
    let _one_at_a_time = SLCAN_PTY_TESTS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let sim = slcan_simulator("12");
    let prefix = if cfg!(windows) { "COM" } else { "/dev/" };
    assert!(sim.endpoint.starts_with(prefix), "path {:?}", sim.endpoint);
    let can = format!("slcan:{}", sim.endpoint);
    let with = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend(node_9400("12", &can));
        all.extend(["--timeout", "300ms"]);
        drivescript(&all, "")
    };

    let out = with(&[
        "read",
        "ident",
        "heatsink_temperature",
        "rated_motor_current",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("json");
    assert_eq!(json[0]["value"], "05.00.12.07");
    assert_eq!(json[1]["value"], 43.0);
    assert_eq!(json[2]["value"], 10.2);
    assert_eq!(json[2]["unit"], "A");

    // A raw code with its type; the node keeps it between connections.
    let out = with(&["write", "C00011", "3000", "--type", "i32"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = with(&["read", "C00011", "--json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_has(&stdout(&out), &["3000"]);

    // An unknown code: the node's abort, named.
    let out = with(&["read", "C00999"]);
    assert_eq!(out.status.code(), Some(3), "{}", stdout(&out));
    let err = stderr(&out);
    assert!(
        err.contains("C00999") && err.contains("0x06020000 object does not exist in the object dictionary"),
        "{err}"
    );

    // Another node on the same bus stays silent: a clear no-reply error.
    let quick = ["--timeout", "100ms", "--retries", "0"];
    let out = cli(
        &[&["read", "ident"][..], &node_9400("13", &can), &quick].concat(),
        3,
    );
    assert_has(&out.stderr, &["no reply from drive node 13"]);

    // A recipe through the adapter.
    let identity = ["run", "recipes/lenze-9400-identity.yaml"];
    let out = cli(&[&identity[..], &node_9400("12", &can)].concat(), 0);
    assert_has(&out.stdout, &["PASSED"]);
}

#[test]
fn decode_reads_candump_frames_and_gives_the_vectors_json() {
    use crate::support::{drivescript, stdout};
    let vectors = load_frame_vectors(&repo_root().join("tests/vectors/lenze-9400-sdo.yaml"));
    let input: String = vectors
        .iter()
        .map(|v| format!("{}#{}\n", v.id, v.data.replace(' ', "")))
        .collect();
    let out = drivescript(&["decode", "--protocol", "lenze-9400", "--json"], &input);
    assert_eq!(out.status.code(), Some(0), "{}", stdout(&out));
    let lines: Vec<serde_json::Value> = stdout(&out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("json"))
        .collect();
    assert_eq!(lines.len(), vectors.len());
    for (got, v) in lines.iter().zip(&vectors) {
        assert_eq!(got, &v.frame, "{}", v.name);
    }
    // Unquoted, as the shell splits `ID data…`; and a frame that is no SDO.
    let out = cli(
        &words("decode --protocol lenze-9400 605 40 c2 5f 00 00 00 00 00"),
        0,
    );
    assert_has(&out.stdout, &["C00061 heatsink_temperature"]);
    let out = cli(&["decode", "--protocol", "lenze-9400", "123#00"], 1);
    assert_has(&out.stdout, &["not an SDO channel"]);
}

#[test]
fn a_trace_is_a_candump_log_that_decode_explains_again() {
    use crate::support::{drivescript, stdout};
    let dir = std::env::temp_dir().join(format!("drivescript-lenze-trace-{}", std::process::id()));
    let trace = dir.join("run.log");
    cli(
        &[
            "run",
            "recipes/lenze-9400-identity.yaml",
            "--drive",
            "lenze-9400",
            "--fast",
            "--trace",
            trace.to_str().unwrap(),
        ],
        0,
    );
    let text = std::fs::read_to_string(&trace).unwrap();
    let frames: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert!(frames.len() >= 6, "{text}");
    // Exactly candump -l's shape: (seconds.micros) interface ID#DATA.
    for line in &frames {
        let parts: Vec<&str> = line.split(' ').collect();
        assert_eq!(parts.len(), 3, "{line}");
        assert!(
            parts[0].starts_with('(') && parts[0].ends_with(')') && parts[0].len() == 19,
            "{line}"
        );
        assert_eq!(parts[1], "can0");
        assert!(CanFrame::parse_text(parts[2]).is_ok(), "{line}");
    }
    assert_eq!(frames[0], "(0000000000.000000) can0 601#409C5F0000000000");
    let out = drivescript(&["decode", "--protocol", "lenze-9400"], &text);
    assert_eq!(out.status.code(), Some(0), "{}", stdout(&out));
    assert_has(&stdout(&out), &["reply C00099 ident: segmented, 11 bytes"]);
    let _ = std::fs::remove_dir_all(dir);
}

#[cfg(unix)]
#[test]
fn an_slcan_adapter_that_goes_away_during_a_run_ends_in_check_by_hand() {
    use std::io::{BufRead, Read};
    let _one_at_a_time = SLCAN_PTY_TESTS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let path = recipe("slcan-gone", READ_FOR_A_MINUTE);
    // Node 37, which no other test simulates: when the pseudo-terminal's number is given
    // to another test's simulator meanwhile, reopening it must not find this node there.
    let sim = slcan_simulator("37");
    let can = format!("slcan:{}", sim.endpoint);
    let mut run = crate::support::command()
        .args(["run", path.to_str().unwrap()])
        .args(node_9400("37", &can))
        .args(["--reconnect-timeout", "300ms"])
        .current_dir(repo_root())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("run starts");
    let mut out = std::io::BufReader::new(run.stdout.take().expect("stdout is piped"));
    // Once reads have gone through the adapter, it goes away.
    let mut text = String::new();
    while !text.contains("  ok  ") {
        let mut line = String::new();
        if out.read_line(&mut line).expect("run output") == 0 {
            break;
        }
        text.push_str(&line);
    }
    drop(sim);
    out.read_to_string(&mut text).expect("the rest of the output");
    let status = run.wait().expect("run ends");
    assert_eq!(status.code(), Some(3), "{text}");
    // Where the hang-up shows (a read or a write) decides the wording of the port's error.
    assert_has(
        &text,
        &[
            &format!("I/O error on {}", can.trim_start_matches("slcan:")),
            "gave up reopening node 37",
            "CHECK THE DRIVE BY HAND",
        ],
    );
}

#[test]
fn a_can_trace_decoded_as_a_serial_protocol_says_which_protocol_to_give() {
    use crate::support::{drivescript, stderr};
    // Without --protocol a candump log is read as the CAN family's; a serial one given
    // explicitly is refused with the way out.
    let out = drivescript(
        &["decode", "--protocol", "sd2"],
        "(0000000000.000000) can0 601#409C5F0000000000\n",
    );
    assert_eq!(out.status.code(), Some(2));
    assert_has(
        &stderr(&out),
        &["is a CAN frame, not a sd2 telegram; give --protocol lenze-9400"],
    );
}

#[test]
fn the_commissioning_recipe_is_refused_for_a_drive_without_device_control() {
    let text = std::fs::read_to_string(repo_root().join("recipes/commissioning.yaml"))
        .unwrap()
        .replace("drive: sd2", "drive: lenze-9400");
    let path = recipe("commissioning", &text);
    let err = cli(&["check", path.to_str().unwrap(), "--drive", "lenze-9400"], 2).stderr;
    assert_has(&err, &["the state `operation_enabled` needs device control, but the lenze-9400 dictionary has no `profile:`", "`disable_operation` needs device control", "nothing was sent to the drive"]);
}

/// A vendor's EDS gives the 9400 its full code list: each object it adds is found by its
/// code too, and the codes the dictionary has keep their entries.
#[test]
fn an_eds_adds_codes_found_by_their_code_notation() {
    let eds = "tests/eds/lenze-9400-codes.eds";
    let out = cli_with_dictionary(&["objects", "speed"], "lenze-9400", eds, 0);
    assert_has(
        &out.stdout,
        &[
            "reference_speed  C00011 (index 0x5FF4)",
            "C00011, 0x5FF4, Reference speed",
        ],
    );
    let out = cli_with_dictionary(&["write", "C00011", "1500"], "lenze-9400", eds, 0);
    assert_has(&out.stdout, &["reference_speed"]);
    let out = cli_with_dictionary(&["read", "0x5F9C"], "lenze-9400", eds, 0);
    assert_has(&out.stdout, &["ident", "05.00.12.07"]);
}
