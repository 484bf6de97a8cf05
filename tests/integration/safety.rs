//! Every ending stops the drive: each stop signal sent to the real binary talking to a
//! simulated drive through a pseudo-terminal, the stop latency (virtual and real time), a
//! ramp that must not write after a stop, a port that goes away and comes back, and a run
//! killed beyond any safe stop, which must leave a report that says so.

use crate::live_run::LiveRun;
use crate::support::{assert_has, assert_lacks, Simulator};
use crate::support::{scratch, scratch_file, write_file, InProcessRun};
use drivescript::clock::SharedClock;
#[cfg(unix)]
use drivescript::drive::device_control::DeviceState;
use drivescript::family::sd2::codec::{Body, Telegram};
use drivescript::family::sd2::Sd2Simulator;
use drivescript::run::RunResult;
use drivescript::sim::SimulatedDrive;
use drivescript::stop_request::{StopRequests, StopSignal};
use std::path::Path;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};
use std::time::{Duration, Instant};

/// Object indices of the SD2 dictionary the checks below look for.
pub(crate) const CONTROL_WORD: u16 = 68;
pub(crate) const SPEED_SETPOINT: u16 = 395;

/// The value of a write of `index` (little-endian), if `t` is one.
pub(crate) fn written(t: &Telegram, index: u16) -> Option<i64> {
    match &t.body {
        Body::WriteRequest { index: i, data, .. } if *i == index => {
            let b = data.as_slice();
            let mut v = [0u8; 8];
            v[..b.len().min(8)].copy_from_slice(&b[..b.len().min(8)]);
            Some(i64::from_le_bytes(v))
        }
        _ => None,
    }
}

/// Runs a recipe in-process against the built-in simulated drive.
fn run_in_process(
    recipe: &Path,
    fast: bool,
    stop: Arc<StopRequests>,
    clock_slot: Arc<OnceLock<SharedClock>>,
) -> RunResult {
    let prepare = move |_: &Arc<Mutex<dyn SimulatedDrive>>, clock: &SharedClock| {
        let _ = clock_slot.set(clock.clone());
    };
    let mut run = InProcessRun::new(recipe);
    run.fast = fast;
    run.prepare = Some(&prepare);
    run.stop = stop;
    let (result, output) = run.run();
    if result.report.is_none() {
        panic!("the run did not start: {output}");
    }
    result
}

pub(crate) fn received(result: &RunResult) -> Vec<(Duration, Telegram)> {
    let sim = result.simulator.as_ref().expect("simulated drive");
    let mut sim = sim.lock().unwrap_or_else(PoisonError::into_inner);
    let sd2 = sim
        .as_any_mut()
        .downcast_mut::<Sd2Simulator>()
        .expect("an SD2 simulator");
    sd2.received().to_vec()
}

const SAMPLE_EVERY_30_S: &str = "name: Sampling every 30 s
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: 2000 rpm }
  - wait_until: { speed_actual: { near: 2000 rpm, within: 1 % }, timeout: 10 s }
  - sample: { objects: [speed_actual], every: 30 s, for: 10 min }
";

#[test]
fn in_virtual_time_the_stop_starts_at_the_signal_not_at_the_next_sample() {
    let (_, recipe) = scratch_file("virtual-latency", "recipe.yaml", SAMPLE_EVERY_30_S);
    let stop = Arc::new(StopRequests::new());
    let signal_at = Duration::from_millis(45_250);
    stop.schedule(signal_at, StopSignal::TERM);
    let result = run_in_process(&recipe, true, stop, Arc::new(OnceLock::new()));
    assert_eq!(result.exit_code, 143);
    let first_stop = received(&result)
        .into_iter()
        .find(|(at, t)| *at >= signal_at && written(t, SPEED_SETPOINT).is_some())
        .expect("a stop telegram after the signal");
    assert_eq!(written(&first_stop.1, SPEED_SETPOINT), Some(0));
    let latency = first_stop.0 - signal_at;
    assert!(latency < Duration::from_millis(50), "stop latency {latency:?}");
}

#[test]
fn in_real_time_a_signal_during_a_30_s_sample_interval_stops_within_100_ms() {
    let (_, recipe) = scratch_file("real-latency", "recipe.yaml", SAMPLE_EVERY_30_S);
    let stop = Arc::new(StopRequests::new());
    let clock_slot: Arc<OnceLock<SharedClock>> = Arc::new(OnceLock::new());
    let (sender_stop, sender_clock) = (stop.clone(), clock_slot.clone());
    // The spindle reaches 2000 rpm after 1 s; the sample step then waits 30 s.
    let sender = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(2500));
        let clock = sender_clock.get().expect("the run has started");
        let at = clock.now();
        sender_stop.request(StopSignal::INT);
        at
    });
    let wall = Instant::now();
    let result = run_in_process(&recipe, false, stop, clock_slot);
    let signal_at = sender.join().expect("sender");
    assert_eq!(result.exit_code, 130);
    assert!(
        wall.elapsed() < Duration::from_secs(20),
        "the run went on after the signal"
    );
    let first_stop = received(&result)
        .into_iter()
        .find(|(at, t)| *at >= signal_at && written(t, SPEED_SETPOINT).is_some())
        .expect("a stop telegram after the signal");
    let latency = first_stop.0 - signal_at;
    assert!(
        latency < Duration::from_millis(100),
        "stop latency {latency:?} (signal at {signal_at:?})"
    );
}

