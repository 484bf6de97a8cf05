//! Link benchmark: SD2 round trips per second at 57600 bit/s, as a ratio of the physical limit.
//!
//! A measurement, not a test (DESIGN: "Benchmarks report ratios against a stated physical
//! limit, never a timed assertion in a test"). Run with `cargo bench --bench link_round_trips`.
//!
//! The limit of one round trip is the time both telegrams occupy an 8N1 line plus the
//! drive's reply latency: `(request + reply bytes) × 10 bit / 57600 bit/s + 250 µs`. The
//! simulated drive is set to answer after exactly those 250 µs (the manual's worst case),
//! so the limit and the simulated drive agree and the ratio shows only what the link, the
//! transport and the clock lose. Telegram sizes are taken from the bytes the link actually
//! sent and received, not assumed.
//!
//! Two paths, each with every telegram kind:
//! - in-process: `Sd2Link` → `MemoryTransport` (wire-time emulation) → `Sd2Simulator`;
//! - pseudo-terminal: `Sd2Link` → `SerialTransport` on a pty → `SimServer` (wire-time
//!   emulation) in a thread → `Sd2Simulator`. This adds the operating system's pty latency.
//!
//! Prints `PASS` for a path when every ratio is at least 90 %, else `BELOW TARGET`; exits
//! non-zero only when the link reports an error.

use drivescript::bus::{MemoryTransport, Peer, SharedTransport, WireTime};
use drivescript::clock::{RealClock, SharedClock};
use drivescript::drive::AccessError;
use drivescript::family::sd2::codec::Cyclic;
use drivescript::family::sd2::LinkConfig;
use drivescript::family::sd2::Sd2Link;
use drivescript::family::sd2::{Sd2Simulator, SimConfig};
use drivescript::link::{CoreLink, Direction, TelegramObserver};
use drivescript::sim::SimulatedDrive;
use std::hint::black_box;
use std::process::ExitCode;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Line rate of the benchmark, 8N1.
const BAUD: u32 = 57_600;
/// Bits per character on an 8N1 line: start, 8 data, stop.
const BITS_PER_BYTE: f64 = 10.0;
/// The drive's reply latency: the manual's worst case, used both for the limit and the simulator.
const DRIVE_LATENCY: Duration = Duration::from_micros(250);
/// Timed round trips per telegram kind and path (about 1.5 s each at 57600 bit/s).
const ROUND_TRIPS: u32 = 400;
/// Untimed round trips before each measurement.
const WARM_UP: u32 = 5;
/// Share of the theoretical rate a path must reach.
const TARGET: f64 = 0.90;
/// DNC address of the simulated drive.
const DRIVE: u8 = 2;

/// What ends a measurement: the link's own error, boxed because it is large.
type Failure = Box<AccessError>;

const STATUS_WORD: u16 = 67;
const SPEED_SETPOINT: u16 = 395;
const ACTUAL_SPEED: u16 = 398;

#[derive(Debug, Clone, Copy)]
enum Kind {
    ReadStatusWord,
    ReadActualSpeed,
    WriteSpeedSetpoint,
    Cyclic,
}

const KINDS: [Kind; 4] = [
    Kind::ReadStatusWord,
    Kind::ReadActualSpeed,
    Kind::WriteSpeedSetpoint,
    Kind::Cyclic,
];

impl Kind {
    fn label(self) -> &'static str {
        match self {
            Kind::ReadStatusWord => "read status word (67)",
            Kind::ReadActualSpeed => "read actual speed (398)",
            Kind::WriteSpeedSetpoint => "write speed setpoint (395)",
            Kind::Cyclic => "cyclic telegram",
        }
    }

    /// One round trip; `i` varies the values written so no two requests need be alike.
    fn round_trip(self, link: &mut Sd2Link, i: u32) -> Result<(), Failure> {
        match self {
            Kind::ReadStatusWord => {
                black_box(link.read_object(DRIVE, STATUS_WORD, 0)?);
            }
            Kind::ReadActualSpeed => {
                black_box(link.read_object(DRIVE, ACTUAL_SPEED, 0)?);
            }
            Kind::WriteSpeedSetpoint => {
                // 0..=999 rpm in milli-rpm, well inside the drive's range.
                let milli_rpm = i32::try_from(i % 1000).unwrap_or(0) * 1000;
                link.write_object(DRIVE, SPEED_SETPOINT, 0, black_box(&milli_rpm.to_le_bytes()))?;
            }
            Kind::Cyclic => {
                // Control word 0 keeps the drive in switch on disabled; the heartbeat toggles.
                let request = Cyclic::request(0, 0, i % 2 == 1);
                black_box(link.cyclic(DRIVE, black_box(request))?);
            }
        }
        Ok(())
    }
}

/// Sizes of the telegrams that crossed the line, summed per direction.
#[derive(Debug, Default, Clone, Copy)]
struct Traffic {
    sent: u64,
    sent_telegrams: u64,
    sent_min: usize,
    sent_max: usize,
    received: u64,
    received_telegrams: u64,
    received_min: usize,
    received_max: usize,
}

