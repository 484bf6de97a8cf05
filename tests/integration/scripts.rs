//! Rhai scripts against the simulated drive: the shipped examples check and pass, the
//! telegrams a script sends, every ending (failed expect, drive fault, script error,
//! panic, a stop request during `sample` and during pure computation, a signal through a
//! real pseudo-terminal) runs the safe stop, and the sandbox refuses what it must.

use crate::live_run::LiveRun;
use crate::safety::{received, written, CONTROL_WORD, SPEED_SETPOINT};
use crate::support::{
    assert_has, assert_lacks, cli, control_words, drivescript, faults_before_the_run, repo_root, scratch,
    scratch_file, stderr, stdout, wide_speed_and_current_rows, write_file, InProcessRun,
};
use drivescript::run::RunResult;
use drivescript::stop_request::{StopRequests, StopSignal};
use std::sync::Arc;
use std::time::Duration;

/// Runs `text` as a script in-process (virtual time), with `prepare` for the simulator.
fn run_script(
    name: &str,
    text: &str,
    prepare: Option<&drivescript::run::PrepareSimulator>,
    stop: Arc<StopRequests>,
) -> (RunResult, String) {
    let dir = scratch(&format!("script-{name}"));
    let mut run = InProcessRun::new(write_file(&dir, "script.rhai", text));
    run.prepare = prepare;
    run.stop = stop;
    run.output_dir = dir;
    run.run()
}

/// [`run_script`] with nothing prepared and no stop request, which must exit with `code`.
#[track_caller]
fn script_exits(name: &str, text: &str, code: i32) -> (RunResult, String) {
    let (result, output) = run_script(name, text, None, Arc::new(StopRequests::new()));
    assert_eq!(result.exit_code, code, "{output}");
    (result, output)
}

#[test]
fn every_example_script_checks_and_passes_in_virtual_time() {
    let mut ran = 0;
    for entry in std::fs::read_dir(repo_root().join("recipes")).expect("recipes/") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("rhai") {
            continue;
        }
        let p = path.to_str().expect("utf-8 path");
        let check = cli(&["check", p], 0);
        assert!(check.stdout.contains("(script, "), "{p}: {}", check.stdout);
        let run = drivescript(&["run", p, "--fast"], "");
        let shown = format!("{}{}", stdout(&run), stderr(&run));
        assert_eq!(run.status.code(), Some(0), "{p}:\n{shown}");
        assert!(stdout(&run).contains("PASSED"), "{p}:\n{shown}");
        assert!(
            stdout(&run).contains("drive left in ready to switch on at 0 rpm"),
            "{p}:\n{shown}"
        );
        ran += 1;
    }
    assert!(ran >= 3, "only {ran} example scripts");
}

const START_AND_SPIN: &str = r#"//! drive: sd2
let d = drive();
d.shutdown();
d.switch_on();
d.set("speed_setpoint", "3000 rpm");
d.enable_operation();
d.wait_until("speed_actual", |v| v > 2970.0, "10 s");
let s = d.sample(["speed_actual"], "100 ms", "2 s");
expect_near("speed mean", s.mean("speed_actual"), 3000.0, "0.5 %");
d.set("speed_setpoint", 1.5, "krpm");
"#;

#[test]
fn a_script_sends_the_telegrams_its_calls_name_then_the_default_safe_stop() {
    let (result, output) = script_exits("telegrams", START_AND_SPIN, 0);
    // shutdown, switch_on, enable_operation; then the default finally's disable
    // operation and shutdown.
    assert_eq!(control_words(&result), [6, 7, 15, 7, 6], "{output}");
    let setpoints: Vec<i64> = received(&result)
        .iter()
        .filter_map(|(_, t)| written(t, SPEED_SETPOINT))
        .collect();
    // 0.001 rpm per count: 3000 rpm, 1.5 krpm, then the safe stop's 0.
    assert_eq!(setpoints, [3_000_000, 1_500_000, 0], "{output}");
    assert_has(
        &output,
        &[
            "script  script (",
            "     3  ok    shutdown  control word 6",
            "     5  ok    set speed_setpoint = 3000 rpm  written",
            "PASS  speed mean: measured",
            "finally 1  ok    set speed_setpoint = 0 rpm (default finally)",
            "drive left in ready to switch on at 0 rpm",
            "PASSED — ",
        ],
    );
    let report = result.report.expect("a report");
    assert_eq!(report.checks.iter().filter(|c| c.name == "speed mean").count(), 1);
    let check = report
        .checks
        .iter()
        .find(|c| c.name == "speed mean")
        .expect("check");
    assert_eq!(
        (check.limits.low, check.limits.high),
        (Some(2985.0), Some(3015.0))
    );
    assert_eq!((check.origin.line, check.origin.column), (9, 1));
    assert!(check.origin.path.ends_with("script.rhai"));
}

