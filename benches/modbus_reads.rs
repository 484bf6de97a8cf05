//! Modbus RTU benchmark: register reads per second through a pseudo-terminal at 19 200 and
//! 115 200 bit/s, as a ratio of the line's limit including the inter-frame silence.
//!
//! A measurement, not a test (DESIGN: benchmarks report ratios against a stated physical
//! limit). Run with `cargo bench --bench modbus_reads`.
//!
//! Path: `ModbusLink` → `SerialTransport` on a pty (8E1) → `SimServer` with wire-time
//! emulation at 11 bits a character in a thread → `ModbusSimulator`. One read is a read
//! holding registers request of one register (8 bytes) and its reply (7 bytes). The limit
//! of one read: both frames on the wire, the slave's silence before it may answer (it sees
//! the request's end only after 3.5 characters), and the master's silence before its next
//! request (Serial Line V1.02, 2.5.1.1: 3.5 characters, fixed at 1.75 ms above 19 200
//! bit/s):
//!   limit = (8 + 7) × 11 bit / baud + 2 × t3.5
//! The simulator answers after exactly t3.5, so limit and simulated slave agree and the
//! ratio shows what the link, the pty and the clock lose. Frame sizes are taken from the
//! bytes the link sent and received, not assumed.
//!
//! Each read is timed from its request to the end of the silence after its reply. The mean
//! and the median are both printed with the longest read; the verdict is on the median,
//! because on a shared machine a few reads stall for the scheduler (the longest shows
//! them), which says nothing about the link. Prints `PASS` per rate when the median ratio
//! is at least 95 %, else `BELOW TARGET`; exits non-zero only when the link reports an
//! error.

use drivescript::bus::{Peer, SerialSettings, SerialTransport, SharedTransport, WireTime};
use drivescript::clock::{RealClock, SharedClock};
use drivescript::family::modbus::codec::{rtu, Function, Request};
use drivescript::family::modbus::{Framing, LinkConfig, ModbusLink, ModbusSimulator};
use drivescript::link::{CoreLink, Direction, TelegramObserver};
use drivescript::sim::SimConfig;
use drivescript::sim_server::{PtyEndpoint, SimServer};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::Duration;

const BITS_PER_CHAR: u32 = 11;
const READS: u32 = 400;
const WARM_UP: u32 = 5;
const TARGET: f64 = 0.95;
const SLAVE: u8 = 1;

#[derive(Default)]
struct Sizes {
    sent: u64,
    received: u64,
    frames_sent: u64,
    frames_received: u64,
}

struct Count(Arc<Mutex<Sizes>>);

impl TelegramObserver for Count {
    fn telegram(&mut self, _: Duration, direction: Direction, bytes: &[u8]) {
        let mut s = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        match direction {
            Direction::Sent => {
                s.sent += bytes.len() as u64;
                s.frames_sent += 1;
            }
            Direction::Received => {
                s.received += bytes.len() as u64;
                s.frames_received += 1;
            }
        }
    }
    fn event(&mut self, _: Duration, _: &str) {}
}

struct Row {
    baud: u32,
    request: f64,
    reply: f64,
    silence: Duration,
    /// Mean seconds per read.
    measured: f64,
    /// Median and longest seconds per read.
    median: f64,
    longest: f64,
}

impl Row {
    fn limit(&self) -> f64 {
        (self.request + self.reply) * f64::from(BITS_PER_CHAR) / f64::from(self.baud)
            + 2.0 * self.silence.as_secs_f64()
    }
    fn ratio(&self) -> f64 {
        self.limit() / self.measured
    }
    fn median_ratio(&self) -> f64 {
        self.limit() / self.median
    }
}

