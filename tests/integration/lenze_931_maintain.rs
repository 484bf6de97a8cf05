//! `drivescript maintain` on the simulated Lenze 931, in virtual time: each action's
//! command line and the drive's reply, the refusals (no --force where the state cannot be
//! read; an enabled drive even with --force; no confirmation), a lost or garbled reply,
//! the family's list of destructive actions, and one action through a real pty.

use crate::lenze_931::{completed_template, dictionary_args, with_lenze};
use crate::support::{assert_has, cli, drivescript, scratch, stderr, stdout};
use drivescript::bus::Peer;
use drivescript::drive::{DeviceState, DriveError};
use drivescript::family::lenze_931::{Lenze931Family, LenzeSimulator};
use drivescript::family::Family;
use drivescript::family::Registry;
use drivescript::run::{run_maintain, MaintainRequest, PrepareMaintained};
use drivescript::run::{ConnectionArgs, DictionaryArgs};
use drivescript::sim::SimulatedDrive;
use drivescript::stop_request::StopRequests;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};
use std::time::Duration;

/// What one `maintain` did: exit code, standard output, errors, and the request lines
/// the simulated drive received after `setup` (lines sent to it first).
struct Outcome {
    code: i32,
    out: String,
    err: String,
    requests: Vec<String>,
    mode: u16,
    line_rate: u32,
}

impl Outcome {
    /// Fails the test, showing both outputs, unless `maintain` exited with `code` after
    /// sending exactly `requests`.
    #[track_caller]
    fn sent(&self, code: i32, requests: &[&str]) {
        assert_eq!(self.code, code, "{}{}", self.out, self.err);
        assert_eq!(self.requests, requests);
    }
}

fn maintain(
    dictionary: &DictionaryArgs,
    action: &str,
    value: Option<&str>,
    force: bool,
    confirm: Option<bool>,
    setup: &[&str],
    prepare: &dyn Fn(&mut LenzeSimulator),
) -> Outcome {
    let setup_count = Mutex::new(0);
    let before = |sim: &Arc<Mutex<dyn SimulatedDrive>>| {
        with_lenze(sim, |s| {
            for line in setup {
                s.receive(format!("{line}\r").as_bytes(), Duration::ZERO);
            }
            *setup_count.lock().unwrap_or_else(PoisonError::into_inner) = s.requests().len();
            prepare(s);
        })
    };
    let mut asked = Vec::new();
    let mut ask = |question: &str| {
        asked.push(question.to_string());
        confirm.unwrap_or(false)
    };
    let request = MaintainRequest {
        registry: &Registry::builtin(),
        dictionary,
        connection: &ConnectionArgs::simulated(),
        action: Some(action),
        value,
        force,
        confirm: confirm.map(|_| &mut ask as &mut dyn FnMut(&str) -> bool),
        stop: Arc::new(StopRequests::new()),
        prepare_simulator: Some(&before),
    };
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let result = run_maintain(request, &mut out, &mut err);
    let sim = result.simulator.expect("the simulated drive was opened");
    let skip = *setup_count.lock().unwrap_or_else(PoisonError::into_inner);
    let (requests, mode, line_rate) = with_lenze(&sim, |s| {
        (s.requests()[skip..].to_vec(), s.operating_mode(), s.line_rate())
    });
    let mut err = String::from_utf8_lossy(&err).to_string();
    if confirm.is_some() {
        err.push_str(&format!("asked: {asked:?}\n"));
    }
    Outcome {
        code: result.exit_code,
        out: String::from_utf8_lossy(&out).to_string(),
        err,
        requests,
        mode,
        line_rate,
    }
}

/// Runs one `maintain` on the simulated 931 with what a test needs to vary: who answers
/// the question, the stop requests and what is done to the simulated drive first. Returns
/// the exit code, the errors and every request line the drive received.
fn run_request<'a>(
    dictionary: &'a DictionaryArgs,
    action: &'a str,
    force: bool,
    confirm: Option<&'a mut (dyn FnMut(&str) -> bool + 'a)>,
    stop: Arc<StopRequests>,
    prepare: Option<&'a PrepareMaintained<'a>>,
) -> (i32, String, Vec<String>) {
    static REGISTRY: OnceLock<Registry> = OnceLock::new();
    static CONNECTION: OnceLock<ConnectionArgs> = OnceLock::new();
    let request = MaintainRequest {
        registry: REGISTRY.get_or_init(Registry::builtin),
        dictionary,
        connection: CONNECTION.get_or_init(ConnectionArgs::simulated),
        action: Some(action),
        value: None,
        force,
        confirm,
        stop,
        prepare_simulator: prepare,
    };
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let result = run_maintain(request, &mut out, &mut err);
    let requests = result
        .simulator
        .map(|sim| with_lenze(&sim, |s| s.requests().to_vec()))
        .unwrap_or_default();
    (
        result.exit_code,
        String::from_utf8_lossy(&err).to_string(),
        requests,
    )
}