#[test]
fn a_loop_numbers_its_steps_by_line_and_pass_and_keeps_them_bounded() {
    let text = "let d = drive();\nfor i in 0..3 {\n    d.set(\"speed_setpoint\", i * 100, \"rpm\");\n}\n";
    let (result, _) = script_exits("passes", text, 0);
    let numbers: Vec<String> = result
        .report
        .expect("report")
        .steps
        .iter()
        .filter(|s| s.phase == "steps")
        .map(|s| s.number.clone())
        .collect();
    assert_eq!(numbers, ["3", "3.2", "3.3"]);
}

#[test]
fn a_failed_expect_fails_the_run_with_exit_1_and_the_drive_is_stopped() {
    let text = "let d = drive();\nd.go_to(\"operation_enabled\");\nexpect(\"speed is high\", d.read(\"speed_actual\") > 100.0, d.read(\"speed_actual\"));\nprint(\"goes on\");\n";
    let (result, output) = script_exits("failed-expect", text, 1);
    assert_has(&output, &["FAIL  speed is high: measured"]);
    assert!(
        output.contains("goes on"),
        "a failed expect lets the script go on:\n{output}"
    );
    assert!(control_words(&result).ends_with(&[7, 6]), "{output}");
}

#[test]
fn fail_ends_the_script_even_inside_try() {
    let text =
        "let d = drive();\ntry { fail(\"too slow\"); } catch { print(\"swallowed\"); }\nprint(\"after\");\n";
    let (_, output) = script_exits("fail", text, 1);
    assert!(
        !output.contains("swallowed") && !output.contains("after"),
        "{output}"
    );
}

#[test]
fn a_fault_caught_by_the_script_can_be_reset_and_the_start_retried() {
    let prepare = faults_before_the_run(|f| f.trip_at(Duration::from_millis(1), 4660));
    let text = std::fs::read_to_string(repo_root().join("recipes/fault-reset-start.rhai")).expect("example");
    let (result, output) = run_script("retry", &text, Some(&prepare), Arc::new(StopRequests::new()));
    assert_eq!(result.exit_code, 0, "{output}");
    assert_has(&output, &["resetting"]);
    // The fault reset (128) was sent before the successful start.
    let words = control_words(&result);
    let reset = words.iter().position(|w| *w == 128).expect("a fault reset");
    assert!(words[reset..].contains(&15), "{words:?}");
}

#[test]
fn a_stop_request_during_sample_stops_the_drive_at_once() {
    let stop = Arc::new(StopRequests::new());
    let signal_at = Duration::from_millis(4_250);
    stop.schedule(signal_at, StopSignal::INT);
    let text =
        "let d = drive();\nd.set(\"speed_setpoint\", 2000.0, \"rpm\");\nd.go_to(\"operation_enabled\");\n\
                let s = d.sample([\"speed_actual\"], \"30 s\", \"10 min\");\nprint(\"not reached\");\n";
    let (result, output) = run_script("signal-sample", text, None, stop);
    assert_eq!(result.exit_code, 130, "{output}");
    assert_lacks(&output, &["not reached"]);
    assert_has(&output, &["INTERRUPTED"]);
    let first_stop = received(&result)
        .into_iter()
        .find(|(at, t)| *at >= signal_at && written(t, SPEED_SETPOINT).is_some())
        .expect("a stop telegram after the signal");
    assert_eq!(written(&first_stop.1, SPEED_SETPOINT), Some(0));
    assert!(first_stop.0 - signal_at < Duration::from_millis(50), "{output}");
    assert!(control_words(&result).ends_with(&[7, 6]), "{output}");
}

