//! One run pipeline for recipes and scripts: what a script used to skip because it ran
//! through a copy of the recipe's pipeline — the comparison with the drive's own limits
//! for named drives, the early word about a drive that never answers, and the not-run
//! JUnit and HTML reports of a run that cannot start.

use crate::lenze_931::refused_on_931;
use crate::support::{scratch, scratch_file, write_file};

/// A script with `//! drives:` has its literal values compared with the limits each
/// named drive reports, as a recipe with `drives:` does, before anything moves. (Only
/// the 931 reports limits, and it has one drive per line, so the drive is one.)
#[test]
fn a_script_with_named_drives_is_refused_by_a_drive_limit_before_anything_moves() {
    let (output, requests) = refused_on_931(
        "script-drives-limits",
        "named.rhai",
        "//! drives: axis = lenze-931\nlet axis = drive(\"axis\");\naxis.set(\"operating_mode\", 9);\naxis.set(\"speed_setpoint\", 100.0, \"rpm\");\n",
    );
    // The state read that tells a silent drive early, then each object's limits once.
    assert_eq!(
        requests,
        ["OR:0021", "ON:0014", "OX:0014", "ON:0010", "OX:0010"],
        "{output}"
    );
    assert!(
        output.contains(
            "named.rhai:3:28: set axis.operating_mode = 9 is above the maximum the drive reports, 3"
        ),
        "{output}"
    );
    assert!(output.contains("nothing was sent to move the drive"), "{output}");
}

/// A script on a drive that never answers is told so once, before it starts, with what
/// to check, as a recipe is; its JUnit file says why.
#[test]
fn a_script_against_a_drive_that_never_answers_says_so_early() {
    let (_, script) = scratch_file(
        "script-silent",
        "silent.rhai",
        "let d = drive();\nprint(d.read(\"speed_actual\"));\n",
    );
    let err = crate::command_line::said_early_that_the_drive_does_not_answer(
        script.to_str().expect("utf-8"),
        "script-silent",
    );
    assert!(err.contains("the script did not start"), "{err}");
}

/// A script that cannot start (invalid, or its port cannot be opened) replaces the JUnit
/// and HTML files it was asked for with ones that say why, as a recipe does.
#[test]
fn a_refused_script_writes_its_not_run_junit_and_html() {
    let dir = scratch("script-not-run");
    let p = |name: &str| dir.join(name).to_str().expect("utf-8").to_string();
    let (junit, html) = (p("junit.xml"), p("report.html"));
    let bad = write_file(
        &dir,
        "bad.rhai",
        "let d = drive();\nd.set(\"speed_setpont\", 1.0, \"rpm\");\n",
    );
    crate::outputs::invalid_run_writes_not_run_reports(&bad, &junit, &html);

    let good = write_file(
        &dir,
        "good.rhai",
        "let d = drive();\nprint(d.read(\"speed_actual\"));\n",
    );
    crate::outputs::unreachable_run_writes_not_run_reports(good.to_str().expect("utf-8"), &junit, &html);
}

/// What a further observer of the run gets: every check and the finished report, after
/// the console, for a recipe and for a script alike.
#[derive(Default)]
struct Tally {
    checks: Vec<String>,
    finished: Option<String>,
}

impl drivescript::session::RunObserver for Tally {
    fn check(&mut self, result: &drivescript::session::CheckResult) {
        self.checks.push(result.name.clone());
    }
    fn run_finished(&mut self, report: &drivescript::session::RunReport) {
        self.finished = Some(report.recipe.clone());
    }
}

#[test]
fn an_observer_given_with_the_request_sees_every_check_of_a_recipe_and_a_script() {
    let (_, script) = scratch_file(
        "observers",
        "tally.rhai",
        "let d = drive();\nexpect_near(\"zero\", d.read(\"speed_actual\"), 0.0, 5.0);\n",
    );
    let recipe = crate::support::repo_root().join("tests/cases/ok/commissioning/recipe.yaml");
    for file in [recipe, script] {
        let tally = std::sync::Arc::new(std::sync::Mutex::new(Tally::default()));
        let mut run = crate::support::InProcessRun::new(&file);
        run.observers.push(tally.clone());
        let (result, output) = run.run();
        let report = result.report.expect("the run started");
        let tally = tally.lock().expect("not poisoned");
        let names: Vec<String> = report.checks.iter().map(|c| c.name.clone()).collect();
        assert!(!names.is_empty(), "{output}");
        assert_eq!(tally.checks, names, "{output}");
        assert_eq!(tally.finished.as_deref(), Some(report.recipe.as_str()));
    }
}

/// `--quiet` prints what a CI log needs and nothing else: failed steps and checks, the
/// drive's end state, the safe stop's notes when it went wrong, and the verdict line.
#[test]
fn quiet_runs_print_failures_the_end_state_and_the_verdict_only() {
    let case = |name: &str| format!("{}/tests/cases/{name}/recipe.yaml", env!("CARGO_MANIFEST_DIR"));
    let quiet_run = |name: &str| {
        let mut run = crate::support::InProcessRun::new(case(name));
        run.outputs.quiet = true;
        run.output_dir = scratch(&format!("quiet-{}", name.replace('/', "-")));
        let (result, output) = run.run();
        (result.exit_code, output)
    };
    let (code, output) = quiet_run("ok/run_in");
    assert_eq!(code, 0, "{output}");
    let lines: Vec<&str> = output.lines().collect();
    assert_eq!(lines.len(), 2, "{output}");
    assert_eq!(lines[0], "drive left in ready to switch on at 0 rpm");
    assert!(
        lines[1].starts_with("PASSED — 22 step(s), 4 check(s) passed, 0 failed, 5 wait(s) met"),
        "{output}"
    );

    let (code, output) = quiet_run("failed/expect_out_of_tolerance");
    assert_eq!(code, 1, "{output}");
    let lines: Vec<&str> = output.lines().collect();
    assert_eq!(lines.len(), 4, "{output}");
    assert!(
        lines[0]
            .trim_start()
            .starts_with("FAIL  speed_actual near 5000 rpm"),
        "{output}"
    );
    assert!(lines[1].trim_start().starts_with("4  FAIL  expect"), "{output}");
    assert!(lines[3].starts_with("FAILED — "), "{output}");

    // A safe stop that went wrong keeps its notes.
    use drivescript::drive::device_control::DeviceCommand;
    let ignore = |sim: &std::sync::Arc<std::sync::Mutex<dyn drivescript::sim::SimulatedDrive>>,
                  _: &drivescript::clock::SharedClock| {
        let mut sim = sim.lock().expect("simulator lock");
        sim.faults().ignore_commands(&[
            DeviceCommand::DisableOperation,
            DeviceCommand::Shutdown,
            DeviceCommand::QuickStop,
            DeviceCommand::DisableVoltage,
        ]);
    };
    let mut run = crate::support::InProcessRun::new(case("error/drive_ignores_every_stop"));
    run.outputs.quiet = true;
    run.prepare = Some(&ignore);
    run.safe_stop.stop_timeout = Some(std::time::Duration::from_secs(5));
    run.output_dir = scratch("quiet-stop");
    let (result, output) = run.run();
    assert_eq!(result.exit_code, 3, "{output}");
    assert!(
        output.contains("safe stop: power stage switched off at once"),
        "{output}"
    );
    assert!(output.contains("CHECK THE DRIVE BY HAND"), "{output}");
    assert!(!output.contains(" ok "), "{output}");
    assert!(
        output.contains("ERROR: the safe stop could not be confirmed"),
        "{output}"
    );
}