fn builtin() -> DictionaryArgs {
    dictionary_args(None)
}

fn no_prepare(_: &mut LenzeSimulator) {}

/// `maintain --force` with the built-in dictionary: `setup` lines sent to the simulated
/// 931 first, then `prepare` done to it.
fn forced(
    action: &str,
    value: Option<&str>,
    setup: &[&str],
    prepare: &dyn Fn(&mut LenzeSimulator),
) -> Outcome {
    maintain(&builtin(), action, value, true, None, setup, prepare)
}

#[test]
fn each_action_sends_its_command_once_and_reads_the_documented_reply() {
    let reset = forced("reset", None, &["OW:0014:00000003"], &no_prepare);
    reset.sent(0, &["RESET!"]);
    assert_has(
        &reset.out,
        &[
            "reset: sending RESET! to the 931 on",
            "done: the drive answered `931 SIMULATED: reset`",
        ],
    );
    assert_eq!(reset.mode, 0, "the reset drive has its default operating mode");

    let init = forced("init", None, &["OW:0014:00000002"], &no_prepare);
    init.sent(0, &["INIT!"]);
    assert_has(
        &init.out,
        &["done: the drive answered `931 SIMULATED: default parameter set loaded`"],
    );
    assert_eq!(init.mode, 0, "the default parameter set is back");

    // SEP! loads what SAVE! stored in flash, over the mode written since.
    let load = forced(
        "load",
        None,
        &["OW:0014:00000002", "SAVE!", "OW:0014:00000001"],
        &no_prepare,
    );
    load.sent(0, &["SEP!"]);
    assert_has(
        &load.out,
        &["load: sending SEP! to", "done: the drive answered `DONE`"],
    );
    assert_eq!(load.mode, 2);

    let baud = forced("baud", Some("19200"), &[], &no_prepare);
    baud.sent(0, &["BAUD19200"]);
    assert_eq!(baud.line_rate, 19200);
    assert_has(
        &baud.out,
        &[
            "baud 19200: sending BAUDbbbb with RATE 19200 to",
            "done: the drive answered `OK!`",
            "the drive now talks at 19200 baud, not at the rate used so far",
        ],
    );
    // Without a profile each of them says plainly that the state cannot be checked.
    assert_has(&baud.err, &["warning: the drive's state cannot be checked: the lenze-931 dictionary has no device-control profile"]);
}

#[test]
fn without_force_nothing_is_sent_where_the_state_cannot_be_read() {
    for (action, value) in [
        ("reset", None),
        ("init", None),
        ("load", None),
        ("baud", Some("19200")),
    ] {
        let o = maintain(&builtin(), action, value, false, Some(true), &[], &no_prepare);
        assert_eq!(o.code, 2, "{action}: {}{}", o.out, o.err);
        assert!(o.requests.is_empty(), "{action}: {:?}", o.requests);
        assert!(
            o.err.contains("the drive's state cannot be checked: the lenze-931 dictionary has no device-control profile, so drivescript cannot tell whether the drive is enabled. Make sure the drive is disabled and the motor at rest, then give --force; nothing was sent"),
            "{action}: {}",
            o.err
        );
        // A confirmation cannot stand in for the state: nobody was asked.
        assert_has(&o.err, &["asked: []"]);
    }
}

#[test]
fn with_a_profile_an_enabled_drive_is_refused_and_a_disabled_one_confirmed() {
    let dir = scratch("maintain-profile");
    let with_profile = dictionary_args(Some(completed_template(&dir)));
    let enable = ["OW:0020:00000006", "OW:0020:00000007", "OW:0020:0000000F"];
    let o = maintain(&with_profile, "reset", None, true, None, &enable, &no_prepare);
    assert_eq!(o.code, 2, "{}{}", o.out, o.err);
    assert_has(&o.err, &["error: the drive is in operation enabled, and reset is refused while it is enabled (the drive restarts)"]);
    assert_has(
        &o.err,
        &["disable it first with `drivescript stop` and the same connection options"],
    );
    assert!(!o.requests.iter().any(|r| r == "RESET!"), "{:?}", o.requests);

    // Disabled: no --force and nobody to ask is a refusal; a typed no too; a yes sends.
    let o = maintain(&with_profile, "init", None, false, None, &[], &no_prepare);
    assert_eq!(o.code, 2, "{}", o.err);
    assert_has(&o.err, &["init is destructive (the default parameter set replaces the parameters in use): give --force, or run it on a terminal to confirm; nothing was sent"]);
    assert!(!o.requests.iter().any(|r| r == "INIT!"), "{:?}", o.requests);
    let o = maintain(&with_profile, "init", None, false, Some(false), &[], &no_prepare);
    assert_eq!(o.code, 2, "{}", o.err);
    assert_has(
        &o.err,
        &[
            "error: init was not confirmed; nothing was sent",
            "The drive is in switch on disabled. Type yes to go on:",
        ],
    );
    let o = maintain(&with_profile, "init", None, false, Some(true), &[], &no_prepare);
    assert_eq!(o.code, 0, "{}{}", o.out, o.err);
    assert_eq!(o.requests.last().map(String::as_str), Some("INIT!"));
}