#[test]
fn a_ramp_writes_no_further_setpoint_after_a_stop_request() {
    let (_, recipe) = scratch_file(
        "ramp",
        "recipe.yaml",
        "name: Ramp
steps:
  - go_to: operation_enabled
  - ramp: { object: speed_setpoint, from: 1000 rpm, to: 12000 rpm, step: 1000 rpm, every: 2 s }
",
    );
    let stop = Arc::new(StopRequests::new());
    // Exactly when the fourth point is due: it must not be written.
    let signal_at = Duration::from_secs(6) + Duration::from_millis(20);
    stop.schedule(signal_at, StopSignal::HUP);
    let result = run_in_process(&recipe, true, stop, Arc::new(OnceLock::new()));
    assert_eq!(result.exit_code, 129);
    let setpoints: Vec<(Duration, i64)> = received(&result)
        .iter()
        .filter_map(|(at, t)| written(t, SPEED_SETPOINT).map(|v| (*at, v)))
        .collect();
    let after: Vec<i64> = setpoints
        .iter()
        .filter(|(at, _)| *at >= signal_at)
        .map(|(_, v)| *v)
        .collect();
    assert_eq!(after, vec![0], "setpoints written after the stop: {setpoints:?}");
    let before: Vec<i64> = setpoints
        .iter()
        .filter(|(at, _)| *at < signal_at)
        .map(|(_, v)| *v)
        .collect();
    assert_eq!(before, vec![1_000_000, 2_000_000, 3_000_000, 4_000_000]);
}

/// The control words written in a trace file's TX lines, with their clock seconds.
pub(crate) fn traced_writes(trace: &str, index: u16) -> Vec<(f64, i64)> {
    trace
        .lines()
        .filter_map(|line| {
            let mut tokens = line.split_whitespace();
            let secs: f64 = tokens.next()?.parse().ok()?;
            if tokens.next()? != "TX" {
                return None;
            }
            let bytes: Vec<u8> = tokens
                .take_while(|t| *t != "#")
                .map(|t| u8::from_str_radix(t, 16))
                .collect::<Result<_, _>>()
                .ok()?;
            let telegram = Telegram::decode(&bytes).ok()?;
            written(&telegram, index).map(|v| (secs, v))
        })
        .collect()
}

