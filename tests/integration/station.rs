//! The operator station end to end: `drivescript station` serving its page to a real
//! headless Chromium (over the DevTools protocol), on the built-in simulated drive in real
//! time. Every operator step kind answered in the page (a wrong value asked again, as on
//! the terminal) ends PASS and the store holds the answers with the operator's name; the
//! Stop button brakes to standstill before the power stage goes off (control words in the
//! trace); a drive fault shows FAIL with the reason; a page closed mid-run and opened in
//! another browser rejoins the live run; a second Start is refused saying why; requests
//! without the token or with a wrong one are refused; SIGTERM to the station mid-run stops
//! the drive before it exits. Screenshots at 1280×800 and 1024×600 are kept under
//! `target/station-shots/` for a look.

#![cfg(unix)]

use crate::brake_first::{control_words, speed_replies, ENABLE_OPERATION, STANDSTILL};
use crate::live_run::LiveRun;
use crate::support::{assert_left_at_standstill, repo_root, scratch_file};
use crate::support_browser::Browser;
use std::io::{Read, Write};
use std::path::PathBuf;

const SERIAL: &str = "SP-104233";

/// Every operator step kind, a sampled run-up for the plot, and a clean stop.
const ACCEPTANCE: &str = "name: Station acceptance
drive: sd2
steps:
  - enter_text: { prompt: \"Scan the spindle's serial number\", pattern: \"SP-[0-9]{6}\", sets: serial }
  - instruct: Fit the balancing adapter and close the guard
    name: guard
  - go_to: operation_enabled
  - set: { speed_setpoint: 3000 rpm }
  - sample: { objects: [speed_actual, current_actual], every: 20 ms, for: 2 s }
  - confirm: Is the spindle running quietly?
    name: quiet
  - enter_value: { prompt: Vibration on the hand-held meter, unit: mm/s, at_most: 2.8 mm/s }
    name: vibration
  - set: { speed_setpoint: 0 rpm }
  - wait_until: { speed_actual: { below: 10 rpm }, timeout: 20 s }
";

/// A spindle at speed for a long time: for Stop, SIGTERM, rejoining and a second Start.
const LONG_RUN: &str = "name: Long run
drive: sd2
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: 6000 rpm }
  - wait_until: { speed_actual: { near: 6000 rpm, within: 2 % }, timeout: 20 s }
  - sample: { objects: [speed_actual], every: 50 ms, for: 2 s }
  - instruct: Check the spindle from the other side
    name: look
  - dwell: 1 h
";

/// `drivescript station RECIPE` on a free port of 127.0.0.1, recording in a store of its
/// own and writing its reports and trace to its scratch folder.
struct StationUnderTest {
    run: LiveRun,
    url: String,
    dir: PathBuf,
}