#[test]
fn a_stop_request_ends_a_script_that_only_computes() {
    // Real time: the virtual clock stands still while a script computes, so a stop
    // arrives from another thread, as a signal does, while the loop runs (five million
    // operations take over a second in a test build; the stop comes after 300 ms).
    let stop = Arc::new(StopRequests::new());
    let text = "let d = drive();\nd.go_to(\"operation_enabled\");\nprint(\"computing\");\nlet i = 0;\ntry { while true { i += 1; } } catch { print(\"swallowed\"); }\n";
    let dir = scratch("script-signal-compute");
    let mut run = InProcessRun::new(write_file(&dir, "script.rhai", text));
    run.fast = false;
    run.stop = stop.clone();
    let sender = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(300));
        stop.request(StopSignal::TERM);
    });
    let (result, output) = run.run();
    sender.join().expect("sender");
    assert_eq!(result.exit_code, 143, "{output}");
    assert!(
        output.contains("computing"),
        "the stop came before the loop:\n{output}"
    );
    assert_lacks(&output, &["swallowed", "operations without calling the drive"]);
    assert!(control_words(&result).ends_with(&[7, 6]), "{output}");
}

#[test]
fn a_loop_that_calls_the_drive_runs_past_the_operation_limit() {
    // 20 000 passes of about 300 operations each: more than the limit in all, but never
    // that many between two drive calls.
    let text = "let d = drive();\nlet n = 0;\nfor i in 0..20000 {\n    let x = 0;\n    for k in 0..100 { x += k; }\n    n += d.read(\"speed_actual\") * 0.0 + 1;\n}\nexpect(\"passes\", n == 20000, n);\n";
    script_exits("long-loop", text, 0);
}

#[test]
fn the_sandbox_refuses_modules_eval_file_or_process_access_and_oversized_data() {
    let dir = scratch("sandbox");
    for (name, text, code, said) in [
        ("import", "import \"other\" as o;\n", 2, "modules are disabled"),
        ("eval", "let x = eval(\"1 + 2\");\n", 2, "`eval` is disabled"),
        (
            "file",
            "let f = open(\"/etc/passwd\");\n",
            2,
            "unknown function `open`",
        ),
        (
            "read-file",
            "let t = read_string(\"/etc/passwd\");\n",
            2,
            "unknown function `read_string`",
        ),
        (
            "process",
            "system(\"rm -rf /\");\n",
            2,
            "unknown function `system`",
        ),
        // A function named only at run time is not there either.
        (
            "computed",
            "let f = Fn(\"open\");\nf.call(\"/etc/passwd\");\n",
            3,
            "Function not found: open",
        ),
    ] {
        let path = dir.join(format!("{name}.rhai"));
        std::fs::write(&path, text).expect("script");
        let p = path.to_str().expect("utf-8");
        if code == 2 {
            let check = cli(&["check", p], 2);
            assert!(check.stderr.contains(said), "{name}: {}", check.stderr);
        }
        let (result, output) = InProcessRun::new(&path).run();
        assert_eq!(result.exit_code, code, "{name}:\n{output}");
        assert!(output.contains(said), "{name}:\n{output}");
        if code == 2 {
            assert!(result.simulator.is_none(), "{name}: nothing may be sent");
        }
        // The help names what a script can call, unless a close name of the API is meant.
        let close = output.contains("did you mean `read");
        if (said.starts_with("unknown function") && !close) || code == 3 {
            assert!(
                output.contains("no file, process or module access"),
                "{name}:\n{output}"
            );
        }
    }
}