/// Sends `signal` to a real run on a real pseudo-terminal while a sample step waits 30 s
/// for its next sample (and `second` while the safe stop brakes the spindle); checks the
/// exit code, the stop telegrams, the drive's state and both reports. Under Wine the
/// pseudo-terminal is a COM port and a SIGINT is the console's Ctrl-C.
fn signal_through_a_pty(signal: StopSignal, second: Option<StopSignal>) {
    let sim = Simulator::pty(&[]);
    let (dir, recipe) = scratch_file(
        &format!("pty-{}-{}", signal.name, second.map_or("", |s| s.name)),
        "recipe.yaml",
        SAMPLE_EVERY_30_S,
    );
    let (junit, html, trace) = (
        dir.join("junit.xml"),
        dir.join("report.html"),
        dir.join("run.trace"),
    );
    // An earlier run's pass, which must not survive this run's end.
    std::fs::write(&junit, "<testsuites tests=\"1\" failures=\"0\"/>").expect("old junit");
    let mut run = LiveRun::run_on(
        &recipe,
        &sim.endpoint,
        &[("--junit", &junit), ("--report", &html), ("--trace", &trace)],
    );
    run.wait_for("wait until speed_actual");
    let placeholder = std::fs::read_to_string(&junit).expect("junit exists during the run");
    assert_has(&placeholder, &["NOT FINISHED"]);
    // The sample step has taken its first sample and now waits 30 s.
    std::thread::sleep(Duration::from_millis(300));
    let before = std::fs::read_to_string(&trace).expect("trace").lines().count();
    let sent = Instant::now();
    let kill = |s: StopSignal| run.signal(&s.name[3..]);
    kill(signal);
    // The first telegram after the signal, seen in the trace as it is flushed.
    let latency = loop {
        let text = std::fs::read_to_string(&trace).expect("trace");
        let fresh: String = text.lines().skip(before).collect::<Vec<_>>().join("\n");
        if !traced_writes(&fresh, SPEED_SETPOINT).is_empty() {
            break sent.elapsed();
        }
        assert!(
            sent.elapsed() < Duration::from_secs(10),
            "no stop telegram: {fresh}"
        );
        std::thread::sleep(Duration::from_millis(1));
    };
    if let Some(s) = second {
        // The default safe stop now brakes the spindle from 2000 rpm for about 1 s.
        std::thread::sleep(Duration::from_millis(300));
        kill(s);
    }
    let (code, all) = run.finish();
    // After a second signal the power stage is off at once and the spindle still coasts:
    // a spindle left coasting is exit code 3, whatever ended the run.
    let expected = match second {
        Some(_) => 3,
        None => signal.exit_code(),
    };
    assert_eq!(code, Some(expected), "{all}");
    // Under Wine the Ctrl-C is pressed by the Linux side, which first looks the process up
    // among all of Linux's: that lookup is in this time too.
    let limit = Duration::from_millis(if cfg!(windows) { 1000 } else { 100 });
    assert!(
        latency < limit,
        "{}: the stop telegram came {latency:?} after the signal",
        signal.name
    );
    let verdict = match second {
        Some(_) => "ERROR: interrupted by",
        None => "INTERRUPTED: interrupted by",
    };
    assert_has(&all, &[&format!("{verdict} {}", signal.describe())]);
    let (words, state_after) = match second {
        None => {
            assert_has(&all, &["drive left in ready to switch on at 0 rpm"]);
            (vec![7, 6], "ready to switch on")
        }
        Some(_) => {
            assert_has(
                &all,
                &[
                    "power stage switched off at once (disable voltage)",
                    "drive left in switch on disabled at",
                    "STILL COASTING",
                ],
            );
            (vec![0], "switch on disabled")
        }
    };
    let trace_text = std::fs::read_to_string(&trace).expect("trace");
    let after: Vec<i64> = traced_writes(
        &trace_text.lines().skip(before).collect::<Vec<_>>().join("\n"),
        CONTROL_WORD,
    )
    .into_iter()
    .map(|(_, v)| v)
    .collect();
    assert_eq!(after, words, "control words after the signal");
    // Every report says the verdict the console said.
    let (junit_verdict, html_verdict) = match second {
        Some(_) => ("ERROR: interrupted by", "ERROR"),
        None => ("INTERRUPTED: the run was interrupted by", "INTERRUPTED"),
    };
    let junit_text = std::fs::read_to_string(&junit).expect("junit");
    assert_has(&junit_text, &[junit_verdict]);
    assert_lacks(&junit_text, &["NOT FINISHED"]);
    let html_text = std::fs::read_to_string(&html).expect("html");
    assert_has(&html_text, &[html_verdict]);
    assert!(html_text.contains(signal.describe()), "{html_text}");
    // The simulated drive keeps its state: ask it.
    let state = crate::support::drivescript(&["state", "--port", &sim.endpoint], "");
    let shown = crate::support::stdout(&state);
    assert!(shown.contains(state_after), "{shown}");
}

#[test]
fn sigint_through_a_pty_stops_the_drive_and_exits_130() {
    signal_through_a_pty(StopSignal::INT, None);
}

#[test]
#[cfg_attr(windows, ignore = "Windows has no SIGTERM (its Ctrl-C is tested)")]
fn sigterm_through_a_pty_stops_the_drive_and_exits_143() {
    signal_through_a_pty(StopSignal::TERM, None);
}

#[test]
#[cfg_attr(windows, ignore = "Windows has no SIGHUP (its Ctrl-C is tested)")]
fn sighup_through_a_pty_stops_the_drive_and_exits_129() {
    signal_through_a_pty(StopSignal::HUP, None);
}

#[test]
#[cfg_attr(windows, ignore = "Windows has no SIGQUIT (its Ctrl-C is tested)")]
fn sigquit_through_a_pty_stops_the_drive_and_exits_131() {
    signal_through_a_pty(StopSignal::QUIT, None);
}

/// Windows has no SIGTERM: there the first signal is a Ctrl-C as well.
#[test]
fn a_second_signal_through_a_pty_switches_the_power_stage_off_at_once() {
    let first = if cfg!(windows) {
        StopSignal::INT
    } else {
        StopSignal::TERM
    };
    signal_through_a_pty(first, Some(StopSignal::INT));
}