#[test]
fn a_lost_or_garbled_reply_is_not_repeated_and_says_what_to_check() {
    let o = forced("reset", None, &[], &|s: &mut LenzeSimulator| {
        s.faults().drop_replies(5);
    });
    // Sent once.
    o.sent(3, &["RESET!"]);
    assert_has(&o.err, &["error: reset failed: no reply", "whether the drive carried out reset is unknown: check the drive before repeating it (a drive that restarts may answer later than --timeout allows)"]);
    let o = forced("baud", Some("38400"), &[], &|s: &mut LenzeSimulator| {
        s.faults().drop_replies(5);
    });
    o.sent(3, &["BAUD38400"]);
    assert_has(
        &o.err,
        &["the drive may already talk at the new rate: try again with --baud 38400"],
    );
    // A reply that is not the documented one (`DONE` with a character lost).
    let o = forced("load", None, &[], &|s: &mut LenzeSimulator| {
        s.faults().corrupt_checksum(1);
    });
    o.sent(3, &["SEP!"]);
    assert_has(
        &o.err,
        &[
            "error: load failed:",
            "it is not sent again",
            "whether the drive carried out load is unknown",
        ],
    );
}

#[test]
fn the_family_says_which_actions_it_has_and_which_are_destructive() {
    let registry = Registry::builtin();
    let lenze = registry.family("lenze-931").expect("lenze-931");
    let actions: Vec<(&str, bool)> = lenze
        .maintenance_actions()
        .iter()
        .map(|a| (a.name, a.destructive.is_some()))
        .collect();
    assert_eq!(
        actions,
        [("reset", true), ("init", true), ("load", true), ("baud", true)]
    );
    for other in ["sd2", "ct-ansi", "lenze-9400"] {
        let family = registry.family(other).expect(other);
        assert!(family.maintenance_actions().is_empty(), "{other}");
    }
    let out = cli(&["maintain", "--drive", "lenze-931"], 0);
    assert_has(
        &out.stdout,
        &[
            "  baud RATE  BAUDbbbb  set the baud rate; the drive answers OK!",
            "destructive: the drive restarts; needs --force or a confirmation",
        ],
    );
    let out = cli(&["maintain", "--drive", "sd2", "reset"], 2);
    assert_has(
        &out.stderr,
        &["error: the sd2 family has no maintenance actions; nothing was sent"],
    );
    let out = cli(&["maintain", "--drive", "lenze-931", "rest", "--force"], 2);
    assert_has(&out.stderr, &["did you mean `reset`?"]);
}

#[test]
fn through_a_pseudo_terminal_baud_changes_the_rate_and_says_how_to_reconnect() {
    let sim = crate::support::Simulator::start(&["--drive", "lenze-931", "--pty"]);
    let port = sim.endpoint.as_str();
    // Not on a terminal and without --force: refused, nothing sent.
    let out = drivescript(
        &[
            "maintain",
            "baud",
            "19200",
            "--drive",
            "lenze-931",
            "--port",
            port,
        ],
        "yes\n",
    );
    assert_eq!(out.status.code(), Some(2), "{}", stdout(&out));
    assert_has(&stderr(&out), &["then give --force; nothing was sent"]);
    let text = cli(
        &[
            "maintain",
            "baud",
            "19200",
            "--force",
            "--drive",
            "lenze-931",
            "--port",
            port,
        ],
        0,
    )
    .stdout;
    assert_has(&text, &["done: the drive answered `OK!`", &format!(
            "the drive now talks at 19200 baud, not at the rate used so far: reconnect with --port {port} --baud 19200 on every command from now on"
        )]);
    // The simulated line keeps working: the next command at the new rate is answered.
    let out = cli(
        &[
            "read",
            "TYPE?",
            "--drive",
            "lenze-931",
            "--port",
            port,
            "--baud",
            "19200",
        ],
        0,
    );
    assert_has(&out.stdout, &["\"0931\""]);
}

