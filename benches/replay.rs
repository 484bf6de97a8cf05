//! Replay benchmark: a day-long capture replayed with `--replay` in virtual time, as a
//! ratio against its goal (DESIGN: benchmarks report ratios against a stated limit, never
//! a timed assertion in a test). Run with `cargo bench --bench replay`. It runs the
//! release binary as a user would:
//! - records the capture here: 24 h of an SD2 spindle sampled every second (and the fault
//!   watch's status polls), run with `--fast --trace` against the simulated drive;
//! - replays the same recipe against it with `--replay --fast`: the speed-up over real
//!   time (goal ≥ 5 000×) and the peak resident memory (goal < 30 MB, while the capture
//!   is far larger: it is streamed, never held whole), from `wait4`'s resource usage.

#[path = "support/child_cost.rs"]
mod child_cost;
#[path = "support/goal.rs"]
mod goal;

use child_cost::{measure_child, Cost};
use goal::verdict;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

const DAY: f64 = 24.0 * 3600.0;
const SPEED_UP_GOAL: f64 = 5_000.0;
const RSS_LIMIT_MB: f64 = 30.0;

fn main() -> ExitCode {
    goal::exit_of(measure())
}

fn measure() -> Result<(), String> {
    let dir = std::env::temp_dir().join(format!("drivescript-bench-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let result = day_replay(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn day_replay(dir: &Path) -> Result<(), String> {
    println!("replay: 24 h of speed_actual and current_actual sampled every second, recorded and replayed");
    let recipe = dir.join("day.yaml");
    std::fs::write(
        &recipe,
        "name: A day at 1 Hz\ndrive: sd2\nsteps:\n  - go_to: operation_enabled\n  - set: { speed_setpoint: 6000 rpm }\n  - sample: { objects: [speed_actual, current_actual], every: 1 s, for: 24 h }\n  - expect: { speed_actual: { near: 6000 rpm, within: 1 % } }\n",
    )
    .map_err(|e| e.to_string())?;
    let trace = dir.join("day.trace");
    let trace_arg = trace.to_string_lossy().to_string();
    let (_, recorded) = run(&recipe, &["--fast", "--trace", &trace_arg])?;
    let size_mb = std::fs::metadata(&trace).map_err(|e| e.to_string())?.len() as f64 / 1e6;
    let lines = BufReader::new(std::fs::File::open(&trace).map_err(|e| e.to_string())?)
        .lines()
        .count();
    println!(
        "  recorded     {:>7.1} s wall, capture {size_mb:.1} MB, {lines} lines",
        recorded.wall.as_secs_f64()
    );
    let (out, cost) = run(&recipe, &["--fast", "--replay", &trace_arg])?;
    if !out.contains("PASSED") {
        return Err(format!("the replay did not pass:\n{out}"));
    }
    let speed_up = DAY / cost.wall.as_secs_f64();
    println!(
        "  replayed     {:>7.1} s wall = {speed_up:>7.0}× real time ({:>5.1} % of goal {SPEED_UP_GOAL:.0}×)  {}",
        cost.wall.as_secs_f64(),
        speed_up / SPEED_UP_GOAL * 100.0,
        verdict(speed_up >= SPEED_UP_GOAL)
    );
    println!(
        "  replayed     CPU {:.1} s in user space, {:.1} s in the kernel (reading the capture)",
        cost.user.as_secs_f64(),
        cost.system.as_secs_f64()
    );
    let rss_mb = cost.peak_rss_kb as f64 / 1024.0;
    println!(
        "  replayed     peak RSS {rss_mb:>6.1} MB ({:>5.1} % of the {RSS_LIMIT_MB:.0} MB limit; {:.0} % of the capture's size)  {}",
        rss_mb / RSS_LIMIT_MB * 100.0,
        rss_mb / size_mb * 100.0,
        verdict(rss_mb < RSS_LIMIT_MB)
    );
    Ok(())
}

fn binary() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_drivescript"))
}

/// Runs `recipe` with `args`; its standard output and what it cost (from `wait4`).
fn run(recipe: &Path, args: &[&str]) -> Result<(String, Cost), String> {
    let mut command = Command::new(binary());
    command.arg("run").arg(recipe).args(args).arg("--no-progress");
    measure_child(command)
}