impl Traffic {
    fn record(&mut self, direction: Direction, n: usize) {
        let (total, count, min, max) = match direction {
            Direction::Sent => (
                &mut self.sent,
                &mut self.sent_telegrams,
                &mut self.sent_min,
                &mut self.sent_max,
            ),
            Direction::Received => (
                &mut self.received,
                &mut self.received_telegrams,
                &mut self.received_min,
                &mut self.received_max,
            ),
        };
        *min = if *count == 0 { n } else { (*min).min(n) };
        *max = (*max).max(n);
        *total += n as u64;
        *count += 1;
    }

    /// Mean bytes per round trip, both directions.
    fn bytes_per_round_trip(&self) -> f64 {
        mean(self.sent, self.sent_telegrams) + mean(self.received, self.received_telegrams)
    }
}

fn mean(total: u64, count: u64) -> f64 {
    if count == 0 {
        0.0
    } else {
        total as f64 / count as f64
    }
}

/// `12`, or `12–14` when sizes varied.
fn size_range(min: usize, max: usize) -> String {
    if min == max {
        min.to_string()
    } else {
        format!("{min}–{max}")
    }
}

/// Counts the bytes of every telegram the link sends and receives.
struct TrafficObserver(Arc<Mutex<Traffic>>);

impl TelegramObserver for TrafficObserver {
    fn telegram(&mut self, _: Duration, direction: Direction, bytes: &[u8]) {
        if let Ok(mut t) = self.0.lock() {
            t.record(direction, bytes.len());
        }
    }

    fn event(&mut self, _: Duration, _: &str) {}
}

/// One row of the table.
struct Row {
    kind: Kind,
    traffic: Traffic,
    elapsed: Duration,
    /// Median and longest single round trip.
    median: Duration,
    longest: Duration,
    retries: u64,
    timeouts: u64,
    corrupt_or_mismatched: u64,
}

impl Row {
    /// `(req + reply) × 10 / baud + 250 µs`, in seconds.
    fn theoretical_seconds(&self) -> f64 {
        self.traffic.bytes_per_round_trip() * BITS_PER_BYTE / f64::from(BAUD) + DRIVE_LATENCY.as_secs_f64()
    }

    fn measured_seconds(&self) -> f64 {
        self.elapsed.as_secs_f64() / f64::from(ROUND_TRIPS)
    }

    fn ratio(&self) -> f64 {
        self.theoretical_seconds() / self.measured_seconds()
    }

    fn clean(&self) -> bool {
        self.retries == 0 && self.timeouts == 0 && self.corrupt_or_mismatched == 0
    }
}

/// Measures every telegram kind over `link`.
fn measure(link: &mut Sd2Link, clock: &SharedClock) -> Result<Vec<Row>, Failure> {
    let mut rows = Vec::new();
    for kind in KINDS {
        for i in 0..WARM_UP {
            kind.round_trip(link, i)?;
        }
        let traffic = Arc::new(Mutex::new(Traffic::default()));
        link.set_observer(Box::new(TrafficObserver(traffic.clone())));
        let mut each = Vec::with_capacity(ROUND_TRIPS as usize);
        let before = link.stats();
        let start = clock.now();
        let mut last = start;
        for i in 0..ROUND_TRIPS {
            kind.round_trip(link, i)?;
            let now = clock.now();
            each.push(now.saturating_sub(last));
            last = now;
        }
        let elapsed = last.saturating_sub(start);
        let after = link.stats();
        link.take_observer();
        let traffic = *traffic.lock().expect("traffic counter poisoned");
        each.sort_unstable();
        let median = each.get(each.len() / 2).copied().unwrap_or_default();
        let longest = each.last().copied().unwrap_or_default();
        rows.push(Row {
            kind,
            traffic,
            elapsed,
            median,
            longest,
            retries: after.retries - before.retries,
            timeouts: after.timeouts - before.timeouts,
            corrupt_or_mismatched: (after.corrupt_replies + after.mismatched_replies)
                - (before.corrupt_replies + before.mismatched_replies),
        });
    }
    Ok(rows)
}

fn simulator() -> Sd2Simulator {
    let mut sim = Sd2Simulator::new(SimConfig {
        address: DRIVE,
        response_latency: DRIVE_LATENCY,
        ..SimConfig::default()
    });
    // Thousands of telegrams nobody inspects.
    sim.set_logging(false);
    sim
}

/// Path a: link → memory transport with wire time → simulator, all in this thread.
fn in_process() -> Result<Vec<Row>, Failure> {
    let clock = RealClock::shared();
    let peer: Arc<Mutex<dyn Peer>> = Arc::new(Mutex::new(simulator()));
    let transport = MemoryTransport::new("in-process simulator", peer, clock.clone())
        .with_wire_time(WireTime::new_8n1(BAUD));
    let mut link = Sd2Link::new(
        SharedTransport::new(Box::new(transport)),
        clock.clone(),
        LinkConfig::default(),
    );
    measure(&mut link, &clock)
}

