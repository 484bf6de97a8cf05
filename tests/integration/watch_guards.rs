//! `watch:` limits on the line: a watch shares the sample step's exchanges instead of
//! adding its own telegrams, and the run-in of issue 41 (`--sim heating=40K/A`, a watch
//! `motor_temperature below 80 °C`) ends within one watch interval of crossing 80 °C, in
//! virtual time. Both counted on the run's `--trace` of the simulated line. And `check`
//! refuses watches that would take more of a named serial line than they may.

use crate::support::{
    assert_has, assert_left_at_standstill, cli, repo_root, run_recording, scratch, scratch_file, write_file,
    InProcessRun,
};
use std::path::Path;

/// One telegram of a trace: its time, `TX` or `RX`, and what `decode` says of it.
struct Traced {
    at: f64,
    sent: bool,
    meaning: String,
}

fn traced(path: &Path) -> Vec<Traced> {
    let text = std::fs::read_to_string(path).expect("trace written");
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let mut words = l.split_whitespace();
            let at = words.next()?.parse().ok()?;
            let sent = words.next()? == "TX";
            let meaning = l.split_once("# ")?.1.to_string();
            Some(Traced { at, sent, meaning })
        })
        .collect()
}

/// Runs `recipe` on the simulated SD2 drive in virtual time with `physics`; its console
/// output and its trace.
fn run_traced(name: &str, recipe: &str, physics: &[&str]) -> (i32, String, Vec<Traced>) {
    let (dir, file) = scratch_file(name, "recipe.yaml", recipe);
    let mut run = InProcessRun::new(file);
    run.output_dir = dir.clone();
    run.outputs.trace = Some(dir.join("run.trace"));
    run.connection.sim = physics
        .iter()
        .map(|p| drivescript::sim::SimSetting::parse(p).expect("a --sim setting"))
        .collect();
    let (result, output) = run.run();
    let trace = traced(&dir.join("run.trace"));
    (result.exit_code, output, trace)
}

fn reads_of(trace: &[Traced], object: &str) -> usize {
    let read = "read object ";
    trace
        .iter()
        .filter(|t| t.sent && t.meaning.starts_with(read) && t.meaning.ends_with(&format!(" {object}")))
        .count()
}

const SAMPLE: &str = "steps:\n  - sample: { objects: [speed_actual], every: 100 ms, for: 5 s }\n";

/// While a sample step reads the watched object, the watch judges the sample's values:
/// the run sends exactly the reads it sends without the watch. A watch of another object
/// reads on its own (the count sees a watch's reads), and a watch judging the sample's
/// values still ends the run when they cross it.
#[test]
fn a_watch_reads_the_sample_steps_value_instead_of_a_telegram_of_its_own() {
    let plain = format!("name: plain\ndrive: sd2\n{SAMPLE}");
    let (code, output, trace) = run_traced("plain", &plain, &[]);
    assert_eq!(code, 0, "{output}");
    let sampled = reads_of(&trace, "speed_actual");
    assert!(sampled >= 50, "{sampled} reads of speed_actual");

    let watched = format!(
        "name: watched\ndrive: sd2\nwatch:\n  speed_actual: {{ below: 20000 rpm }}\n  every: 100 ms\n{SAMPLE}"
    );
    let (code, output, trace) = run_traced("watched", &watched, &[]);
    assert_eq!(code, 0, "{output}");
    assert_eq!(
        reads_of(&trace, "speed_actual"),
        sampled,
        "the watch added reads of speed_actual during the sample:\n{output}"
    );

    let other = format!(
        "name: other\ndrive: sd2\nwatch:\n  motor_temperature: {{ below: 200 °C }}\n  every: 100 ms\n{SAMPLE}"
    );
    let (code, output, trace) = run_traced("other", &other, &[]);
    assert_eq!(code, 0, "{output}");
    assert_eq!(reads_of(&trace, "speed_actual"), sampled);
    assert!(
        reads_of(&trace, "motor_temperature") >= 45,
        "a watch of an object no sample reads reads it itself"
    );

    // The shared value is judged: standing still is not above 100 rpm.
    let crossed = format!(
        "name: crossed\ndrive: sd2\nwatch:\n  speed_actual: {{ above: 100 rpm }}\n  every: 100 ms\n{SAMPLE}"
    );
    let (code, output, trace) = run_traced("crossed", &crossed, &[]);
    assert_eq!(code, 1, "{output}");
    assert!(
        output.contains("FAIL  watch speed_actual above 100 rpm: 0 rpm at 0.000 s of the run"),
        "{output}"
    );
    assert!(
        reads_of(&trace, "speed_actual") < sampled,
        "the run ended at the first sample"
    );
}

