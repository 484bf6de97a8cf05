//! The safe stop brakes a turning drive before anything disables it: Ctrl-C on every
//! shipped recipe and script that enables a drive, through a real pseudo-terminal (a COM
//! port under Wine) against the simulated SD2, must show the spindle below the standstill
//! threshold before the first disable telegram, whatever the recipe's own `finally`; and
//! `check` says where a recipe or script opts out.

use crate::support::{drivescript, stdout};

use crate::live_run::LiveRun;
use crate::safety::{traced_writes, CONTROL_WORD, SPEED_SETPOINT};
use crate::support::{repo_root, Simulator};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The default standstill threshold (rpm).
pub(crate) const STANDSTILL: f64 = 10.0;
/// Control word of enable operation (SD2).
pub(crate) const ENABLE_OPERATION: i64 = 15;

/// The shipped recipes and scripts that enable a drive.
fn shipped_recipes_that_enable() -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(repo_root().join("recipes"))
        .expect("recipes/")
        .map(|e| e.expect("entry").path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "rhai")))
        .filter(|p| {
            std::fs::read_to_string(p)
                .expect("recipe text")
                .contains("operation_enabled")
        })
        .collect();
    found.sort();
    found
}

/// The speed values (rpm) of the trace's speed_actual replies, each with its line number.
pub(crate) fn speed_replies(trace: &str) -> Vec<(usize, f64)> {
    numbered(trace, |line| {
        let (_, after) = line.split_once("# reply speed_actual = ")?;
        after.split_whitespace().next()?.parse().ok()
    })
}

/// The line numbers and values of the control words written in the trace.
pub(crate) fn control_words(trace: &str) -> Vec<(usize, i64)> {
    numbered(trace, |line| {
        Some(traced_writes(line, CONTROL_WORD).into_iter().next()?.1)
    })
}

/// What `find` finds in the trace's lines, each with its line number.
fn numbered<T>(trace: &str, find: impl Fn(&str) -> Option<T>) -> Vec<(usize, T)> {
    trace
        .lines()
        .enumerate()
        .filter_map(|(i, line)| Some((i, find(line)?)))
        .collect()
}

