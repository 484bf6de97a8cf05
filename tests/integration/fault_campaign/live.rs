//! The campaign's stop signals sent to the real binary (the in-process campaign schedules
//! them on the run's stop requests; only a process shows that the signal handlers lead
//! there): per family one seeded scenario on the built-in simulated drive in real time, a
//! signal while the drive turns and, for some, a second one inside the safe stop; held to
//! the campaign's invariants on exit code, console, JUnit, HTML, the store and the time
//! the stop takes. `DRIVESCRIPT_CAMPAIGN_LIVE=N` runs N of them (default: one per family).

use super::judge::{self, Ended};
use super::recipe_gen::Rng;
use super::target::{target_of, TARGETS};
use super::{replay_command, stored_verdict, STOP_TIMEOUT};
use crate::live_run::LiveRun;
use crate::support::{scratch, write_file};
use drivescript::stop_request::StopSignal;
use std::time::{Duration, Instant};

/// Seeds of the live scenarios start here, apart from the in-process ones.
const FIRST_LIVE_SEED: u64 = 1_000_000;

fn live_recipe(seed: u64) -> (String, &'static str) {
    let target = target_of(seed);
    let name = format!("campaign live seed {seed} ({})", target.name);
    let body = if target.controlled {
        let rpm = 60 * (10 + (seed / 8) % 10);
        format!(
            "  - set: {{ speed_setpoint: 0 rpm }}\n  - go_to: {{ state: operation_enabled, timeout: 2 s }}\n  - set: {{ speed_setpoint: {rpm} rpm }}\n  - wait_until: {{ speed_actual: {{ near: {rpm} rpm, within: 1 % }}, timeout: 15 s }}\n  - dwell: 1 h\n"
        )
    } else {
        format!("  - read: [{}]\n  - dwell: 1 h\n", target.reads[0])
    };
    let waits_for = if target.controlled {
        "wait until speed_actual"
    } else {
        "read "
    };
    (
        format!("name: {name}\n{}steps:\n{body}", target.header),
        waits_for,
    )
}

/// One live scenario: what broke, if anything.
fn live(seed: u64) -> Vec<String> {
    let mut rng = Rng::new(seed);
    let dir = scratch(&format!("live-{seed}"));
    let (yaml, waits_for) = live_recipe(seed);
    let recipe = write_file(&dir, "recipe.yaml", &yaml);
    let (junit, html, store) = (
        dir.join("junit.xml"),
        dir.join("report.html"),
        dir.join("results.sqlite"),
    );
    let args: Vec<std::ffi::OsString> = vec![
        "run".into(),
        recipe.into(),
        "--no-progress".into(),
        "--stop-timeout".into(),
        format!("{}s", STOP_TIMEOUT.as_secs()).into(),
        "--junit".into(),
        junit.clone().into(),
        "--report".into(),
        html.clone().into(),
        "--results".into(),
        store.clone().into(),
    ];
    let mut run = LiveRun::start(args);
    run.wait_for(waits_for);
    std::thread::sleep(Duration::from_millis(rng.below(400)));
    let first = rng.pick(&StopSignal::ALL);
    run.signal(&first.name[3..]);
    let signalled = Instant::now();
    if rng.chance(50) {
        // Inside the safe stop, which brakes the spindle for up to a second.
        std::thread::sleep(Duration::from_millis(20 + rng.below(600)));
        run.signal(&rng.pick(&StopSignal::ALL).name[3..]);
    }
    let (code, console) = run.finish();
    let took = signalled.elapsed();
    let exit = code.unwrap_or(-1);
    let mut problems = Vec::new();
    // The verdict rule: a spindle left coasting (a second signal switches the power stage
    // off at once, mid-brake) is exit code 3 whatever ended the run.
    let expected = match console.contains("STILL COASTING") {
        true => 3,
        false => first.exit_code(),
    };
    if exit != expected {
        problems.push(format!("exit {exit} after {} (expected {expected})", first.name));
    }
    let name = yaml
        .lines()
        .next()
        .and_then(|l| l.strip_prefix("name: "))
        .unwrap_or("");
    problems.extend(judge::problems(&Ended {
        exit,
        report: None,
        console: &console,
        junit: std::fs::read_to_string(&junit).ok(),
        html: std::fs::read_to_string(&html).ok(),
        stored: stored_verdict(&store, name),
        state: None,
        speed_rpm: 0.0,
        changes: Vec::new(),
        stop_start: Duration::ZERO,
        end: took,
        stop_bound: STOP_TIMEOUT + Duration::from_secs(10),
    }));
    if !problems.is_empty() {
        problems.push(format!(
            "replay: DRIVESCRIPT_CAMPAIGN_LIVE_SEED={seed} cargo test --test integration fault_campaign_live -- --nocapture (in-process: {})\n--- recipe ---\n{yaml}--- console ---\n{console}",
            replay_command(seed)
        ));
    }
    problems
}

#[cfg(unix)]
#[test]
fn fault_campaign_live_signals_to_the_real_binary() {
    let seeds: Vec<u64> = match std::env::var("DRIVESCRIPT_CAMPAIGN_LIVE_SEED") {
        Ok(s) => s.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
        Err(_) => {
            let n = std::env::var("DRIVESCRIPT_CAMPAIGN_LIVE")
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(TARGETS.len() as u64);
            (FIRST_LIVE_SEED..FIRST_LIVE_SEED + n).collect()
        }
    };
    let failures: Vec<String> = seeds
        .iter()
        .filter_map(|&seed| {
            let p = live(seed);
            (!p.is_empty())
                .then(|| format!("== live seed {seed} ({})\n{}", target_of(seed).name, p.join("\n")))
        })
        .collect();
    eprintln!(
        "fault campaign, live: {} scenario(s), {} failed",
        seeds.len(),
        failures.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
