//! The Control Techniques family end to end: the golden messages of the UD70/UD78 manuals
//! (including the printed one whose block check is wrong), `decode` naming control
//! characters, the shipped commissioning recipe with only `drive:` changed (in virtual
//! time and through a real pseudo-terminal), exact decimals on the wire, a group write
//! that gets no reply and is not repeated, and Ctrl-C during a run on the simulated drive.

use crate::live_run::ctrl_c_during_a_dwell;
use crate::support::{
    assert_every_vector_decodes, assert_has, assert_matches_shared, cli, control_words, drivescript,
    load_vectors, repo_root, scratch_file, stderr, stdout, write_file, InProcessRun,
};
use drivescript::bus::MemoryTransport;
use drivescript::clock::{SharedClock, VirtualClock};
use drivescript::dictionary::{Address, DataType, RawValue};
use drivescript::family::ct_ansi::codec::{Reply, Request};
use drivescript::family::ct_ansi::CtSimulator;
use drivescript::family::{Family, LinkContext, LinkOptions, Registry, SimPeer};
use drivescript::hex::parse_hex;
use drivescript::sim::SimConfig;
use serde_json::Value;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

fn vectors() -> Vec<crate::support::Vector> {
    load_vectors(&repo_root().join("tests/vectors/ct-ansi.yaml"))
}

fn family() -> Arc<dyn Family> {
    Registry::builtin().family("ct-ansi").expect("the ct-ansi family")
}

fn explainer() -> Box<dyn drivescript::link::TelegramExplainer> {
    let dictionary = Registry::builtin()
        .load_dictionary("ct-unidrive-sp")
        .expect("the built-in dictionary");
    family().explainer(Arc::new(dictionary))
}

#[test]
fn the_copy_matches_the_shared_vectors() {
    assert_matches_shared(&vectors(), "ct-ansi.yaml");
}

#[test]
fn every_vector_decodes_to_its_frame_or_is_rejected() {
    let mut e = explainer();
    assert_every_vector_decodes(&vectors(), 12, |bytes| e.json(bytes));
}

#[test]
fn rejections_give_the_documented_reason() {
    let reason = |prefix: &str| {
        let v = vectors()
            .into_iter()
            .find(|v| v.name.starts_with(prefix))
            .unwrap();
        Request::decode(&parse_hex(&v.hex).unwrap())
            .unwrap_err()
            .to_string()
    };
    // "block check: expected 0x21 (!), got 0x31 (1)"
    assert!(
        reason("write #1.21 = +76.4 as printed").starts_with("block check: expected 0x21 (!), got 0x31 (1)"),
        "{}",
        reason("write #1.21 = +76.4 as printed")
    );
    // "address digits not doubled (1 2)"
    assert!(reason("write with undoubled").starts_with("address digits not doubled (1 2)"));
}

#[test]
fn the_encoder_reproduces_the_canonical_messages() {
    for v in vectors() {
        let Ok(bytes) = parse_hex(&v.hex) else { continue };
        // Messages written the way drivescript writes them come out byte for byte.
        if let Ok(r) = Request::decode(&bytes) {
            let again = r.encode().unwrap();
            if v.name.contains("-34.5") || v.name.starts_with("read #") {
                assert_eq!(again, bytes, "{}", v.name);
            }
        }
        if let Ok(r @ (Reply::Accepted | Reply::Refused | Reply::NoSuchParameter)) = Reply::decode(&bytes) {
            assert_eq!(r.encode().unwrap(), bytes, "{}", v.name);
        }
    }
}

