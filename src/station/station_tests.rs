//! The station's runs in process, on the built-in simulated drive through the one run
//! pipeline: one run at a time, answers only to the open question, and a web server that
//! died stopping the run through its safe stop.

use super::*;
use crate::family::Registry;
use crate::run::{ConnectionArgs, DictionaryArgs, RecordArgs, RunOptions};
use std::time::{Duration, Instant};

const RECIPE: &str = "name: Dwell at speed
drive: sd2
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: 3000 rpm }
  - instruct: Look at the spindle
    name: look
  - dwell: 1 h
";

fn station(name: &str) -> Station {
    let dir = crate::scratch_dir::scratch_dir(&format!("station-{name}"));
    let recipe = dir.join("recipe.yaml");
    std::fs::write(&recipe, RECIPE).expect("recipe");
    let options = RunOptions {
        set: Vec::new(),
        fast: false,
        realtime: false,
        output_dir: dir.clone(),
        dictionary: DictionaryArgs::builtin_default(),
        connection: ConnectionArgs::simulated(),
        outputs: Default::default(),
        safe_stop: Default::default(),
        operator: Default::default(),
        record: RecordArgs {
            no_results: true,
            ..Default::default()
        },
    };
    Station::new(StationSetup::new(Registry::builtin(), &[recipe], options).expect("the recipe loads"))
}

/// Waits until the view satisfies `ready` (at most 20 s).
fn until(station: &Station, what: &str, ready: impl Fn(&StationView) -> bool) {
    let started = Instant::now();
    while !station.log().read(&ready) {
        assert!(
            started.elapsed() < Duration::from_secs(20),
            "waited 20 s for {what}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn dialog_id(station: &Station) -> Option<u64> {
    station
        .log()
        .read(|v| v.run.as_ref().and_then(|r| r.dialog.as_ref()).map(|d| d.id))
}

#[test]
fn one_run_at_a_time_answers_only_to_the_open_question_and_a_dead_server_stops_the_run() {
    let station = station("dead-server");
    assert!(station.start(0, "", "A").is_err(), "a serial is needed");
    assert!(
        station.start(0, "SP-1", "").is_err(),
        "an operator's name is needed"
    );
    assert!(station.start(7, "SP-1", "A").is_err(), "only the recipes given");
    station.start(0, "SP-1", "A").expect("the run starts");
    let refused = station.start(0, "SP-2", "B").expect_err("one run per drive");
    assert!(
        refused.0.contains("a run is under way") && refused.0.contains("SP-1"),
        "{refused}"
    );
    until(&station, "the question", |v| {
        v.run.as_ref().is_some_and(|r| r.dialog.is_some())
    });
    let id = dialog_id(&station).expect("a question");
    assert!(
        station.answer(id + 1, "").is_err(),
        "an answer to another question"
    );
    station.answer(id, "").expect("the answer");
    assert!(
        station.answer(id, "").is_err(),
        "a second answer to the same question"
    );
    until(&station, "the dwell", |v| {
        v.run.as_ref().is_some_and(|r| {
            r.steps
                .iter()
                .any(|s| s.label.starts_with("dwell") && s.state == "running")
        })
    });
    // The web server's thread is gone: nobody could press Stop any more.
    let signals = crate::stop_request::StopRequests::new();
    assert_eq!(supervise(&station, &signals, &|| false), Ended::ServerFailed);
    let result = station
        .log()
        .read(|v| v.run.as_ref().and_then(|r| r.result.clone()))
        .expect("the run ended");
    assert_eq!(result.verdict, "INTERRUPTED");
    assert!(
        result.reason.as_deref().is_some_and(|r| r.contains("web server")),
        "{:?}",
        result.reason
    );
    assert_eq!(
        result.end,
        vec!["drive left in ready to switch on at 0 rpm".to_string()]
    );
    assert!(
        station.start(0, "SP-3", "A").is_err(),
        "no new run once the station ends"
    );
}
