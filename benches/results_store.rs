//! Results-store benchmark: what recording costs, each figure as a ratio against its goal.
//!
//! A measurement, not a test (DESIGN: benchmarks report ratios against a stated limit,
//! never a timed assertion). Run with `cargo bench --bench results_store`. It runs the
//! release binary as a user would, on SQLite in a scratch folder:
//! - 24 h of sampling two objects at 100 Hz with `--fast`, with `--no-results` and with
//!   `--results FILE` (interleaved, the least of three runs each, wall and CPU time): the
//!   run with the store at most 10 % slower, and the store grown by at most 2 MB (the file with its WAL);
//! - `drivescript results list` over a store of 10 000 runs (5 checks each): at most
//!   100 ms, the whole command (the median of five), as it lists by default (the newest
//!   50) and with all 10 000 rows printed;
//! - `drivescript results trend CHECK` over the same 10 000 runs, by a check's full name
//!   and by its key, and with its page (`--html`, the newest 2000 drawn): at most 200 ms;
//! - `drivescript results yield` and `results capability CHECK` (also with its
//!   histogram page) over the same 10 000 runs: at most 200 ms each;
//! - `drivescript results serve` answering its list page over the same 10 000 runs (the
//!   newest 50, as it opens, and all 10 000 rows): at most 100 ms from the request to
//!   the page's last byte (the median of 21 requests on loopback, server in this process);
//! - the lookup of a unit's last passed run for `compared_with_last_pass` over the same
//!   store (opening it and the query, as a run does before its first step): at most
//!   100 ms, against the 10 s a run waits at most.

// Only the wait for a child is needed here; the other benchmarks use the rest.
#[allow(dead_code)]
#[path = "support/child_cost.rs"]
mod child_cost;

use child_cost::wait_cost;
use drivescript::results::{CheckRow, EndRow, Locator, Record, RunRow, StoreHistory};
use drivescript::session::{History, Limits, UnitIdentity};
use drivescript::store_site::StoreSite;
use drivescript::web::WebSettings;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_drivescript")
}

fn verdict(ok: bool) -> &'static str {
    if ok {
        "ok"
    } else {
        "OVER THE GOAL"
    }
}

/// Runs the binary with `args` to a successful end; the wall time.
fn timed(args: &[&str]) -> Result<Duration, String> {
    costs(args).map(|(wall, _)| wall)
}

/// Runs the binary with `args` to a successful end; the wall time and the CPU time (user
/// and kernel, every thread) from `wait4`, which a machine busy with other work disturbs
/// less than the wall time.
fn costs(args: &[&str]) -> Result<(Duration, Duration), String> {
    let started = Instant::now();
    let child = Command::new(binary())
        .args(args)
        .env_remove("DRIVESCRIPT_RESULTS")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("cannot start drivescript: {e}"))?;
    let (code, cost) = wait_cost(child.id() as libc::pid_t, started)?;
    if code != Some(0) {
        return Err(format!("drivescript {args:?} failed"));
    }
    Ok((cost.wall, cost.user + cost.system))
}

fn size_of_store(path: &Path) -> u64 {
    let with = |suffix: &str| {
        let mut p = path.as_os_str().to_os_string();
        p.push(suffix);
        std::fs::metadata(PathBuf::from(p)).map_or(0, |m| m.len())
    };
    with("") + with("-wal")
}