#[test]
fn run_refuses_a_misspelt_call_before_it_opens_the_port() {
    let (_, path) = scratch_file(
        "misspelt",
        "script.rhai",
        "//! drive: sd2\nlet d = drive();\nd.go_to(\"operation_enabled\");\nlet w = d.sampel([\"speed_actual\"], \"100 ms\", \"1 s\");\n",
    );
    let p = path.to_str().expect("utf-8");
    // A port that does not exist: the script is refused before anything tries to open it.
    let run = drivescript(&["run", p, "--port", "/dev/drivescript-no-such-port"], "");
    assert_eq!(run.status.code(), Some(2), "{}", stderr(&run));
    let err = stderr(&run);
    assert_has(
        &err,
        &[
            "script.rhai:4:11]",
            "unknown method `sampel`",
            "did you mean `sample`?",
            "nothing was sent",
        ],
    );
    assert!(!err.contains("no-such-port"), "{err}");
}

#[test]
fn check_finds_literal_mistakes_with_places_and_suggestions_without_a_port() {
    let (_, path) = scratch_file(
        "check",
        "script.rhai",
        "//! drive: sd2\nlet d = drive();\nd.set(\"speed_setpont\", 3000.0, \"rpm\");\nd.set(\"speed_setpoint\", 300000.0, \"rpm\");\n\
         d.go_to(\"operation_enabld\", \"5 s\");\ndwell(\"5\");\nlet v = d.read_as(\"speed_actual\", \"A\");\n",
    );
    let p = path.to_str().expect("utf-8");
    // A port that does not exist: check must not try to open it.
    let err = cli(&["check", p, "--set", "sped=1"], 2).stderr;
    assert_has(
        &err,
        &[
            "script.rhai:3:7]",
            "did you mean `speed_setpoint`",
            "above the maximum of speed_setpoint",
            "did you mean `operation_enabled`",
            "`5` is not a duration",
            "A is not a unit of speed_actual",
            "--set sped: the script reads no parameter `sped`",
            "6 problems found; nothing was sent to the drive",
        ],
    );
}

#[test]
fn a_scripts_finally_replaces_the_default_and_the_stop_is_still_verified() {
    let text = "let d = drive();\nfn finally(d) {\n    d.set(\"speed_setpoint\", 0.0, \"rpm\");\n    d.wait_until(\"speed_actual\", |v| v.abs() < 5.0, \"30 s\");\n    d.quick_stop();\n}\nd.set(\"speed_setpoint\", 1000.0, \"rpm\");\nd.go_to(\"operation_enabled\");\ndwell(\"3 s\");\n";
    let (result, output) = run_script("finally", text, None, Arc::new(StopRequests::new()));
    assert_lacks(&output, &["(default finally)"]);
    assert_has(&output, &["finally 3  ok    quick_stop"]);
    // The verification reads the state back and says the truth.
    assert_has(&output, &["drive left in"]);
    let words = control_words(&result);
    assert_eq!(words.last(), Some(&2), "{words:?}");
}

#[test]
fn params_come_from_set() {
    let (_, path) = scratch_file(
        "params",
        "script.rhai",
        "let d = drive();\nlet speed = param(\"speed\");\nd.set(\"speed_setpoint\", speed);\nexpect(\"speed\", number(speed, \"rpm\") == 4000.0, speed);\n",
    );
    let mut run = InProcessRun::new(&path);
    run.set = vec![("speed".into(), "4 krpm".into())];
    run.run_expecting(0, &["params  speed = 4 krpm", "set speed_setpoint = 4000 rpm"]);
    InProcessRun::new(&path).run_expecting(3, &["parameter `speed` is not set: run with --set speed=VALUE"]);
}