/// Issue 41's run-in: a motor that heats more than expected (`heating=40K/A`) at
/// 18000 rpm crosses 80 °C in the first 50-minute dwell; the watch read every 10 s ends
/// the run there. The crossing lies after the last reading below 80 °C, so the safe
/// stop's first telegram (the speed setpoint 0) within 10 s of that reading is within one
/// watch interval of the crossing.
#[test]
fn the_run_in_ends_within_one_watch_interval_of_crossing_80_c_in_virtual_time() {
    let recipe = "name: Run-in with a temperature watch\ndrive: sd2\nwatch:\n  motor_temperature: { below: 80 °C }\n  every: 10 s\n\
                  steps:\n  - set: { speed_setpoint: 18000 rpm }\n  - go_to: operation_enabled\n  - repeat:\n      times: 5\n      steps:\n        - dwell: 50 min\n        - expect: { motor_temperature: { below: 80 °C } }\n";
    let (code, output, trace) = run_traced("run-in", recipe, &["heating=40K/A"]);
    assert_eq!(code, 1, "{output}");
    assert!(output.contains("watch crossed in step 3[1].1"), "{output}");
    let temperature = |t: &Traced| -> Option<f64> {
        let value = t.meaning.strip_prefix("reply motor_temperature = ")?;
        value.strip_suffix(" °C")?.parse().ok()
    };
    let replies: Vec<(f64, f64)> = trace
        .iter()
        .filter(|t| !t.sent)
        .filter_map(|t| Some((t.at, temperature(t)?)))
        .collect();
    let crossed = replies
        .iter()
        .position(|(_, v)| *v >= 80.0)
        .expect("a reading at 80 °C or above");
    assert!(crossed > 0, "the first reading is below 80 °C");
    let (below_at, below) = replies[crossed - 1];
    assert!(below < 80.0);
    let stop_at = trace
        .iter()
        .find(|t| t.sent && t.at >= below_at && t.meaning.contains("speed_setpoint = 0 rpm"))
        .expect("the safe stop's setpoint 0")
        .at;
    let took = stop_at - below_at;
    // One interval, and the few exchanges of the reading itself.
    assert!(
        took <= 10.0 + 0.05,
        "the safe stop began {took:.3} s after the last reading below 80 °C (at {below_at:.3} s)"
    );
    // The run ended in the first dwell, not after four hours of failed checks.
    assert!(stop_at < 3000.0 + 10.0, "stopped at {stop_at:.3} s");
    assert_eq!(
        replies.iter().filter(|(_, v)| *v >= 80.0).count(),
        1,
        "nothing read the temperature over the limit again"
    );
}

/// Three watches every 50 ms at 9600 baud would take 150 % of the line (each SD2 read is
/// 24 bytes, 25 ms on the wire): `check` and `run` refuse them with each watch's place and
/// the interval that fits, which then passes; at the family's 57600 baud they fit, and
/// without a line named there is nothing to compare with.
#[test]
fn check_refuses_watches_the_named_line_cannot_carry() {
    let watches = |every: &str| {
        format!(
            "name: Busy watches\ndrive: sd2\nwatch:\n  motor_temperature: {{ below: 80 °C }}\n  speed_actual: {{ below: 12000 rpm }}\n  current_actual: {{ below: 12 A }}\n  every: {every}\nsteps:\n  - dwell: 1 s\n"
        )
    };
    let (dir, busy) = scratch_file("busy", "busy.yaml", &watches("50 ms"));
    let busy = busy.to_string_lossy();
    let refused = cli(&["check", &busy, "--baud", "9600"], 2);
    let said = format!("{}{}", refused.stdout, refused.stderr);
    assert_has(
        &said,
        &[
            "the watches would take 150 % of the line's time on the wire alone, more than the 50 %",
            "busy.yaml:4:3: watch motor_temperature below 80 °C every 50ms: each read is 24 bytes, 25.0 ms on the wire at 9600 8N1",
            "busy.yaml:6:3: watch current_actual below 12 A every 50ms",
            "read less often (a larger `every`; 150 ms at the least) or at a higher baud rate",
        ],
    );
    let run = cli(&["run", &busy, "--baud", "9600", "--fast"], 2);
    assert_has(&run.stderr, &["the watches would take 150 %"]);
    assert!(!run.stdout.contains("finally"), "nothing ran:\n{}", run.stdout);
    cli(&["check", &busy, "--baud", "57600"], 0);
    cli(&["check", &busy], 0);
    let fits = write_file(&dir, "fits.yaml", &watches("150 ms"));
    cli(&["check", &fits.to_string_lossy(), "--baud", "9600"], 0);
    // A script's d.watch written with literals is compared with the line the same way.
    let script = |every: &str| {
        format!(
            "//! drive: sd2\nlet d = drive();\nd.watch(\"motor_temperature\", #{{ below: \"80 °C\", every: \"{every}\" }});\nd.watch(\"speed_actual\", #{{ below: \"12000 rpm\", every: \"{every}\" }});\nd.watch(\"current_actual\", #{{ below: 12, every: \"{every}\" }});\ndwell(\"1 s\");\n"
        )
    };
    let busy = write_file(&dir, "busy.rhai", &script("50 ms"));
    let refused = cli(&["check", &busy.to_string_lossy(), "--baud", "9600"], 2);
    assert_has(
        &refused.stderr,
        &[
            "the watches would take 150 % of the line's time",
            "busy.rhai:4:3: watch speed_actual below 12000 rpm every 50ms",
        ],
    );
    let fits = write_file(&dir, "fits.rhai", &script("150 ms"));
    cli(&["check", &fits.to_string_lossy(), "--baud", "9600"], 0);
}