/// Path b: link → serial port on a pseudo-terminal → `SimServer` with wire time in a thread.
#[cfg(unix)]
fn through_pty() -> Result<Vec<Row>, Failure> {
    use drivescript::bus::{SerialSettings, SerialTransport, TransportError};
    use drivescript::sim_server::{PtyEndpoint, SimServer};
    use std::sync::atomic::Ordering;

    fn port_failure(e: TransportError) -> Failure {
        Box::new(AccessError::from(e))
    }

    let clock = RealClock::shared();
    let pty = PtyEndpoint::open().map_err(port_failure)?;
    let path = pty.path.clone();
    // Only the master moves to the server thread; `pty` keeps the slave open meanwhile.
    let mut master = pty.master;
    let peer: Arc<Mutex<dyn Peer>> = Arc::new(Mutex::new(simulator()));
    let server = SimServer::new(peer, clock.clone()).with_wire_time(WireTime::new_8n1(BAUD));
    let stop = server.stop_flag();
    let handle = std::thread::spawn(move || server.serve(&mut master));

    let measured = SerialTransport::open(&path, SerialSettings::with_baud(BAUD))
        .map_err(port_failure)
        .and_then(|port| {
            let mut link = Sd2Link::new(
                SharedTransport::new(Box::new(port)),
                clock.clone(),
                LinkConfig::default(),
            );
            measure(&mut link, &clock)
        });

    stop.store(true, Ordering::SeqCst);
    let served = handle.join().expect("the simulator server thread panicked");
    let rows = measured?;
    served.map_err(port_failure)?;
    Ok(rows)
}

fn print_table(title: &str, rows: &[Row]) {
    println!();
    println!("{title}");
    println!(
        "{:<27} {:>5} {:>5} {:>8} {:>8} {:>8} {:>8} {:>7} {:>7} {:>7} {:>7} {:>7} {:>8}",
        "kind",
        "req B",
        "rep B",
        "limit µs",
        "limit/s",
        "mean µs",
        "meas./s",
        "ratio",
        "over µs",
        "p50 µs",
        "max µs",
        "retries",
        "timeouts"
    );
    for r in rows {
        let limit = r.theoretical_seconds();
        let measured = r.measured_seconds();
        let bad = if r.corrupt_or_mismatched > 0 {
            format!("  ({} corrupt or mismatched replies)", r.corrupt_or_mismatched)
        } else {
            String::new()
        };
        println!(
            "{:<27} {:>5} {:>5} {:>8.1} {:>8.1} {:>8.1} {:>8.1} {:>6.1}% {:>7.1} {:>7} {:>7} {:>7} {:>8}{bad}",
            r.kind.label(),
            size_range(r.traffic.sent_min, r.traffic.sent_max),
            size_range(r.traffic.received_min, r.traffic.received_max),
            limit * 1e6,
            1.0 / limit,
            measured * 1e6,
            1.0 / measured,
            r.ratio() * 100.0,
            (measured - limit) * 1e6,
            r.median.as_micros(),
            r.longest.as_micros(),
            r.retries,
            r.timeouts,
        );
    }
}

fn verdict(path: &str, rows: &[Row]) {
    let worst = rows.iter().map(Row::ratio).fold(f64::INFINITY, f64::min);
    let word = if rows.iter().all(|r| r.ratio() >= TARGET) {
        "PASS"
    } else {
        "BELOW TARGET"
    };
    println!(
        "{path}: {word} (lowest ratio {:.1} %, target {:.0} %)",
        worst * 100.0,
        TARGET * 100.0
    );
    if !rows.iter().all(Row::clean) {
        println!("{path}: WARNING the link retried or refused replies; the measurement is not clean");
    }
}

/// One path's measurement.
struct Measured {
    name: &'static str,
    title: &'static str,
    result: Result<Vec<Row>, Failure>,
}

fn main() -> ExitCode {
    println!(
        "SD2 link round trips at {BAUD} bit/s 8N1, {ROUND_TRIPS} timed per kind (after {WARM_UP} untimed)"
    );
    println!(
        "limit per round trip = (request + reply bytes) × 10 bit / {BAUD} bit/s + {} µs drive latency",
        DRIVE_LATENCY.as_micros()
    );
    println!(
        "simulator response_latency = {} µs, the manual's worst case, so limit and simulated drive agree",
        DRIVE_LATENCY.as_micros()
    );
    println!("ratio = limit / mean round trip; over = mean − limit; p50, max = median, longest round trip");

    let mut paths = vec![Measured {
        name: "in-process",
        title: "a) in-process: Sd2Link → MemoryTransport (wire time) → simulator",
        result: in_process(),
    }];
    #[cfg(unix)]
    paths.push(Measured {
        name: "pseudo-terminal",
        title: "b) end to end: Sd2Link → SerialTransport on a pty → SimServer (wire time) → simulator \
                (includes the OS pty latency)",
        result: through_pty(),
    });

    let mut failed = false;
    for p in &paths {
        match &p.result {
            Ok(rows) => print_table(p.title, rows),
            Err(e) => {
                println!();
                println!("{}", p.title);
                eprintln!("{}: link error: {e}", p.name);
                failed = true;
            }
        }
    }
    println!();
    for p in &paths {
        match &p.result {
            Ok(rows) => verdict(p.name, rows),
            Err(_) => println!("{}: ERROR (see above)", p.name),
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