/// A signal to the real binary driving a simulated drive through a pseudo-terminal while
/// a script samples every 30 s: the drive is stopped at once and the run exits 130.
#[test]
fn sigint_during_a_scripts_sample_through_a_pty_stops_the_drive() {
    use crate::safety::traced_writes;
    use crate::support::Simulator;
    let sim = Simulator::pty(&[]);
    let (dir, script) = scratch_file(
        "script-pty",
        "script.rhai",
        "let d = drive();\nd.go_to(\"operation_enabled\", \"2 s\");\nd.set(\"speed_setpoint\", 2000.0, \"rpm\");\n\
         d.wait_until(\"speed_actual\", |v| v > 1980.0, \"10 s\");\nprint(\"sampling\");\n\
         let s = d.sample([\"speed_actual\"], \"30 s\", \"10 min\");\n",
    );
    let trace = dir.join("run.trace");
    let mut run = LiveRun::run_on(&script, &sim.endpoint, &[("--trace", &trace)]);
    run.wait_for("sampling");
    std::thread::sleep(Duration::from_millis(300));
    let before = std::fs::read_to_string(&trace).expect("trace").lines().count();
    run.signal("INT");
    let (code, all) = run.finish();
    assert_eq!(code, Some(130), "{all}");
    assert_has(
        &all,
        &["INTERRUPTED", "drive left in ready to switch on at 0 rpm"],
    );
    let trace_text = std::fs::read_to_string(&trace).expect("trace");
    let after: String = trace_text.lines().skip(before).collect::<Vec<_>>().join("\n");
    let setpoints: Vec<i64> = traced_writes(&after, SPEED_SETPOINT)
        .into_iter()
        .map(|(_, v)| v)
        .collect();
    assert_eq!(setpoints.first(), Some(&0), "{after}");
    let words: Vec<i64> = traced_writes(&after, CONTROL_WORD)
        .into_iter()
        .map(|(_, v)| v)
        .collect();
    assert_eq!(words, [7, 6], "control words after the signal");
}

#[test]
fn a_scripts_checks_reach_junit_html_and_csv_like_a_recipes() {
    let dir = scratch("script-reports");
    let text =
        "let d = drive();\nd.set(\"speed_setpoint\", 2000.0, \"rpm\");\nd.go_to(\"operation_enabled\");\n\
                d.wait_until(\"speed_actual\", |v| v > 1980.0, \"10 s\");\n\
                let s = d.sample([\"speed_actual\", \"current_actual\"], \"100 ms\", \"2 s\");\n\
                expect_near(\"speed mean\", s.mean(\"speed_actual\"), 2000.0, \"0.5 %\");\n\
                expect_near(\"too tight\", s.mean(\"speed_actual\"), 2100.0, \"5 rpm\");\n";
    let mut run = InProcessRun::new(write_file(&dir, "script.rhai", text));
    let (junit, html) = run.reports_in(&dir);
    let csv = dir.join("samples.csv");
    run.outputs.csv = Some(csv.clone());
    let (result, output) = run.run();
    assert_eq!(result.exit_code, 1, "{output}");
    let junit_text = std::fs::read_to_string(&junit).expect("junit");
    let doc = roxmltree::Document::parse(&junit_text).expect("well-formed JUnit");
    let cases: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("testcase"))
        .filter_map(|n| n.attribute("name"))
        .collect();
    assert!(cases.iter().any(|c| c.contains("speed mean")), "{junit_text}");
    assert!(cases.iter().any(|c| c.contains("too tight")), "{junit_text}");
    let failures = doc.descendants().filter(|n| n.has_tag_name("failure")).count();
    assert_eq!(failures, 1, "{junit_text}");
    assert_has(&junit_text, &["script.rhai:7:1"]);
    let html_text = std::fs::read_to_string(&html).expect("html");
    assert!(
        html_text.contains("too tight") && html_text.contains("FAILED"),
        "html report"
    );
    let csv_text = std::fs::read_to_string(&csv).expect("csv");
    assert!(csv_text.lines().count() > 2 * 20, "{csv_text}");
    // Every row names the script's step it was sampled in, as a recipe's rows do.
    let steps: Vec<&str> = csv_text
        .lines()
        .skip(1)
        .filter_map(|row| row.split(',').nth(2))
        .collect();
    assert!(
        !steps.is_empty() && steps.iter().all(|s| !s.is_empty()),
        "{csv_text}"
    );
}