/// A script's `d.watch` is named, reported and stored as a recipe's watch: the failed check
/// `watch motor_temperature below 80 °C` with its value, time and limit in JUnit and in the
/// results store, and the step it ended with the `d.watch` call's place.
#[test]
fn a_script_watch_is_reported_and_stored_as_a_recipe_watch() {
    let dir = scratch("script-store");
    let script = repo_root().join("tests/cases/failed/script_watch_crossed/script.rhai");
    let store = dir.join("store.db");
    let store = store.to_string_lossy();
    let junit = dir.join("run.xml");
    let (code, output) = run_recording(
        &script,
        &store,
        &[
            "--fast",
            "--sim",
            "heating=80K/A",
            "--junit",
            &junit.to_string_lossy(),
            "--output-dir",
            &dir.to_string_lossy(),
        ],
    );
    assert_eq!(code, 1, "{output}");
    let xml = std::fs::read_to_string(&junit).expect("JUnit written");
    assert_has(
        &xml,
        &[
            "<testcase name=\"watch motor_temperature below 80 °C\"",
            "<failure type=\"expect\" message=\"80 °C at 1175.495 s of the run: the watch motor_temperature below 80 °C was crossed; measured 80.0 °C; limits &lt; 80 °C\"",
        ],
    );
    let listed = cli(&["results", "list", "--simulated", "--results", &store], 0).stdout;
    let id = listed
        .lines()
        .nth(1)
        .and_then(|l| l.split_whitespace().next())
        .expect("the run listed");
    let shown = cli(&["results", "show", id, "--results", &store], 0).stdout;
    assert_has(
        &shown,
        &[
            "FAIL  watch motor_temperature below 80 °C: 80 °C at 1175.495 s of the run",
            "11  FAIL  dwell 50m  watch crossed in step 11: 80 °C at 1175.495 s of the run",
            "script_watch_crossed/script.rhai:7:3); the run ends here",
        ],
    );
}

/// The real process, in real time: a watch ends the run, and SIGTERM (a cancelled CI job)
/// arrives while the stop it started brakes the spindle. The stop goes on to the end, the
/// drive is read back safe, and the exit code names the signal. Windows has no SIGTERM:
/// there the signal is Ctrl-C.
#[test]
fn a_real_sigterm_during_the_stop_a_watch_started_lets_the_stop_finish() {
    let (signal, exit, said) = if cfg!(windows) {
        ("INT", 130, "INTERRUPTED: interrupted by Ctrl-C")
    } else {
        ("TERM", 143, "INTERRUPTED: interrupted by SIGTERM")
    };
    let (_, recipe) = scratch_file(
        "sigterm",
        "run.yaml",
        "name: A watch ends the run-in\ndrive: sd2\nwatch:\n  speed_actual: { below: 5000 rpm }\n  every: 500 ms\nsteps:\n  - go_to: operation_enabled\n  - set: { speed_setpoint: 6000 rpm }\n  - dwell: 1 h\n",
    );
    let mut run =
        crate::live_run::LiveRun::start(["run".as_ref(), recipe.as_os_str(), "--no-progress".as_ref()]);
    run.wait_for("watch crossed in step 3");
    run.signal(signal);
    let (code, output) = run.finish();
    assert_eq!(code, Some(exit), "{output}");
    assert_has(
        &output,
        &[
            "finally 4  ok    shutdown (default finally)  control word 6",
            said,
            "0 check(s) passed, 1 failed",
        ],
    );
    assert_left_at_standstill(&output, "ready to switch on");
}