fn long_run(dir: &Path) -> Result<(), String> {
    println!("long run: 24 h sampling speed_actual and current_actual every 10 ms, --fast");
    let recipe = dir.join("long.yaml");
    std::fs::write(
        &recipe,
        "name: A day at 100 Hz\nsteps:\n  - go_to: operation_enabled\n  - set: { speed_setpoint: 6000 rpm }\n  - sample: { objects: [speed_actual, current_actual], every: 10 ms, for: 24 h }\n  - expect:\n      speed_actual: { mean: { near: 6000 rpm, within: 1 % } }\n",
    )
    .map_err(|e| e.to_string())?;
    let recipe = recipe.to_string_lossy().to_string();
    let store = dir.join("long.sqlite");
    let store_arg = store.to_string_lossy().to_string();
    // One run first, so the store exists and the growth is the run's alone.
    timed(&["run", &recipe, "--fast", "--no-progress", "--results", &store_arg])?;
    let before = size_of_store(&store);
    let (mut without, mut with) = ((Duration::MAX, Duration::MAX), (Duration::MAX, Duration::MAX));
    // Interleaved, the least of three each: other work on the machine only adds time.
    for _ in 0..3 {
        let a = costs(&["run", &recipe, "--fast", "--no-progress", "--no-results"])?;
        let b = costs(&["run", &recipe, "--fast", "--no-progress", "--results", &store_arg])?;
        without = (without.0.min(a.0), without.1.min(a.1));
        with = (with.0.min(b.0), with.1.min(b.1));
    }
    let grown = size_of_store(&store).saturating_sub(before) / 3;
    for (what, a, b) in [("wall", without.0, with.0), ("CPU", without.1, with.1)] {
        let slower = b.as_secs_f64() / a.as_secs_f64() - 1.0;
        println!(
            "  {what:<4} without the store {:>6.2} s, with it {:>6.2} s: {:>+5.1} % ({:>5.1} % of the 10 % limit)  {}",
            a.as_secs_f64(),
            b.as_secs_f64(),
            slower * 100.0,
            slower.max(0.0) / 0.10 * 100.0,
            verdict(slower <= 0.10)
        );
    }
    let mb = grown as f64 / 1e6;
    println!(
        "  the store grew by {mb:>6.3} MB per run ({:>5.1} % of the 2 MB limit)  {}",
        mb / 2.0 * 100.0,
        verdict(mb <= 2.0)
    );
    Ok(())
}