impl StationUnderTest {
    fn start(name: &str, recipe: &str, extra: &[&str]) -> StationUnderTest {
        let (dir, recipe) = scratch_file(&format!("station-{name}"), "recipe.yaml", recipe);
        let store = dir.join("results.sqlite");
        let mut args: Vec<String> = [
            "station",
            &recipe.to_string_lossy(),
            "--listen",
            "127.0.0.1:0",
            "--results",
            &store.to_string_lossy(),
            "--output-dir",
            &dir.to_string_lossy(),
            "--trace",
            "run.trace",
            "--unit",
            "station=bench-7",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        args.extend(extra.iter().map(|s| s.to_string()));
        let mut run = LiveRun::start(&args);
        let url = run
            .wait_for("open the operator station at http")
            .split_whitespace()
            .find(|w| w.starts_with("http://"))
            .expect("the address")
            .to_string();
        StationUnderTest { run, url, dir }
    }

    /// SIGTERM, then its exit code and all it printed.
    fn end(self) -> (Option<i32>, String) {
        self.run.signal("TERM");
        self.run.finish()
    }

    fn trace(&self) -> String {
        std::fs::read_to_string(self.dir.join("run.trace")).expect("the run's trace")
    }
}

fn browser(name: &str, width: u32, height: u32) -> Option<Browser> {
    Browser::launch(name, width, height)
}

/// Where the screenshots are kept for a look.
fn shot(b: &mut Browser, name: &str) {
    let dir = repo_root().join("target/station-shots");
    std::fs::create_dir_all(&dir).expect("the screenshots' folder");
    b.screenshot(&dir.join(format!("{name}.png")));
}

/// Types the operator's name, then — as a barcode scanner does, into the field that has
/// the focus after the page loads — the serial and Enter.
fn start_in_page(b: &mut Browser, url: &str, operator: &str, serial: &str) {
    b.open(url);
    b.wait_for("!document.getElementById('start').hidden", "the start form");
    b.click("#operator");
    b.eval("document.getElementById('operator').value = ''");
    b.type_text(operator);
    b.open(url);
    b.wait_for("!document.getElementById('start').hidden", "the start form");
    assert_eq!(
        b.eval("document.activeElement.id"),
        serde_json::json!("serial"),
        "the serial field has the focus"
    );
    assert_eq!(
        b.eval("document.getElementById('operator').value"),
        serde_json::json!(operator),
        "the operator's name is remembered"
    );
    b.type_text(serial);
    b.enter();
    b.wait_for("!document.getElementById('run').hidden", "the run to start");
}

/// A browser (1280 × 800) at a station `name` of `recipe` (with `extra` arguments), its
/// run started in the page by A. Operator for `serial`; `None` where no browser can be
/// launched.
fn started_in_a_browser(
    name: &str,
    recipe: &str,
    extra: &[&str],
    serial: &str,
) -> Option<(Browser, StationUnderTest)> {
    let mut b = browser(name, 1280, 800)?;
    let station = StationUnderTest::start(name, recipe, extra);
    start_in_page(&mut b, &station.url, "A. Operator", serial);
    Some((b, station))
}

/// Waits for the open dialog that asks `text` and is not being judged.
fn dialog(b: &mut Browser, text: &str) {
    b.wait_for_text("#dialog-text", text);
    b.wait_for(
        "!document.querySelector('#dialog-input').disabled && ![...document.querySelectorAll('#dialog-buttons button')].some(b => b.disabled)",
        "the dialog to take an answer",
    );
}

fn answer_typed(b: &mut Browser, text: &str) {
    b.click("#dialog-input");
    b.type_text(text);
    b.enter();
}

#[test]
fn every_operator_step_answered_in_the_page_passes_and_the_store_holds_the_answers() {
    let Some(mut b) = browser("acceptance", 1280, 800) else {
        return;
    };
    let station = StationUnderTest::start("acceptance", ACCEPTANCE, &[]);
    b.open(&station.url);
    b.wait_for("!document.getElementById('start').hidden", "the start form");
    shot(&mut b, "start-1280x800");
    b.resize(1024, 600);
    shot(&mut b, "start-1024x600");
    b.resize(1280, 800);
    start_in_page(&mut b, &station.url, "J. Smith", SERIAL);

    dialog(&mut b, "Scan the spindle's serial number");
    assert!(
        b.text("#dialog-hint").contains("SP-[0-9]{6}"),
        "the pattern is shown"
    );
    answer_typed(&mut b, "SP-12");
    // Judged as on the terminal: no answer, asked again saying why.
    b.wait_for_text("#dialog-error", "answer again");
    answer_typed(&mut b, SERIAL);

    dialog(&mut b, "Fit the balancing adapter");
    shot(&mut b, "dialog-instruct-1280x800");
    b.resize(1024, 600);
    shot(&mut b, "dialog-instruct-1024x600");
    b.resize(1280, 800);
    b.click("#dialog-buttons .ok");

    dialog(&mut b, "Is the spindle running quietly?");
    // The sampled run-up is plotted while the question waits.
    b.wait_for(
        "document.querySelectorAll('#plots canvas').length >= 2",
        "two live plots",
    );
    b.click("#dialog-buttons .yes");

    dialog(&mut b, "Vibration on the hand-held meter");
    assert_eq!(b.text("#dialog-unit"), "mm/s");
    assert_eq!(b.text("#dialog-hint"), "in mm/s, at most 2.8 mm/s");
    shot(&mut b, "dialog-value-1280x800");
    b.resize(1024, 600);
    shot(&mut b, "dialog-value-1024x600");
    b.resize(1280, 800);
    answer_typed(&mut b, "1.2");
    b.wait_for("document.getElementById('dialog').hidden", "the dialog to close");
    shot(&mut b, "live-plot-1280x800");
    b.resize(1024, 600);
    shot(&mut b, "live-plot-1024x600");
    b.resize(1280, 800);

    b.wait_for_text("#word", "PASS");
    let end = b.text("#end");
    assert_left_at_standstill(&end, "ready to switch on");
    assert!(b.text("#links").contains("Run report"), "a link to the report");
    b.wait_for_text("#runs", SERIAL);
    shot(&mut b, "result-1280x800");
    b.resize(1024, 600);
    shot(&mut b, "result-1024x600");
    // The report and the certificate are served.
    let report = b.eval("fetch('report').then(r => r.status + ' ' + r.headers.get('content-type'))");
    assert_eq!(report, serde_json::json!("200 text/html; charset=utf-8"));
    let certificate = b.eval("fetch('certificate').then(r => r.text())");
    assert!(
        certificate.as_str().unwrap_or_default().contains(SERIAL),
        "{certificate}"
    );

    // The store holds every answer with who gave it.
    let store = station.dir.join("results.sqlite");
    let mut store = drivescript::results::Locator::parse(&store.to_string_lossy())
        .open(false)
        .expect("the station's store");
    let runs = store
        .unit_runs_in(&drivescript::results::RunFilter {
            unit: Some(SERIAL.into()),
            simulated: true,
            ..Default::default()
        })
        .expect("the unit's runs");
    assert_eq!(runs.len(), 1, "one run of the unit");
    assert_eq!(runs[0].verdict(), "passed");
    assert_eq!(runs[0].run.unit.operator.as_deref(), Some("J. Smith"));
    let answers: Vec<(String, String)> = runs[0]
        .checks
        .iter()
        .filter(|c| c.message.contains("by J. Smith"))
        .map(|c| (c.name.clone(), c.measured_text.clone().unwrap_or_default()))
        .collect();
    for (question, answer) in [
        ("Scan the spindle's serial number", SERIAL),
        ("Fit the balancing adapter and close the guard", "acknowledged"),
        ("Is the spindle running quietly?", "yes"),
        ("Vibration on the hand-held meter", "1.2 mm/s"),
    ] {
        assert!(
            answers.iter().any(|(q, a)| q == question && a == answer),
            "{question}: {answer} by J. Smith is not in the store: {answers:?}"
        );
    }
    drop(b);
    let (_, printed) = station.end();
    // The station's log says what the terminal would, without the terminal's input marker
    // (nobody types at the station's output).
    assert!(
        printed.contains("?     Scan the spindle's serial number"),
        "{printed}"
    );
    assert!(!printed.contains("       > "), "{printed}");
}

/// The run's clock seconds of the first enable, and of the first other control word
/// after it, with the last speed read in between.
fn braked_before_disable(trace: &str) -> (f64, i64) {
    let words = control_words(trace);
    let enabled = words
        .iter()
        .find(|(_, v)| *v == ENABLE_OPERATION)
        .map(|(i, _)| *i)
        .unwrap_or_else(|| panic!("never enabled:\n{trace}"));
    let (disable, word) = *words
        .iter()
        .find(|(i, v)| *i > enabled && *v != ENABLE_OPERATION)
        .unwrap_or_else(|| panic!("no disable after the enable:\n{trace}"));
    let speeds = speed_replies(trace);
    assert!(
        speeds
            .iter()
            .any(|(i, v)| *i > enabled && *i < disable && v.abs() > 5000.0),
        "the spindle was at speed before the stop"
    );
    let last = speeds
        .iter()
        .rev()
        .find(|(i, _)| *i > enabled && *i < disable)
        .map(|(_, v)| *v)
        .expect("a speed read before the disable");
    (last, word)
}

#[test]
fn stop_in_the_page_brakes_to_standstill_and_a_second_start_is_refused_and_a_reopened_page_rejoins() {
    let Some((mut first, station)) = started_in_a_browser("stop", LONG_RUN, &[], "SP-000001") else {
        return;
    };
    dialog(&mut first, "Check the spindle from the other side");

    // A second browser sees the run under way, and its Start is refused saying why.
    let Some(mut second) = browser("stop-second", 1024, 600) else {
        return;
    };
    second.open(&station.url);
    second.wait_for_text("#run-title", "SP-000001");
    second.eval("startRun(0, 'SP-000002', 'B. Other')");
    second.wait_for_text("#notice", "a run is under way on this drive");

    // The first browser closes; the run goes on and a new page rejoins it, question and all.
    drop(first);
    std::thread::sleep(std::time::Duration::from_millis(500));
    let Some(mut again) = browser("stop-again", 1280, 800) else {
        return;
    };
    again.open(&station.url);
    dialog(&mut again, "Check the spindle from the other side");
    assert!(
        again.text("#steps").contains("wait until speed_actual"),
        "{}",
        again.text("#steps")
    );
    again.click("#dialog-buttons .ok");
    again.wait_for_text("#steps", "dwell");

    again.click("#stop-button");
    again.wait_for_text("#stop-note", "Press again");
    again.wait_for_text("#word", "FAIL");
    let line = again.text("#verdict-line");
    assert!(
        line.contains("INTERRUPTED") && line.contains("Stop button"),
        "{line}"
    );
    let (last, word) = braked_before_disable(&station.trace());
    assert!(
        last.abs() < STANDSTILL,
        "the first disable (control word {word}) went out at {last} rpm"
    );
    second.wait_for_text("#word", "FAIL");
    drop((again, second));
    station.end();
}

#[test]
fn a_drive_fault_shows_fail_with_the_reason() {
    let trip = ["--sim", "trip-at=1s:0x1234"];
    let Some((mut b, station)) = started_in_a_browser("fault", LONG_RUN, &trip, "SP-000003") else {
        return;
    };
    b.wait_for_text("#word", "FAIL");
    let line = b.text("#verdict-line");
    assert!(line.contains("ERROR") && line.contains("fault"), "{line}");
    assert!(
        b.text("#failed").contains("FAIL") || !b.text("#failed").is_empty(),
        "what failed is listed"
    );
    shot(&mut b, "fault-1280x800");
    drop(b);
    station.end();
}

#[test]
fn sigterm_to_the_station_mid_run_stops_the_drive_before_it_exits() {
    let Some((mut b, station)) = started_in_a_browser("sigterm", LONG_RUN, &[], "SP-000004") else {
        return;
    };
    dialog(&mut b, "Check the spindle from the other side");
    station.run.signal("TERM");
    // Every page hears that the station shuts down and how the run ended.
    b.wait_for_text("#word", "FAIL");
    assert!(
        b.text("#verdict-line").contains("SIGTERM"),
        "{}",
        b.text("#verdict-line")
    );
    let trace_path = station.dir.join("run.trace");
    let (code, out) = station.run.finish();
    assert_eq!(code, Some(143), "{out}");
    let trace = std::fs::read_to_string(trace_path).expect("the trace");
    let (last, word) = braked_before_disable(&trace);
    assert!(
        last.abs() < STANDSTILL,
        "disable (control word {word}) at {last} rpm"
    );
}

/// One raw HTTP/1.1 request; the status code and the whole answer.
fn http(url: &str, request: &str) -> (u16, String) {
    let address = url
        .trim_start_matches("http://")
        .split('/')
        .next()
        .expect("host:port");
    let mut s = std::net::TcpStream::connect(address).expect("the station listens");
    s.write_all(request.replace("HOST", address).as_bytes())
        .expect("the request is sent");
    let mut answer = String::new();
    let _ = s.read_to_string(&mut answer);
    let status = answer
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    (status, answer)
}

#[test]
fn without_the_token_or_with_a_wrong_one_nothing_is_served_or_started() {
    let (_, token_file) = scratch_file(
        "token-file",
        "token",
        "a-long-enough-secret-for-this-bench-0123456789\n",
    );
    let token_arg = token_file.to_string_lossy().to_string();
    let station = StationUnderTest::start("token", LONG_RUN, &["--token-file", &token_arg]);
    let base = station.url.clone();
    // A token from a file stays out of the console.
    assert!(!station.url.contains("token"), "{}", station.url);
    let get = |path: &str| {
        http(
            &base,
            &format!("GET {path} HTTP/1.1\r\nHost: HOST\r\nConnection: close\r\n\r\n"),
        )
    };
    assert_eq!(get("/").0, 401, "no token");
    assert_eq!(get("/events").0, 401, "no token for the events");
    assert_eq!(get("/?token=wrong").0, 403, "a wrong token");
    let body = r#"{"recipe":0,"serial":"SP-999999","operator":"Eve X"}"#;
    let post = |header: &str| {
        http(
            &base,
            &format!(
                "POST /api/start HTTP/1.1\r\nHost: HOST\r\nConnection: close\r\n{header}Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
                body.len()
            ),
        )
    };
    assert_eq!(post("").0, 401, "a start without the token");
    assert_eq!(
        post("x-drivescript-token: wrong\r\n").0,
        403,
        "a start with a wrong token"
    );
    let (code, answer) = post("x-drivescript-token: a-long-enough-secret-for-this-bench-0123456789\r\n");
    assert_eq!(code, 200, "the right token starts a run: {answer}");
    let stop = "POST /api/stop HTTP/1.1\r\nHost: HOST\r\nConnection: close\r\nContent-Length: 0\r\n\r\n";
    assert_eq!(http(&base, stop).0, 401, "a Stop without the token");
    // The address printed opens the page (the token becomes a cookie), whose own
    // requests carry the token: it shows the run and stops it.
    if let Some(mut b) = browser("token", 1280, 800) {
        b.open(&format!(
            "{base}?token=a-long-enough-secret-for-this-bench-0123456789"
        ));
        dialog(&mut b, "Check the spindle from the other side");
        assert!(
            !b.eval("location.href")
                .as_str()
                .unwrap_or_default()
                .contains("token"),
            "the token left the address bar"
        );
        // Stop is at hand in the dialog too.
        b.click("#dialog-stop");
        b.wait_for_text("#word", "FAIL");
    }
    let store = station.dir.join("results.sqlite");
    station.end();
    // Only the one start with the right token ran.
    let listed = crate::support::drivescript(
        &[
            "results",
            "list",
            "--simulated",
            "--results",
            &store.to_string_lossy(),
        ],
        "",
    );
    let listed = crate::support::stdout(&listed);
    assert_eq!(listed.matches("SP-999999").count(), 1, "{listed}");
}