fn measure(baud: u32) -> Result<Row, String> {
    let clock: SharedClock = RealClock::shared();
    let silence = rtu::frame_silence(baud, BITS_PER_CHAR);
    let pty = PtyEndpoint::open().map_err(|e| e.to_string())?;
    let path = pty.path.clone();
    let mut master = pty.master;
    let config = SimConfig {
        response_latency: silence,
        ..SimConfig::default()
    };
    let peer: Arc<Mutex<dyn Peer>> = Arc::new(Mutex::new(ModbusSimulator::new(SLAVE, Framing::Rtu, config)));
    let wire = WireTime {
        baud,
        bits_per_byte: BITS_PER_CHAR,
    };
    let server = SimServer::new(peer, clock.clone()).with_wire_time(wire);
    let stop = server.stop_flag();
    let handle = std::thread::spawn(move || server.serve(&mut master));

    let settings = SerialSettings {
        parity: drivescript::bus::Parity::Even,
        ..SerialSettings::with_baud(baud)
    };
    let sizes = Arc::new(Mutex::new(Sizes::default()));
    let measured = SerialTransport::open(&path, settings)
        .map_err(|e| e.to_string())
        .and_then(|port| {
            let link_config = LinkConfig {
                silence,
                ..LinkConfig::default()
            };
            let mut link = ModbusLink::new(
                SharedTransport::new(Box::new(port)),
                clock.clone(),
                SLAVE,
                link_config,
            );
            let request = Request::Read {
                function: Function::ReadHolding,
                start: 0x2000,
                count: 1,
            };
            for _ in 0..WARM_UP {
                link.exchange(&request).map_err(|e| e.to_string())?;
            }
            link.set_observer(Box::new(Count(sizes.clone())));
            // Each read from its request to the next one's: the silence after the reply
            // belongs to the read it ends.
            let mut times = Vec::with_capacity(READS as usize);
            let mut before = clock.now();
            for _ in 0..READS {
                link.exchange(&request).map_err(|e| e.to_string())?;
                let after = clock.now() + silence;
                times.push((after - before).as_secs_f64());
                before = after;
            }
            if link.stats().retries > 0 {
                return Err(format!("{} retries", link.stats().retries));
            }
            Ok(times)
        });
    stop.store(true, Ordering::SeqCst);
    let _ = handle.join();
    let mut times = measured?;
    times.sort_by(f64::total_cmp);
    let s = sizes.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    Ok(Row {
        baud,
        request: s.sent as f64 / s.frames_sent.max(1) as f64,
        reply: s.received as f64 / s.frames_received.max(1) as f64,
        silence,
        measured: times.iter().sum::<f64>() / times.len() as f64,
        median: times[times.len() / 2],
        longest: times[times.len() - 1],
    })
}

fn main() -> ExitCode {
    println!("Modbus RTU reads through a pseudo-terminal, 8E1 ({BITS_PER_CHAR} bits a character), {READS} reads per rate");
    println!("limit per read = (request + reply bytes) × {BITS_PER_CHAR} bit / baud + 2 × t3.5 (slave's silence before answering, master's before the next request)");
    let mut failed = false;
    for baud in [19_200, 115_200] {
        match measure(baud) {
            Ok(r) => {
                let wire_ms = (r.request + r.reply) * f64::from(BITS_PER_CHAR) / f64::from(baud) * 1e3;
                println!();
                println!(
                    "{baud} bit/s: ({:.0} + {:.0}) B × {BITS_PER_CHAR} / {baud} = {wire_ms:.3} ms on the wire, t3.5 = {:.3} ms → limit {:.3} ms = {:.1} reads/s",
                    r.request,
                    r.reply,
                    r.silence.as_secs_f64() * 1e3,
                    r.limit() * 1e3,
                    1.0 / r.limit()
                );
                println!(
                    "  mean {:.3} ms per read = {:.1} reads/s, ratio {:.1} %; median {:.3} ms = {:.1} reads/s, ratio {:.1} % → {}; longest {:.3} ms",
                    r.measured * 1e3,
                    1.0 / r.measured,
                    r.ratio() * 100.0,
                    r.median * 1e3,
                    1.0 / r.median,
                    r.median_ratio() * 100.0,
                    if r.median_ratio() >= TARGET { "PASS" } else { "BELOW TARGET" },
                    r.longest * 1e3
                );
            }
            Err(e) => {
                println!("{baud} bit/s: error: {e}");
                failed = true;
            }
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
