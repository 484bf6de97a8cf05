//! The one verdict rule seen from outside: a run whose checks all passed but whose spindle
//! is left coasting is the same ERROR (exit code 3) on the console, in JUnit, in the HTML
//! report, in the results store and on the unit's certificate; and `check` warns of an
//! enable that would start at a setpoint left from before a disable.

use crate::support::{assert_has, cli, drivescript, scratch_file, stderr, stdout};

/// Every check passes, but the coast-down ends at 3000 rpm and the stop timeout (2 s)
/// ends before the spindle stands still.
const COASTING_AT_THE_END: &str = "name: Coast-down as the last step\ndrive: sd2\nsteps:\n  - set: { speed_setpoint: 6000 rpm }\n  - go_to: operation_enabled\n  - wait_until: { speed_actual: { near: 6000 rpm, within: 1 % } }\n  - coast_down: { from: 5900 rpm, below: 3000 rpm, expect: { below: 60 s } }\n";

#[test]
fn a_spindle_left_coasting_is_the_same_error_in_every_report_and_the_store() {
    let (dir, recipe) = scratch_file("verdict-coasting", "recipe.yaml", COASTING_AT_THE_END);
    let (junit, html, store) = (
        dir.join("junit.xml"),
        dir.join("report.html"),
        dir.join("results.sqlite"),
    );
    let path = |p: &std::path::Path| p.to_string_lossy().to_string();
    let out = drivescript(
        &[
            "run",
            &path(&recipe),
            "--fast",
            "--stop-timeout",
            "2s",
            "--unit",
            "serial=SP-900001",
            "--junit",
            &path(&junit),
            "--report",
            &path(&html),
            "--results",
            &path(&store),
        ],
        "",
    );
    let text = stdout(&out);
    assert_eq!(out.status.code(), Some(3), "{text}{}", stderr(&out));
    let why = "the spindle was left coasting above standstill";
    assert_has(
        &text,
        &[
            "PASS  coast-down",
            "still coasts at",
            "STILL COASTING",
            &format!("ERROR: {why}"),
        ],
    );
    let junit_text = std::fs::read_to_string(&junit).expect("junit");
    assert_has(
        &junit_text,
        &[
            "name=\"verdict\" value=\"ERROR\"",
            "name=\"exit_code\" value=\"3\"",
            why,
        ],
    );
    let html_text = std::fs::read_to_string(&html).expect("html");
    assert_has(&html_text, &["ERROR (exit code 3)", why]);
    let listed = cli(&["results", "list", "--simulated", "--results", &path(&store)], 0);
    assert_has(
        &listed.stdout,
        &["ERROR (simulated)  Coast-down as the last step  SP-900001"],
    );
    let certificate = cli(
        &[
            "results",
            "report",
            "--unit",
            "SP-900001",
            "--simulated",
            "--results",
            &path(&store),
        ],
        0,
    );
    assert_has(&certificate.stdout, &["NOT CONFIRMED", "still coasting", why]);
}

#[test]
fn check_warns_of_an_enable_at_a_setpoint_left_from_before_a_disable() {
    let (_, recipe) = scratch_file(
        "verdict-leftover",
        "recipe.yaml",
        "name: Enable again\ndrive: sd2\nsteps:\n  - set: { speed_setpoint: 12000 rpm }\n  - go_to: operation_enabled\n  - go_to: ready_to_switch_on\n  - go_to: operation_enabled\n",
    );
    let out = cli(&["check", &recipe.to_string_lossy()], 0);
    let shown = recipe.display();
    assert_has(
        &out.stderr,
        &[&format!(
            "warning: {shown}:7:5: this enable starts the drive at speed_setpoint = 12000 rpm, left standing from {shown}:4:5 though the drive was disabled at {shown}:6:5"
        )],
    );
}