/// Runs `recipe` on a pty, sends Ctrl-C once the spindle was told to turn, and checks that
/// the last speed read before the first disable telegram is below standstill. `Err` says
/// what went wrong (the test collects every recipe's outcome before it fails).
fn ctrl_c_while_turning(recipe: &Path) -> Result<(), String> {
    let sim = Simulator::pty(&[]);
    let name = recipe.file_stem().and_then(|s| s.to_str()).unwrap_or("recipe");
    let dir = crate::support::scratch(&format!("shipped-{name}"));
    let trace = dir.join("run.trace");
    let run = LiveRun::run_on(
        recipe,
        &sim.endpoint,
        &[("--trace", &trace), ("--output-dir", &dir)],
    );
    let started = Instant::now();
    loop {
        let text = std::fs::read_to_string(&trace).unwrap_or_default();
        if traced_writes(&text, SPEED_SETPOINT).iter().any(|(_, v)| *v != 0) {
            break;
        }
        if started.elapsed() > Duration::from_secs(30) {
            let (_, out) = run.finish();
            return Err(format!("{name}: no speed setpoint written in 30 s\n{out}"));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    // The spindle accelerates; the run's own steps are still going.
    std::thread::sleep(Duration::from_millis(200));
    run.signal("INT");
    let (code, out) = run.finish();
    let text = std::fs::read_to_string(&trace).map_err(|e| format!("{name}: trace: {e}"))?;
    if code != Some(130) {
        return Err(format!("{name}: exit code {code:?}, not 130\n{out}"));
    }
    let words = control_words(&text);
    let enabled = words
        .iter()
        .find(|(_, v)| *v == ENABLE_OPERATION)
        .map(|(i, _)| *i)
        .ok_or(format!("{name}: the drive was never enabled\n{out}"))?;
    let (disable, word) = *words
        .iter()
        .find(|(i, v)| *i > enabled && *v != ENABLE_OPERATION)
        .ok_or(format!("{name}: no disable telegram after the enable\n{out}"))?;
    let speeds = speed_replies(&text);
    let last = speeds
        .iter()
        .rev()
        .find(|(i, _)| *i > enabled && *i < disable)
        .map(|(_, v)| *v)
        .ok_or(format!(
            "{name}: no speed read between the enable and the first disable (control word {word})\n{out}"
        ))?;
    if last.abs() >= STANDSTILL {
        return Err(format!(
            "{name}: the first disable (control word {word}) was sent at {last} rpm\n{out}"
        ));
    }
    let turned = speeds.iter().any(|(i, v)| *i > enabled && v.abs() >= STANDSTILL);
    if !turned {
        return Err(format!("{name}: the spindle never turned before the stop\n{out}"));
    }
    if out.contains("STILL COASTING") {
        return Err(format!("{name}: still coasting at the end\n{out}"));
    }
    Ok(())
}

#[test]
fn ctrl_c_on_every_shipped_recipe_brakes_to_standstill_before_the_first_disable() {
    let recipes = shipped_recipes_that_enable();
    let names: Vec<String> = recipes
        .iter()
        .filter_map(|p| p.file_name().and_then(|n| n.to_str()).map(str::to_string))
        .collect();
    // Every shipped kind: recipes with their own finally, a script with its own, and the
    // default finally.
    for expected in [
        "commissioning.yaml",
        "spindle-run-in.yaml",
        "adaptive-run-in.rhai",
        "speed-sweep.rhai",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "{expected} not found in {names:?}"
        );
    }
    let runs: Vec<_> = recipes
        .into_iter()
        .map(|r| std::thread::spawn(move || ctrl_c_while_turning(&r)))
        .collect();
    let failures: Vec<String> = runs
        .into_iter()
        .filter_map(|h| h.join().unwrap_or_else(|_| Err("a run panicked".into())).err())
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn check_says_where_a_recipe_or_script_opts_out_of_braking() {
    let dir = std::env::temp_dir().join(format!("drivescript-brake-check-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let recipe = dir.join("coast.yaml");
    std::fs::write(
        &recipe,
        "name: Coast\nsafe_stop: { brake_to_standstill: false }\nsteps: [shutdown]\n",
    )
    .expect("recipe");
    let script = dir.join("coast.rhai");
    std::fs::write(
        &script,
        "//! drive: sd2\n//! safe_stop: brake_to_standstill=false\nlet d = drive();\nd.shutdown();\n",
    )
    .expect("script");
    let braking = dir.join("brake.yaml");
    std::fs::write(&braking, "name: Brake\nsteps: [shutdown]\n").expect("recipe");
    for (file, at) in [(&recipe, "coast.yaml:2:35"), (&script, "coast.rhai:2:36")] {
        let out = drivescript(&["check", &file.to_string_lossy()], "");
        let text = stdout(&out);
        assert_eq!(out.status.code(), Some(0), "{text}");
        assert!(
            text.contains("safe stop does not brake: brake_to_standstill is false at")
                && text.contains(at)
                && text.contains("disabled at speed and coasts"),
            "{text}"
        );
    }
    let text = stdout(&drivescript(&["check", &braking.to_string_lossy()], ""));
    assert!(text.starts_with("ok  "), "{text}");
    assert!(!text.contains("does not brake"), "{text}");
}

#[test]
fn run_help_says_the_safe_stop_brakes_before_any_disable() {
    let text = stdout(&drivescript(&["run", "--help"], ""));
    let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        flat.contains("gets the speed setpoint 0 and is waited for until it stands still")
            && flat.contains("before anything disables it, then `finally` runs"),
        "{text}"
    );
    assert!(flat.contains("brake_to_standstill: false"), "{text}");
}