#[test]
fn a_second_stop_request_abandons_the_scripts_finally_and_switches_off_at_once() {
    let stop = Arc::new(StopRequests::new());
    stop.schedule(Duration::from_secs(5), StopSignal::INT);
    stop.schedule(Duration::from_secs(8), StopSignal::INT);
    let text = "let d = drive();\nfn finally(d) {\n    print(\"finally starts\");\n    dwell(\"30 s\");\n    print(\"finally ends\");\n}\n\
                d.set(\"speed_setpoint\", 2000.0, \"rpm\");\nd.go_to(\"operation_enabled\");\ndwell(\"1 min\");\n";
    let (result, output) = run_script("second-signal", text, None, stop);
    assert_eq!(result.exit_code, 130, "{output}");
    assert_has(&output, &["finally starts"]);
    assert_lacks(&output, &["finally ends"]);
    assert_has(&output, &["power stage switched off at once"]);
    assert_eq!(
        control_words(&result).last(),
        Some(&0),
        "disable voltage last:\n{output}"
    );
}

#[test]
fn an_endless_loop_in_the_scripts_finally_is_stopped_and_the_stop_still_verified() {
    let text = "let d = drive();\nfn finally(d) {\n    d.set(\"speed_setpoint\", 0.0, \"rpm\");\n    let i = 0;\n    loop { i += 1; }\n}\n\
                d.go_to(\"operation_enabled\");\n";
    let (result, output) = run_script("finally-loop", text, None, Arc::new(StopRequests::new()));
    assert_has(
        &output,
        &[
            "the script's finally ended early",
            "operations without calling the drive",
            "drive left in",
        ],
    );
    // The verification found the drive still enabled and escalated.
    assert_eq!(result.exit_code, 3, "{output}");
}

/// `//! link:` in a script's header chooses the SD2 cyclic channel as a recipe's `link:`
/// does; a wrong setting is refused before anything is sent.
#[test]
fn a_scripts_header_chooses_the_cyclic_channel() {
    let dir = scratch("script-link");
    let body = "let d = drive();\nd.go_to(\"operation_enabled\", \"5 s\");\nd.set(\"speed_setpoint\", 6000.0, \"rpm\");\n\
                d.wait_until(\"speed_actual\", |v| v > 5900.0, \"30 s\");\n\
                let s = d.sample([\"speed_actual\"], \"100 ms\", \"2 s\");\n\
                expect_near(\"speed mean\", s.mean(\"speed_actual\"), 6000.0, \"0.5 %\");\n";
    let good = write_file(
        &dir,
        "script.rhai",
        &format!("//! drive: sd2\n//! link: channel=cyclic, velocity_scaling=24000rpm\n{body}"),
    );
    let out = cli(&["run", good.to_str().expect("path"), "--fast"], 0);
    assert_has(&out.stdout, &["(cyclic channel)"]);
    let bad = dir.join("bad.rhai");
    std::fs::write(&bad, format!("//! drive: sd2\n//! link: channel=cyclic\n{body}")).expect("script");
    let out = cli(&["run", bad.to_str().expect("path"), "--fast"], 2);
    assert_has(&out.stderr, &["--velocity-scaling"]);
    // Said as for a recipe, naming where the setting is written.
    assert_has(
        &out.stderr,
        &["(link settings come from the script's `//! link:` and the command line)"],
    );
}

/// A link setting is checked as merged: the file's `link:` / `//! link:` gives the
/// velocity scaling, the command line the channel; neither alone is refused.
#[test]
fn the_files_link_settings_and_the_command_lines_are_checked_together() {
    let (dir, script) = scratch_file(
        "link-merged",
        "script.rhai",
        "//! drive: sd2\n//! link: velocity_scaling=24000rpm\nlet d = drive();\nd.go_to(\"operation_enabled\", \"5 s\");\n",
    );
    let recipe = write_file(
        &dir,
        "recipe.yaml",
        "name: merged link\ndrive: sd2\nlink: { velocity_scaling: 24000 rpm }\nsteps:\n  - go_to: operation_enabled\n",
    );
    for file in [&script, &recipe] {
        let path = file.to_str().expect("path");
        let out = cli(&["run", path, "--fast", "--channel", "cyclic"], 0);
        assert_has(&out.stdout, &["(cyclic channel)"]);
    }
}

