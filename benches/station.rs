//! Operator station benchmark: what a page watching a long run costs.
//!
//! A measurement, not a test (DESIGN: benchmarks print ratios against a stated limit).
//! Run with `cargo bench --bench station`. A one-hour run in virtual time (`--fast`)
//! sampling two objects at 100 Hz, started twice with the release binary as a user would:
//! - by `drivescript run` (no page);
//! - by `drivescript station`, with a page connected to its event stream from before the
//!   start to the result (a client reading the server-sent events as a browser does).
//!
//! Goal: the station's CPU time (user + system, from `wait4`, the whole process from its
//! start to its exit) at most 5 % above the plain run's. Also measured the same way: the
//! recipe sampling for one second instead of an hour, the fixed part of each (start-up,
//! the web server, the report), so the printout tells what the page costs per sample row
//! apart from what the station costs to start. Also printed: the bytes the page
//! received and the size of the whole view a page gets on connecting at the end of the
//! run — the page's memory bound, which holds however long the run (at most 1000 points
//! per series for at most 8 series, and the last 200 steps).

#[path = "support/child_cost.rs"]
mod child_cost;

use child_cost::{measure_child, wait_cost, Cost};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, ExitCode, Stdio};
use std::time::Instant;

const LIMIT: f64 = 1.05;
/// Rounds of one plain run and one station run each, in turn (others share the machine:
/// a median over pairs taken side by side holds up where single runs do not).
const ROUNDS: usize = 9;

/// The recipe, sampling for `length` (`1 h`; `1 s` for the fixed part).
fn recipe(length: &str) -> String {
    format!(
        "name: {length} at 100 Hz
drive: sd2
steps:
  - go_to: operation_enabled
  - set: {{ speed_setpoint: 6000 rpm }}
  - sample: {{ objects: [speed_actual, current_actual], every: 10 ms, for: {length} }}
"
    )
}

fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_drivescript")
}

fn cpu(c: &Cost) -> f64 {
    (c.user + c.system).as_secs_f64()
}

/// One HTTP/1.1 request on a fresh connection; the whole answer.
fn http(address: &str, request: &str) -> Result<String, String> {
    let mut s = TcpStream::connect(address).map_err(|e| format!("{address}: {e}"))?;
    s.write_all(request.as_bytes()).map_err(|e| e.to_string())?;
    let mut answer = String::new();
    s.read_to_string(&mut answer).map_err(|e| e.to_string())?;
    Ok(answer)
}

/// What a page that connects now gets first: the whole view (its size in bytes).
fn view_size(address: &str) -> Result<usize, String> {
    let mut s = TcpStream::connect(address).map_err(|e| e.to_string())?;
    s.write_all(format!("GET /events HTTP/1.1\r\nHost: {address}\r\n\r\n").as_bytes())
        .map_err(|e| e.to_string())?;
    let mut reader = BufReader::new(s);
    let mut line = String::new();
    loop {
        line.clear();
        if reader.read_line(&mut line).map_err(|e| e.to_string())? == 0 {
            return Err("the event stream ended before the view".into());
        }
        if let Some(data) = line.strip_prefix("data: ") {
            return Ok(data.len());
        }
    }
}