/// A store of `runs` finished runs of 5 checks each, over 100 units.
fn filled_store(path: &Path, runs: usize) -> Result<(), String> {
    let mut store = Locator::Sqlite(path.to_path_buf())
        .open(true)
        .map_err(|e| e.to_string())?;
    let mut records = Vec::with_capacity(runs * 7);
    for i in 0..runs {
        let id = format!("{i:016x}");
        let started_at = format!(
            "2026-{:02}-{:02}T{:02}:{:02}:00.000Z",
            1 + i / 1000 % 12,
            1 + i / 40 % 28,
            i / 60 % 24,
            i % 60
        );
        records.push(Record::Started(RunRow {
            id: id.clone(),
            kind: "recipe".into(),
            recipe: "Acceptance test".into(),
            recipe_path: "recipes/acceptance-test.yaml".into(),
            tool_version: "0.1.0".into(),
            started_at: started_at.clone(),
            drive: "drive 2 on /dev/ttyUSB0".into(),
            unit: UnitIdentity {
                serial: Some(format!("SP-{}", 100_000 + i % 100)),
                station: Some("Bench 3".into()),
                ..UnitIdentity::default()
            },
            params: vec![("speed".into(), "12000 rpm".into())],
            ..RunRow::default()
        }));
        for c in 0..5 {
            records.push(Record::Check(CheckRow {
                run: id.clone(),
                seq: c + 1,
                name: format!("current_actual max below 5 A #{c}"),
                key: Some(format!("current_actual max below #{c}")),
                measured: Some(3.0 + (i % 17) as f64 * 0.05),
                unit: Some("A".into()),
                limits: Limits::new(None, Some(5.0)),
                passed: true,
                step: format!("{}", c + 3),
                attempt: 1,
                message: "ok".into(),
                inclusive: Some(false),
                ..CheckRow::default()
            }));
        }
        records.push(Record::Finished(EndRow {
            run: id,
            ended_at: started_at,
            verdict: "passed".into(),
            final_state: Some("ready to switch on".into()),
            stop_confirmed: true,
            ..EndRow::default()
        }));
    }
    for chunk in records.chunks(7_000) {
        store.apply_all(chunk).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn median_of_five(args: &[&str]) -> Result<Duration, String> {
    let mut times = (0..5).map(|_| timed(args)).collect::<Result<Vec<_>, _>>()?;
    times.sort();
    Ok(times[2])
}

fn queries(dir: &Path) -> Result<(), String> {
    let store = dir.join("fleet.sqlite");
    filled_store(&store, 10_000)?;
    let s = store.to_string_lossy().to_string();
    let page = dir.join("trend.html").to_string_lossy().to_string();
    let trend = ["results", "trend", "--results", s.as_str()];
    println!("\nqueries over 10 000 stored runs (SQLite, the whole command)");
    for (what, args, goal_ms) in [
        (
            "results list",
            vec!["results", "list", "--results", s.as_str()],
            100.0,
        ),
        (
            "list, all 10 000",
            vec!["results", "list", "--limit", "10000", "--results", s.as_str()],
            100.0,
        ),
        (
            "results trend",
            [&trend[..], &["current_actual max below 5 A #2"]].concat(),
            200.0,
        ),
        (
            "trend by key",
            [&trend[..], &["current_actual max below #2"]].concat(),
            200.0,
        ),
        (
            "trend --html",
            [&trend[..], &["current_actual max below #2", "--html", &page]].concat(),
            200.0,
        ),
        (
            "results yield",
            vec!["results", "yield", "--results", s.as_str()],
            200.0,
        ),
        (
            "capability",
            vec![
                "results",
                "capability",
                "current_actual max below #2",
                "--results",
                s.as_str(),
            ],
            200.0,
        ),
        (
            "capability --html",
            vec![
                "results",
                "capability",
                "current_actual max below #2",
                "--html",
                &page,
                "--results",
                s.as_str(),
            ],
            200.0,
        ),
    ] {
        let ms = median_of_five(&args)?.as_secs_f64() * 1000.0;
        println!(
            "  {what:<17} {ms:>7.1} ms ({:>5.1} % of the {goal_ms:.0} ms goal)  {}",
            ms / goal_ms * 100.0,
            verdict(ms <= goal_ms)
        );
    }
    served_list(&store)?;
    let history = StoreHistory::new(Locator::Sqlite(store.clone()), false);
    let mut times = Vec::new();
    for _ in 0..5 {
        let started = Instant::now();
        let found = history
            .look_up("Acceptance test", "SP-100042")
            .recv()
            .map_err(|e| e.to_string())?
            .map_err(|e| e.to_string())?;
        times.push(started.elapsed());
        if found.is_none_or(|r| r.checks.len() != 5) {
            return Err("the last pass of SP-100042 was not found with its 5 checks".into());
        }
    }
    times.sort();
    let (ms, goal_ms) = (times[2].as_secs_f64() * 1000.0, 100.0);
    println!(
        "  {:<17} {ms:>7.1} ms ({:>5.1} % of the {goal_ms:.0} ms goal)  {}",
        "last-pass lookup",
        ms / goal_ms * 100.0,
        verdict(ms <= goal_ms)
    );
    Ok(())
}

/// `results serve`'s list page over `store`: the median of 21 requests, whole answers.
fn served_list(store: &Path) -> Result<(), String> {
    use std::io::{Read, Write};
    let site = StoreSite::open(Locator::Sqlite(store.to_path_buf())).map_err(|e| e.to_string())?;
    let local = std::net::SocketAddr::from(([127, 0, 0, 1], 0));
    let settings = WebSettings::new(local, None).map_err(|e| e.to_string())?;
    let server = site.serve(settings).map_err(|e| e.to_string())?;
    let at = server.address();
    let get = |path: &str| -> Result<Duration, String> {
        let started = Instant::now();
        let mut s = std::net::TcpStream::connect(at).map_err(|e| e.to_string())?;
        write!(
            s,
            "GET {path} HTTP/1.1\r\nHost: {at}\r\nConnection: close\r\n\r\n"
        )
        .map_err(|e| e.to_string())?;
        let mut answer = Vec::new();
        s.read_to_end(&mut answer).map_err(|e| e.to_string())?;
        let took = started.elapsed();
        let rows = String::from_utf8_lossy(&answer).matches("<tr class=").count();
        if !answer.starts_with(b"HTTP/1.1 200") || rows == 0 {
            return Err(format!("results serve answered {path} without its runs"));
        }
        Ok(took)
    };
    for (what, path) in [("serve: list page", "/"), ("serve: all 10 000", "/?limit=10000")] {
        let mut times = (0..21).map(|_| get(path)).collect::<Result<Vec<_>, _>>()?;
        times.sort();
        let (ms, goal_ms) = (times[10].as_secs_f64() * 1000.0, 100.0);
        println!(
            "  {what:<17} {ms:>7.1} ms ({:>5.1} % of the {goal_ms:.0} ms goal)  {}",
            ms / goal_ms * 100.0,
            verdict(ms <= goal_ms)
        );
    }
    server.shutdown();
    Ok(())
}

fn main() -> ExitCode {
    let dir = std::env::temp_dir().join(format!("drivescript-bench-results-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    let result = long_run(&dir).and_then(|()| queries(&dir));
    let _ = std::fs::remove_dir_all(&dir);
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