/// `d.sample(…, "file.csv")` writes that sample's rows as a recipe sample step's `csv:`
/// does: the same layout, under `--output-dir`, continued by a later pass of the same line.
#[test]
fn a_samples_csv_file_holds_its_rows_in_the_recipes_layout() {
    let dir = scratch("script-sample-csv");
    let text = "let d = drive();\nd.set(\"speed_setpoint\", 2000.0, \"rpm\");\nd.go_to(\"operation_enabled\");\n\
                d.wait_until(\"speed_actual\", |v| v > 1980.0, \"10 s\");\n\
                for pass in 0..2 { let s = d.sample([\"speed_actual\", \"current_actual\"], \"100 ms\", \"1 s\", \"runs/speed.csv\"); }\n";
    let mut run = InProcessRun::new(write_file(&dir, "script.rhai", text));
    run.output_dir = dir.clone();
    let (result, output) = run.run();
    assert_eq!(result.exit_code, 0, "{output}");
    let report = result.report.as_ref().expect("a report");
    let path = dir.join("runs/speed.csv");
    assert_eq!(report.csv_files, [path.display().to_string()], "{output}");
    let mut reader = csv::Reader::from_path(&path).expect("the sample's csv file");
    assert_eq!(
        reader.headers().expect("a header"),
        &csv::StringRecord::from(vec!["time [s]", "utc", "step", "object", "value", "unit"])
    );
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    // 11 samples of two objects, twice.
    assert_eq!(rows.len(), 2 * 11 * 2, "{rows:?}");
    let steps: Vec<&str> = rows.iter().map(|r| &r[2]).collect();
    assert!(steps[..22].iter().all(|s| *s == "5"), "{steps:?}");
    assert!(steps[22..].iter().all(|s| *s == "5.2"), "{steps:?}");
    for pair in rows.chunks(2) {
        assert_eq!((&pair[0][3], &pair[0][5]), ("speed_actual", "rpm"));
        assert_eq!((&pair[1][3], &pair[1][5]), ("current_actual", "A"));
        assert_eq!(pair[0][0], pair[1][0], "one time per sample");
        assert!(humantime::parse_rfc3339(&pair[0][1]).is_ok(), "{pair:?}");
        let speed: f64 = pair[0][4].parse().expect("a number");
        assert!((speed - 2000.0).abs() < 20.0, "{pair:?}");
    }
    let times: Vec<f64> = rows
        .iter()
        .step_by(2)
        .map(|r| r[0].parse().expect("time"))
        .collect();
    assert!(
        times[..11].windows(2).all(|w| ((w[1] - w[0]) - 0.1).abs() < 1e-6),
        "{times:?}"
    );
}

/// `--csv-wide` gives a script's sample file one column per object, as a recipe's.
#[test]
fn csv_wide_gives_a_scripts_sample_file_one_column_per_object() {
    let dir = scratch("script-sample-csv-wide");
    let text = "let d = drive();\nlet s = d.sample([\"speed_actual\", \"current_actual\"], \"100 ms\", \"1 s\", \"wide.csv\");\n";
    let mut run = InProcessRun::new(write_file(&dir, "script.rhai", text));
    run.output_dir = dir.clone();
    run.outputs.csv_wide = true;
    let (result, output) = run.run();
    assert_eq!(result.exit_code, 0, "{output}");
    let rows = wide_speed_and_current_rows(&dir.join("wide.csv"));
    assert_eq!(rows.len(), 11);
    assert!(rows.iter().all(|r| r.len() == 5 && &r[2] == "2"), "{rows:?}");
}