#[test]
fn ctrl_c_at_the_question_sends_nothing_and_exits_130() {
    let dir = scratch("maintain-ctrl-c");
    let with_profile = dictionary_args(Some(completed_template(&dir)));
    let stop = Arc::new(StopRequests::new());
    let signalled = stop.clone();
    let mut ask = |_: &str| {
        signalled.request(drivescript::stop_request::StopSignal::INT);
        false
    };
    let (code, err, requests) = run_request(&with_profile, "reset", false, Some(&mut ask), stop, None);
    assert_eq!(code, 130, "{err}");
    assert_has(&err, &["stopped by Ctrl-C (SIGINT); nothing was sent"]);
    assert!(!requests.iter().any(|r| r == "RESET!"), "{requests:?}");
}

#[test]
fn a_drive_enabled_while_the_question_was_open_is_refused_after_the_yes() {
    let dir = scratch("maintain-enabled-meanwhile");
    let with_profile = dictionary_args(Some(completed_template(&dir)));
    let drive: Mutex<Option<Arc<Mutex<dyn SimulatedDrive>>>> = Mutex::new(None);
    let before = |sim: &Arc<Mutex<dyn SimulatedDrive>>| {
        *drive.lock().unwrap_or_else(PoisonError::into_inner) = Some(sim.clone());
    };
    // Someone enables the drive at its own terminal while the question waits; then yes.
    let mut ask = |_: &str| {
        if let Some(sim) = drive.lock().unwrap_or_else(PoisonError::into_inner).as_ref() {
            with_lenze(sim, |s| {
                for line in ["OW:0020:00000006", "OW:0020:00000007", "OW:0020:0000000F"] {
                    s.receive(format!("{line}\r").as_bytes(), Duration::ZERO);
                }
            });
        }
        true
    };
    let stop = Arc::new(StopRequests::new());
    let (code, err, requests) =
        run_request(&with_profile, "init", false, Some(&mut ask), stop, Some(&before));
    assert_eq!(code, 2, "{err}");
    assert_has(&err, &["the drive went to operation enabled while the question was open, and init is refused while it is enabled"]);
    assert!(!requests.iter().any(|r| r == "INIT!"), "{requests:?}");
}

#[test]
fn a_stop_while_waiting_for_the_answer_says_the_outcome_is_unknown() {
    let stop = Arc::new(StopRequests::new());
    // The drive is silent; Ctrl-C comes while drivescript waits for its answer.
    stop.schedule(
        Duration::from_millis(200),
        drivescript::stop_request::StopSignal::INT,
    );
    let prepare = |sim: &Arc<Mutex<dyn SimulatedDrive>>| {
        with_lenze(sim, |s| {
            s.faults().drop_replies(5);
        });
    };
    let (code, err, _) = run_request(&builtin(), "reset", true, None, stop, Some(&prepare));
    assert_eq!(code, 130, "{err}");
    assert_has(&err, &["whether the drive carried out reset is unknown"]);
}

/// The interlock belongs to the drive layer: any caller that opens a drive gets it, not
/// only `maintain`. An enabled drive refuses a destructive action even with `force`, and
/// nothing is sent; disabled, the clearance carries the state it was given in.
#[test]
fn the_drive_layer_refuses_a_destructive_action_while_the_drive_is_enabled() {
    let dir = scratch("maintain-drive-layer");
    let dictionary = dictionary_args(Some(completed_template(&dir)))
        .load_for(&Registry::builtin(), None)
        .expect("dictionary");
    let mut open = drivescript::run::open_drive(
        &Registry::builtin(),
        &ConnectionArgs::simulated(),
        dictionary,
        true,
        None,
        None,
    )
    .expect("the simulated 931 opens");
    let sim = open.simulator.clone().expect("simulated");
    let reset = *Lenze931Family
        .maintenance_actions()
        .iter()
        .find(|a| a.name == "reset")
        .expect("reset");
    let clearance = open
        .drive
        .clear_for_maintenance(&reset, None, true)
        .expect("a disabled drive is cleared");
    assert_eq!(clearance.state(), Some(DeviceState::SwitchOnDisabled));
    with_lenze(&sim, |s| {
        for line in ["OW:0020:00000006", "OW:0020:00000007", "OW:0020:0000000F"] {
            s.receive(format!("{line}\r").as_bytes(), Duration::ZERO);
        }
    });
    let before = with_lenze(&sim, |s| s.requests().len());
    let e = open
        .drive
        .clear_for_maintenance(&reset, None, true)
        .expect_err("an enabled drive is refused, --force or not");
    assert!(
        matches!(
            e,
            DriveError::EnabledForMaintenance {
                state: DeviceState::OperationEnabled,
                ..
            }
        ),
        "{e}"
    );
    let sent = with_lenze(&sim, |s| s.requests()[before..].to_vec());
    assert_eq!(sent, ["OR:0021"], "only the state was read");
}