#[test]
fn decode_shows_control_characters_by_name_and_rejects_the_printed_example() {
    for protocol in ["ct-unidrive-sp", "ct-ansi", "ct_ansi"] {
        let text = cli(
            &[
                "decode",
                "--protocol",
                protocol,
                "04 31 31 32 32 30 31 32 31 05",
                "02 30 31 32 31 2d 34 37 2e 36 03 37",
                "04 32 32 36 36 02 30 31 32 31 2b 30 37 36 2e 34 03 31",
            ],
            1,
        )
        .stdout;
        assert_has(&text, &["message   EOT 11220121 ENQ", "request   read #1.21 speed_setpoint of drive 1.2", "reply     #1.21 speed_setpoint = -47.6 rpm", "rejected: block check: expected 0x21 (!), got 0x31 (1) at byte 17, in `EOT 2266 STX 0121+076.4 ETX 1`"]);
    }
    let out = drivescript(&["decode", "--protocol", "ct-ansi", "06", "15", "04"], "");
    // Three single bytes given unquoted read as one message; quoted they are three.
    assert_eq!(out.status.code(), Some(1), "{}", stdout(&out));
    let out = drivescript(&["decode", "--protocol", "ct-ansi", "--json", "06"], "");
    assert_eq!(stdout(&out).trim(), r#"{"reply":"ack"}"#);
}

#[test]
fn decode_reads_a_hex_data_field_and_names_a_bad_hex_digit_by_its_byte() {
    let good = "02 30 36 32 31 58 38 33 03 55";
    let bad = "02 30 36 32 31 58 38 47 03 21";
    let text = cli(&["decode", "--protocol", "ct-ansi", good, bad], 1).stdout;
    assert_has(
        &text,
        &[
            "= 131",
            "data      `X83`: hexadecimal",
            "rejected: byte 7: expected a hex digit (0-9, A-F) after X, got 'G'",
        ],
    );
    let out = drivescript(&["decode", "--protocol", "ct-ansi", "--json", good], "");
    assert!(stdout(&out).contains(r#""value":"131""#), "{}", stdout(&out));
}

/// The shipped commissioning recipe with only `drive:` changed.
fn ct_commissioning(dir: &str) -> PathBuf {
    let text = std::fs::read_to_string(repo_root().join("recipes/commissioning.yaml")).unwrap();
    assert!(text.contains("\ndrive: sd2\n"));
    let dir = std::env::temp_dir().join(format!("drivescript-ct-{dir}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("commissioning.yaml");
    std::fs::write(&path, text.replace("\ndrive: sd2\n", "\ndrive: ct-unidrive-sp\n")).unwrap();
    path
}

#[test]
fn the_commissioning_recipe_runs_on_the_simulated_ct_drive_with_exact_decimals() {
    let recipe = ct_commissioning("virtual");
    let trace = recipe.with_file_name("run.trace");
    let mut run = InProcessRun::new(recipe);
    run.set = vec![("speed".into(), "1500.5rpm".into())];
    let (result, _, trace) = run.run_traced(
        &trace,
        0,
        &[
            "using the built-in simulated CT-ANSI drive (drive 1.1",
            "go to operation_enabled  enable operation → operation enabled",
            "finally 1  ok    disable_operation  control word 129",
            "finally 2  ok    shutdown  control word 128",
            "drive left in switched on at 0 rpm",
        ],
    );
    assert_eq!(control_words(&result), vec![131, 129, 128]);
    // 1500.5 rpm goes on the wire as the text 1500.5, after the control-word enable.
    assert_has(
        &trace,
        &[
            "04 31 31 31 31 02 30 31 32 31 31 35 30 30 2e 35 03",
            "write #1.21 speed_setpoint = 1500.5 rpm to drive 1.1",
            "write #6.43 control_word_enable = 1 to drive 1.1",
        ],
    );
}

/// Files in the field written before family ids were unified (`ct_ansi`): a recipe's
/// `drive:` and a user dictionary's `family:` still work; `check` notes where the
/// dictionary spells the old id and what to write instead.
#[test]
fn files_with_the_former_family_id_still_work_and_check_notes_the_new_spelling() {
    let (dir, recipe) = scratch_file(
        "former-id",
        "old.yaml",
        "name: old\ndrive: ct_ansi\nsteps:\n  - read: [feedback]\n",
    );
    let mine = write_file(
        &dir,
        "mine.yaml",
        "# ours\nfamily: ct_ansi\nobjects:\n  - name: speed_actual\n    aliases: [feedback]\n    address: \"#3.02\"\n    type: i32\n    decimals: 1\n    unit: rpm\n    access: ro\n",
    );
    let (recipe, mine) = (recipe.to_str().unwrap(), mine.to_str().unwrap());
    let out = cli(&["check", recipe, "--dictionary", mine], 0);
    assert_has(&out.stdout, &["ok  "]);
    assert_has(
        &out.stderr,
        &[
            &format!("note: {mine}:2:9: `family: ct_ansi` is the former spelling of the family id `ct-ansi`; it still works"),
            "  help: write `family: ct-ansi`",
        ],
    );
    let run = cli(&["run", recipe, "--dictionary", mine], 0);
    assert_has(&run.stdout, &["read speed_actual"]);
}

#[test]
fn raw_parameters_in_the_drives_own_notation() {
    let text = cli(
        &["read", "#5.04", "5.05", "#11.29", "--drive", "ct-unidrive-sp"],
        0,
    )
    .stdout;
    assert_has(&text, &["#5.04"]);
    let out = cli(&["write", "#1.21", "1500.5", "--drive", "ct-unidrive-sp"], 0);
    assert_has(&out.stdout, &["#1.21 = 1500.5 written (raw 1500.5)"]);
    let out = cli(&["read", "#42.42", "--drive", "ct-unidrive-sp"], 3);
    assert_has(
        &out.stderr,
        &["the drive has no parameter #42.42 (it answered EOT)"],
    );
}

/// A drive that accepts every write (ACK) and reads nothing; it notes what reached it.
struct AcceptsWrites(Vec<Vec<u8>>);

impl drivescript::bus::Peer for AcceptsWrites {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<drivescript::bus::PeerReply> {
        self.0.push(bytes.to_vec());
        vec![drivescript::bus::PeerReply {
            at: now + Duration::from_millis(1),
            bytes: vec![0x06],
        }]
    }
}

#[test]
fn a_write_of_the_baud_rate_parameter_waits_20_ms_and_says_to_restart_with_baud() {
    let f = family();
    let clock = Arc::new(VirtualClock::new());
    let peer = Arc::new(std::sync::Mutex::new(AcceptsWrites(Vec::new())));
    let line = MemoryTransport::shared("line", peer.clone(), clock.clone());
    let options = LinkOptions {
        reply_timeout: Duration::from_secs(1),
        retries: 2,
        extra: vec![("baud-parameter".to_string(), "#11.25".to_string())],
    };
    let context = LinkContext {
        clock: clock.clone(),
        observer: None,
        stop: None,
    };
    let drive = f.parse_drive_address(Some("1.2")).unwrap();
    let mut access = f
        .open(&drivescript::bus::Bus::Bytes(line), &drive, &options, context)
        .unwrap();
    let e = access
        .write(&Address::indexed(11, 25), &RawValue::Int(6), DataType::I32)
        .unwrap_err()
        .to_string();
    // The turnaround (2 ms), the ACK at the old rate (1 ms), then the drive's 20 ms.
    assert_eq!(drivescript::clock::Clock::now(&*clock), Duration::from_millis(23));
    assert_has(
        &e,
        &[
            "the write of #11.25 = 6 was accepted (ACK), and drivescript waited 20 ms",
            "restart drivescript with --baud",
        ],
    );
    let e = access
        .read(&Address::indexed(1, 21), DataType::I32)
        .unwrap_err()
        .to_string();
    assert_has(&e, &["changed the drive's baud rate"]);
    assert_eq!(
        peer.lock().unwrap().0.len(),
        1,
        "nothing sent at the old rate after it"
    );
}

#[test]
fn a_group_write_gets_no_reply_and_is_not_repeated() {
    let f = family();
    let clock: SharedClock = Arc::new(VirtualClock::new());
    let drive = f.parse_drive_address(Some("1.2")).unwrap();
    let device = f.simulator(&drive, SimConfig::default());
    let SimPeer::Bytes(peer) = device.peer else {
        panic!("a byte peer")
    };
    // Even with every reply dropped, the group write neither waits nor retries.
    device.drive.lock().unwrap().faults().drop_replies(10);
    let line = MemoryTransport::shared("line", peer, clock.clone());
    let group = f.parse_drive_address(Some("1.0")).unwrap();
    let options = LinkOptions {
        reply_timeout: Duration::from_secs(1),
        retries: 2,
        extra: vec![],
    };
    let context = LinkContext {
        clock: clock.clone(),
        observer: None,
        stop: None,
    };
    let mut access = f
        .open(&drivescript::bus::Bus::Bytes(line), &group, &options, context)
        .unwrap();
    let outcome = access
        .write(
            &Address::indexed(1, 21),
            &RawValue::Decimal {
                digits: 1005,
                places: 1,
            },
            DataType::I32,
        )
        .unwrap();
    assert_eq!(outcome, drivescript::drive::WriteOutcome::Stored);
    assert!(
        clock.now() < Duration::from_millis(100),
        "no reply was waited for: {:?}",
        clock.now()
    );
    let mut sim = device.drive.lock().unwrap();
    let ct = sim.as_any_mut().downcast_mut::<CtSimulator>().unwrap();
    assert_eq!(ct.received().len(), 1, "sent once");
    assert_eq!(ct.setpoint_rpm(), 100.5, "and acted on by drive 1.2");
    // A read to a group address is refused before anything is sent.
    drop(sim);
    let e = access.read(&Address::indexed(1, 21), DataType::I32).unwrap_err();
    assert!(e.to_string().contains("takes writes only"), "{e}");
}

#[test]
fn the_commissioning_recipe_runs_behind_an_adapter_that_echoes() {
    let sim = crate::support::Simulator::start(&["--drive", "ct-unidrive-sp", "--pty", "--echo"]);
    let recipe = ct_commissioning("echo");
    let out = drivescript(
        &["run", recipe.to_str().unwrap(), "--port", &sim.endpoint, "-v"],
        "",
    );
    let (text, trace) = (stdout(&out), stderr(&out));
    assert_eq!(out.status.code(), Some(0), "{text}{trace}");
    assert_has(&text, &["drive left in switched on at 0 rpm"]);
    assert_has(&trace, &["echo of our message skipped: EOT 1111"]);
    assert!(
        !trace.contains("retry"),
        "no echo is taken for a bad reply: {trace}"
    );
    // A read of a parameter the drive lacks: its EOT comes after the echo's.
    let out = drivescript(
        &[
            "read",
            "#9.99",
            "--port",
            &sim.endpoint,
            "--drive",
            "ct-unidrive-sp",
        ],
        "",
    );
    let text = format!("{}{}", stdout(&out), stderr(&out));
    assert_has(&text, &["has no parameter #9.99 (it answered EOT)"]);
}

#[test]
fn the_commissioning_recipe_runs_through_a_pseudo_terminal() {
    let sim = crate::support::Simulator::start(&["--drive", "ct-unidrive-sp", "--pty"]);
    let recipe = ct_commissioning("pty");
    let text = sim.cli(&["run", recipe.to_str().unwrap()], 0).stdout;
    assert_has(
        &text,
        &[
            &format!("drive 1.1 on {} at 4800 7E1", sim.endpoint),
            "drive left in switched on at 0 rpm",
        ],
    );
    // The group address reaches the same drive, without a reply.
    let ct = ["--drive", "ct-unidrive-sp"];
    sim.cli(
        &[&["write", "speed_setpoint", "12.5", "--address", "1.0"][..], &ct].concat(),
        0,
    );
    let out = sim.cli(&[&["read", "speed_setpoint"][..], &ct].concat(), 0);
    assert_has(&out.stdout, &["12.5 rpm"]);
}

#[test]
fn ctrl_c_during_a_run_on_the_simulated_ct_drive_stops_it() {
    let sim = ctrl_c_during_a_dwell(
        ("ct-unidrive-sp", "300 rpm"),
        Duration::from_millis(200),
        ("drive 1.1", "7O1"),
        &[
            "disable_operation (default finally)  control word 129",
            "shutdown (default finally)  control word 128",
            "drive left in switched on",
        ],
    );
    // Read back from the drive itself: stopped.
    let out = drivescript(
        &["state", "--port", &sim.endpoint, "--drive", "ct-unidrive-sp"],
        "",
    );
    assert_has(&stdout(&out), &["switched on"]);
}

#[test]
fn the_recipe_schema_offers_only_what_the_ct_drive_has() {
    let out = cli(&["schema", "--drive", "ct-unidrive-sp"], 0);
    let schema: Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(
        schema["properties"]["drive"]["enum"],
        serde_json::json!(["ct-ansi", "ct-unidrive-sp"])
    );
    let text = schema.to_string();
    assert!(
        !text.contains("quick_stop") && !text.contains("ready_to_switch_on"),
        "{text}"
    );
    assert!(text.contains("enable_operation") && text.contains("switched_on"));
}