/// The test reads the report while the run replaces it, as a viewer may: on Windows the
/// run waits for the reader to let go (it used to end with "access denied").
#[test]
fn a_run_killed_beyond_any_safe_stop_leaves_a_report_that_says_not_finished() {
    let (dir, recipe) = scratch_file("sigkill", "recipe.yaml", SAMPLE_EVERY_30_S);
    let (junit, html) = (dir.join("junit.xml"), dir.join("report.html"));
    std::fs::write(&junit, "<testsuites tests=\"1\" failures=\"0\"/>").expect("old junit");
    std::fs::write(&html, "<p>PASSED</p>").expect("old html");
    let mut child = crate::support::command()
        .arg("run")
        .arg(&recipe)
        .arg("--junit")
        .arg(&junit)
        .arg("--report")
        .arg(&html)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("run starts");
    let started = Instant::now();
    while !std::fs::read_to_string(&html)
        .unwrap_or_default()
        .contains("NOT FINISHED")
    {
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "no placeholder report"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    child.kill().expect("SIGKILL");
    let _ = child.wait();
    let junit_text = std::fs::read_to_string(&junit).expect("junit");
    assert_has(&junit_text, &["failures=\"1\"", "NOT FINISHED"]);
    assert!(std::fs::read_to_string(&html)
        .expect("html")
        .contains("NOT FINISHED"));
}

/// The pty peer goes away (its pseudo-terminal is closed) while the spindle turns and
/// comes back on a new pseudo-terminal under the same path, as a USB adapter does behind
/// its `/dev/serial/by-id` link; the safe stop reopens the port and reaches the drive.
#[cfg(unix)]
#[test]
fn a_lost_port_is_reopened_and_the_stop_reaches_the_drive() {
    use drivescript::bus::Peer;
    use drivescript::clock::RealClock;
    use drivescript::family::sd2::SimConfig;
    use drivescript::sim_server::{PtyEndpoint, SimServer};
    use std::sync::atomic::Ordering;

    let dir = scratch("lost-port");
    let link = dir.join("ttyDRIVE");
    let sim = Arc::new(Mutex::new(Sd2Simulator::new(SimConfig::default())));
    let peer: Arc<Mutex<dyn Peer>> = sim.clone();
    let clock = RealClock::shared();
    let serve = |pty: PtyEndpoint| {
        let server = SimServer::new(peer.clone(), clock.clone());
        let flag = server.stop_flag();
        let handle = std::thread::spawn(move || {
            // Whole, so that its own slave end stays open while it is served (without it
            // the master sees a hang-up whenever the run has the port closed).
            let pty = pty;
            let mut master = pty.master;
            let _ = server.serve(&mut master);
        });
        (flag, handle)
    };
    let first = PtyEndpoint::open().expect("pty");
    std::os::unix::fs::symlink(&first.path, &link).expect("symlink");
    let (first_flag, first_server) = serve(first);

    let recipe = write_file(
        &dir,
        "recipe.yaml",
        "name: Run-in
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: 3000 rpm }
  - dwell: 1 h
",
    );
    let port = link.to_string_lossy().to_string();
    let runner = std::thread::spawn(move || {
        let mut run = InProcessRun::new(recipe);
        run.fast = false;
        run.connection.port = Some(port);
        let (result, output) = run.run();
        (result.exit_code, output)
    });
    let started = Instant::now();
    let state = || sim.lock().unwrap_or_else(PoisonError::into_inner).state();
    while state() != DeviceState::OperationEnabled {
        if runner.is_finished() || started.elapsed() > Duration::from_secs(10) {
            let (code, output) = runner.join().expect("runner");
            panic!("the run never enabled the drive (exit code {code}):\n{output}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(500));
    // Away: the pseudo-terminal closes and its link goes, as udev removes a by-id link
    // with its adapter (the pts number may be given to another test's pty at once); the
    // drive keeps turning.
    std::fs::remove_file(&link).expect("link removed");
    first_flag.store(true, Ordering::SeqCst);
    first_server.join().expect("first server");
    let words_before = sim
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .control_words_written();
    std::thread::sleep(Duration::from_millis(800));
    assert_eq!(state(), DeviceState::OperationEnabled);
    // Back, under the same path.
    let second = PtyEndpoint::open().expect("second pty");
    let tmp = dir.join("ttyDRIVE.new");
    std::os::unix::fs::symlink(&second.path, &tmp).expect("symlink");
    std::fs::rename(&tmp, &link).expect("link back");
    let (second_flag, second_server) = serve(second);

    let (code, output) = runner.join().expect("runner");
    second_flag.store(true, Ordering::SeqCst);
    second_server.join().expect("second server");
    assert_eq!(code, 3, "{output}");
    assert_has(
        &output,
        &[
            "reopening",
            "restored at attempt",
            "drive left in ready to switch on",
        ],
    );
    assert_eq!(state(), DeviceState::ReadyToSwitchOn, "{output}");
    let words = sim
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .control_words_written();
    assert_eq!(&words[..words_before.len()], &words_before[..]);
    assert_eq!(&words[words_before.len()..], &[7, 6], "{output}");
}