/// A script writes only under `--output-dir`: a literal name outside is refused by the
/// check, a computed one when the script gets there (located, after the safe stop).
#[test]
fn a_scripts_csv_file_outside_the_output_directory_is_refused() {
    let dir = scratch("script-sample-csv-outside");
    let literal =
        "let d = drive();\nlet s = d.sample([\"speed_actual\"], \"100 ms\", \"1 s\", \"../escape.csv\");\n";
    let path = write_file(&dir, "script.rhai", literal);
    let err = cli(&["check", path.to_str().expect("utf-8")], 2).stderr;
    assert_has(
        &err,
        &[
            "script.rhai:2:53]",
            "`../escape.csv` is outside the output directory",
        ],
    );
    let computed = "let d = drive();\nd.go_to(\"operation_enabled\");\nlet up = \"..\";\n\
                    let s = d.sample([\"speed_actual\"], \"100 ms\", \"1 s\", up + \"/escape.csv\");\n";
    let (_, output) = script_exits("csv-outside", computed, 3);
    assert_has(
        &output,
        &[
            "script.rhai:4:",
            "is outside the output directory",
            "drive left in ready to switch on",
        ],
    );
    assert!(!dir.parent().expect("a parent").join("escape.csv").exists());
}

/// A `wait_until` condition that uses the drive the wait is called on: `check` finds it
/// where the condition uses the drive (Rhai would refuse the call as a data race with no
/// place), and `run` sends nothing.
#[test]
fn check_finds_a_wait_until_condition_that_uses_the_drive() {
    let (_, path) = scratch_file(
        "script-condition-drive",
        "script.rhai",
        "//! drive: sd2\nlet d = drive();\nd.set(\"speed_setpoint\", 2000.0, \"rpm\");\nd.go_to(\"operation_enabled\");\n\
         d.wait_until(\"speed_actual\", |v| v > d.read(\"speed_setpoint\") - 10.0, \"10 s\");\n",
    );
    let p = path.to_str().expect("utf-8");
    let err = cli(&["check", p], 2).stderr;
    assert_has(
        &err,
        &[
            "a wait_until condition must not use the drive: `d` is used inside the condition",
            "script.rhai:5:3]",
            "the drive, inside the condition",
            "in this wait_until",
            "let target = d.read(\"speed_setpoint\");",
        ],
    );
    let (result, output) = InProcessRun::new(&path).run_expecting(2, &["nothing was sent to the drive"]);
    assert!(result.simulator.is_none(), "no drive opened: {output}");
}

/// A condition the text does not show (kept in an array) still gets a place: Rhai's data
/// race refusal, which has none, is shown at the wait it came from; the safe stop runs.
#[test]
fn a_data_race_in_wait_until_is_located_at_the_wait_and_the_drive_is_stopped() {
    let text =
        "let d = drive();\nd.set(\"speed_setpoint\", 2000.0, \"rpm\");\nd.go_to(\"operation_enabled\");\n\
                let conditions = [|v| v > d.read(\"speed_setpoint\") - 10.0];\n\
                d.wait_until(\"speed_actual\", conditions[0], \"10 s\");\n";
    let (result, output) = script_exits("data-race", text, 3);
    assert_has(
        &output,
        &[
            "script.rhai:5:3]",
            "the wait_until condition holds the drive the wait is called on",
            "or wait on that object itself",
        ],
    );
    assert_lacks(&output, &["Data race detected"]);
    assert_has(&output, &["drive left in ready to switch on"]);
    assert!(control_words(&result).ends_with(&[7, 6]), "{output}");
}

/// A condition that calls another drive handle (made in a function, so the text does not
/// show it) is refused at the call inside the condition, located, and the drive stopped.
#[test]
fn a_condition_that_calls_the_drive_is_refused_at_its_place() {
    let text =
        "let d = drive();\nd.set(\"speed_setpoint\", 2000.0, \"rpm\");\nd.go_to(\"operation_enabled\");\n\
                fn above_setpoint(d) { |v| v > d.read(\"speed_setpoint\") - 10.0 }\n\
                d.wait_until(\"speed_actual\", above_setpoint(d), \"10 s\");\n";
    let (result, output) = script_exits("condition-calls", text, 3);
    assert_has(&output, &["script.rhai:4:34]"]);
    assert!(
        output.contains("ERROR: ")
            && output.contains("script.rhai:4:34: a wait_until condition must not call the drive"),
        "{output}"
    );
    assert_has(&output, &["read any other value before the wait"]);
    assert!(control_words(&result).ends_with(&[7, 6]), "{output}");
}