/// The station runs the recipe once with a page connected; what the process cost, the
/// bytes the page received, and the size of the view a page gets at the end.
fn station_run(recipe: &std::path::Path, dir: &std::path::Path) -> Result<(Cost, usize, usize), String> {
    let started = Instant::now();
    let mut child = Command::new(binary())
        .arg("station")
        .arg(recipe)
        .args(["--fast", "--no-results", "--listen", "127.0.0.1:0"])
        // Each station run writes its HTML report (the result screen links to it).
        .arg("--output-dir")
        .arg(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| e.to_string())?;
    let mut out = BufReader::new(child.stdout.take().ok_or("no output")?);
    let mut line = String::new();
    let address = loop {
        line.clear();
        if out.read_line(&mut line).map_err(|e| e.to_string())? == 0 {
            return Err("the station ended before it listened".into());
        }
        if let Some(url) = line.split_whitespace().find(|w| w.starts_with("http://")) {
            break url
                .trim_start_matches("http://")
                .trim_end_matches('/')
                .to_string();
        }
    };
    // The rest of the output (the run's console) is read as a terminal would.
    let drain = std::thread::spawn(move || {
        let mut rest = Vec::new();
        let _ = out.read_to_end(&mut rest);
    });
    let page = http(
        &address,
        &format!("GET / HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\n\r\n"),
    )?;
    let token = page
        .split("name=\"drivescript-token\" content=\"")
        .nth(1)
        .and_then(|t| t.split('"').next())
        .ok_or("no token in the page")?
        .to_string();
    // The page: connected before the start, reading every event until the result.
    let mut events = TcpStream::connect(&address).map_err(|e| e.to_string())?;
    events
        .write_all(format!("GET /events HTTP/1.1\r\nHost: {address}\r\n\r\n").as_bytes())
        .map_err(|e| e.to_string())?;
    let reader = std::thread::spawn(move || {
        let mut reader = BufReader::new(events);
        let mut line = String::new();
        let mut bytes = 0;
        loop {
            line.clear();
            match reader.read_line(&mut line) {
                Ok(0) | Err(_) => return bytes,
                Ok(n) => bytes += n,
            }
            if line.starts_with("data: {\"kind\":\"result\"") {
                return bytes;
            }
        }
    });
    let body = r#"{"recipe":0,"serial":"BENCH-1","operator":"bench"}"#;
    let started_run = http(
        &address,
        &format!(
            "POST /api/start HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\nx-drivescript-token: {token}\r\nContent-Length: {}\r\n\r\n{body}",
            body.len()
        ),
    )?;
    if !started_run.starts_with("HTTP/1.1 200") {
        return Err(format!("the start was refused: {started_run}"));
    }
    let received = reader.join().map_err(|_| "the page's reader failed")?;
    let view = view_size(&address)?;
    // SAFETY: a signal to our own child.
    unsafe {
        libc::kill(child.id() as libc::pid_t, libc::SIGTERM);
    }
    let _ = drain.join();
    let (code, cost) = wait_cost(child.id() as libc::pid_t, started)?;
    if code != Some(143) {
        return Err(format!("the station ended with {code:?}, not 143 after SIGTERM"));
    }
    Ok((cost, received, view))
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// The plain run's CPU seconds (and its wall time).
fn plain_run(recipe: &std::path::Path, dir: &std::path::Path) -> Result<(f64, f64), String> {
    let mut command = Command::new(binary());
    command
        .arg("run")
        .arg(recipe)
        .args(["--fast", "--no-results", "--no-progress"])
        // The same report the station writes, so only the page makes the difference.
        .args(["--report", "plain.html", "--output-dir"])
        .arg(dir);
    let (_, cost) = measure_child(command)?;
    Ok((cpu(&cost), cost.wall.as_secs_f64()))
}

fn main() -> ExitCode {
    let dir = std::env::temp_dir().join(format!("drivescript-bench-station-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let (hour, second) = (dir.join("hour.yaml"), dir.join("second.yaml"));
    for (path, length) in [(&hour, "1 h"), (&second, "1 s")] {
        if let Err(e) = std::fs::write(path, recipe(length)) {
            eprintln!("cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
    }
    let mut plain = Vec::new();
    let mut paged = Vec::new();
    let mut fixed = (Vec::new(), Vec::new());
    let mut wall = (0.0, 0.0);
    let mut last = (0, 0, 0);
    for _ in 0..ROUNDS {
        match plain_run(&hour, &dir).and_then(|h| Ok((h, plain_run(&second, &dir)?))) {
            Ok(((cpu, w), (short, _))) => {
                plain.push(cpu);
                fixed.0.push(short);
                wall.0 = w;
            }
            Err(e) => {
                eprintln!("the plain run failed: {e}");
                return ExitCode::FAILURE;
            }
        }
        match station_run(&hour, &dir).and_then(|h| Ok((h, station_run(&second, &dir)?))) {
            Ok(((cost, received, view), (short, _, _))) => {
                paged.push(cpu(&cost));
                fixed.1.push(cpu(&short));
                wall.1 = cost.wall.as_secs_f64();
                last = (received, view, cost.peak_rss_kb);
            }
            Err(e) => {
                eprintln!("the station's run failed: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    let pairs: Vec<String> = plain
        .iter()
        .zip(&paged)
        .map(|(a, b)| format!("{:.3}", b / a))
        .collect();
    let (a, b) = (median(plain), median(paged));
    let (fa, fb) = (median(fixed.0), median(fixed.1));
    let ratio = b / a;
    println!("station: 1 h at 100 Hz, two objects, --fast, median of {ROUNDS}");
    println!(
        "  run without a page      {a:8.3} s CPU ({:.2} s wall, last round)",
        wall.0
    );
    println!(
        "  station, page connected {b:8.3} s CPU ({:.2} s wall, last round, from start to exit)",
        wall.1
    );
    println!("  each round's ratio: {}", pairs.join(" "));
    println!(
        "  ratio {:.3} (limit {LIMIT:.2}): {}",
        ratio,
        if ratio <= LIMIT { "ok" } else { "OVER" }
    );
    println!(
        "  fixed part (the recipe for 1 s): run {fa:.3} s, station {fb:.3} s CPU; the hour's rows alone: ratio {:.3}",
        (b - fb) / (a - fa)
    );
    println!(
        "  the page received {} kB; the whole view at the end is {} kB (bounded: 8 series × 1000 points, 200 steps); station peak RSS {} MB",
        last.0 / 1024,
        last.1 / 1024,
        last.2 / 1024
    );
    ExitCode::SUCCESS
}
