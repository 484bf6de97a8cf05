//! Every capture drivescript records replays: per drive family, a run against the simulated
//! drive writes its `--trace`, and `run --replay` of that trace with the same recipe gets
//! the same verdict and exit code. (A CANopen trace used not to: its NMT start was left out
//! of the exchanges, so the replay said the capture "never answered" it.)

use crate::support::{command, console, scratch_file};

/// Enabled, at 600 rpm, checked, stopped by the safe stop: every kind of telegram a run sends.
const MOVES: &str = "  - read: [status_word]
  - go_to: { state: operation_enabled, timeout: 2 s }
  - set: { speed_setpoint: 600 rpm }
  - wait_until: { speed_actual: { near: 600 rpm, within: 2 % }, timeout: 10 s }
  - expect: { speed_actual: { near: 600 rpm, within: 2 % } }
";

/// The verdict line (the last) and exit code of `run RECIPE ARGS`.
fn verdict(recipe: &std::path::Path, args: &[&str]) -> (Option<i32>, String) {
    let out = command()
        .arg("run")
        .arg(recipe)
        .args(args)
        .current_dir(recipe.parent().expect("the recipe's folder"))
        .output()
        .expect("drivescript runs");
    let text = console(&out.stdout, &out.stderr);
    let last = text
        .lines()
        .rev()
        .find(|l| l.starts_with("PASSED") || l.starts_with("FAILED") || l.starts_with("ERROR"))
        .unwrap_or_else(|| panic!("no verdict line in:\n{text}"))
        .to_string();
    (out.status.code(), format!("{last}\n---\n{text}"))
}

fn recorded_then_replayed(drive: &str, steps: &str) {
    let recipe = format!("name: capture round trip\ndrive: {drive}\nsteps:\n{steps}");
    let (dir, path) = scratch_file(drive, "recipe.yaml", &recipe);
    let trace = dir.join("run.trace");
    let trace = trace.to_str().expect("a UTF-8 path");
    let (code, recorded) = verdict(&path, &["--fast", "--trace", trace]);
    assert_eq!(code, Some(0), "{drive}: the recorded run passes: {recorded}");
    let (replay_code, replayed) = verdict(&path, &["--replay", trace]);
    let line = |t: &str| t.lines().next().unwrap_or_default().to_string();
    assert_eq!(
        (replay_code, line(&replayed)),
        (code, line(&recorded)),
        "{drive}: the replay of its own capture gets another verdict:\n{replayed}"
    );
}

#[test]
fn a_canopen_capture_replays_with_its_nmt_start() {
    recorded_then_replayed("canopen", MOVES);
}

#[test]
fn a_lenze_9400_capture_replays() {
    recorded_then_replayed("lenze-9400", "  - read: [ident, heatsink_temperature]\n");
}

#[test]
fn an_sd2_capture_replays() {
    recorded_then_replayed("sd2", MOVES);
}

#[test]
fn a_control_techniques_capture_replays() {
    recorded_then_replayed("ct-unidrive-sp", MOVES);
}

#[test]
fn a_lenze_931_capture_replays() {
    recorded_then_replayed("lenze-931", "  - read: [ident, firmware_version]\n");
}

#[test]
fn a_modbus_rtu_capture_replays() {
    recorded_then_replayed("modbus-inverter", MOVES);
}

#[test]
fn a_modbus_tcp_capture_replays() {
    recorded_then_replayed("modbus-tcp-inverter", MOVES);
}
