//! CANopen benchmark: how long an EDS of 2 000 objects takes to load as a dictionary
//! (limit 50 ms), and SDO expedited reads per second through a simulated SLCAN adapter on a
//! pseudo-terminal, as a ratio against a plain python-can SDO loop on the same simulated
//! CiA 402 node in the same run (target ≥ 1.0).
//!
//! A measurement, not a test (DESIGN: benchmarks print ratios against a stated limit,
//! never a timed assertion). Run with `cargo bench --bench canopen`. Without python-can
//! (`python3 -m pip install python-can pyserial`) the ratio is skipped with a message.

use drivescript::bus::{SerialSettings, SerialTransport, Shared, SharedFrameBus, SlcanAdapter, SlcanBus};
use drivescript::clock::{RealClock, SharedClock};
use drivescript::family::canopen::sim::Cia402Node;
use drivescript::family::canopen::{SdoLink, SdoLinkConfig};
use drivescript::family::Registry;
use drivescript::sim::SimConfig;
use std::process::ExitCode;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

const EDS_OBJECTS: usize = 2_000;
const EDS_LIMIT: Duration = Duration::from_millis(50);
const READS: u32 = 500;
/// Rounds of each side, alternating.
const ROUNDS: u32 = 3;
const NODE: u8 = 1;

/// An EDS of `n` objects: every fourth a RECORD of three sub-objects, the rest VARs of
/// every carried type, with limits and defaults.
fn eds_text(n: usize) -> String {
    let mut text = String::from("[FileInfo]\nFileName=bench.eds\nEDSVersion=4.0\n\n[ManufacturerObjects]\n");
    text.push_str(&format!("SupportedObjects={n}\n"));
    for i in 0..n {
        text.push_str(&format!("{}=0x{:04X}\n", i + 1, 0x2000 + i));
    }
    for i in 0..n {
        let index = 0x2000 + i;
        if i % 4 == 0 {
            text.push_str(&format!(
                "\n[{index:04X}]\nParameterName=Record {i}\nObjectType=0x9\nSubNumber=3\n"
            ));
            for sub in 0..3 {
                text.push_str(&format!(
                    "\n[{index:04X}sub{sub}]\nParameterName=Field {sub}\nDataType=0x0006\nAccessType=rw\nDefaultValue={sub}\n"
                ));
            }
        } else {
            let data_type = [
                0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x10, 0x11, 0x12, 0x13,
                0x14, 0x15, 0x16, 0x18, 0x19, 0x1A, 0x1B,
            ][i % 22];
            text.push_str(&format!(
                "\n[{index:04X}]\nParameterName=Object {i}\nObjectType=0x7\nDataType=0x{data_type:04X}\nAccessType=rw\nLowLimit=0\nHighLimit=100\nDefaultValue=$NODEID+1\nPDOMapping=0\n"
            ));
        }
    }
    text
}

fn eds_load() -> Duration {
    let dir = std::env::temp_dir().join(format!("drivescript-bench-eds-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("bench.eds");
    let _ = std::fs::write(&path, eds_text(EDS_OBJECTS));
    let registry = Registry::builtin();
    let mut best = Duration::MAX;
    for _ in 0..5 {
        let Ok(mut d) = registry.load_dictionary("canopen") else {
            return Duration::MAX;
        };
        let started = Instant::now();
        if let Err(e) = d.extend_from(&path) {
            eprintln!("the benchmark's EDS did not load: {e}");
            return Duration::MAX;
        }
        best = best.min(started.elapsed());
        assert!(d.objects().count() > EDS_OBJECTS);
    }
    let _ = std::fs::remove_dir_all(&dir);
    best
}

/// SDO reads of the statusword per second through the pty, by drivescript's link.
fn drivescript_reads(path: &str) -> Result<f64, String> {
    let transport =
        SerialTransport::open(path, SerialSettings::with_baud(115_200)).map_err(|e| e.to_string())?;
    let bus = SlcanBus::open(Box::new(transport), 500_000).map_err(|e| e.to_string())?;
    let shared: SharedFrameBus = Shared::new(Box::new(bus));
    let clock: SharedClock = Arc::new(RealClock::new());
    let mut link = SdoLink::new(shared, clock, NODE, SdoLinkConfig::default());
    for _ in 0..10 {
        link.upload(0x6041, 0).map_err(|e| e.to_string())?;
    }
    let started = Instant::now();
    for _ in 0..READS {
        link.upload(0x6041, 0).map_err(|e| e.to_string())?;
    }
    Ok(f64::from(READS) / started.elapsed().as_secs_f64())
}

/// The same reads by a plain python-can loop; `None` (with the reason) without python-can.
fn python_can_reads(path: &str) -> Result<f64, String> {
    const SCRIPT: &str = r#"
import sys, time, can
path, reads = sys.argv[1], int(sys.argv[2])
bus = can.Bus(interface="slcan", channel=path, bitrate=500000, ttyBaudrate=115200)
request = can.Message(arbitration_id=0x601, is_extended_id=False, data=[0x40, 0x41, 0x60, 0, 0, 0, 0, 0])
def read():
    bus.send(request)
    while True:
        m = bus.recv(1.0)
        if m is None:
            raise SystemExit("no SDO response")
        if m.arbitration_id == 0x581:
            return
for _ in range(10):
    read()
start = time.perf_counter()
for _ in range(reads):
    read()
print(reads / (time.perf_counter() - start))
bus.shutdown()
"#;
    let out = std::process::Command::new("python3")
        .args(["-c", SCRIPT, path, &READS.to_string()])
        .output()
        .map_err(|e| format!("python3 cannot be started: {e}"))?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).trim().to_string());
    }
    String::from_utf8_lossy(&out.stdout)
        .trim()
        .parse()
        .map_err(|_| "python-can printed no rate".to_string())
}

fn python_can_missing() -> bool {
    !std::process::Command::new("python3")
        .args(["-c", "import can, serial"])
        .status()
        .is_ok_and(|s| s.success())
}

fn main() -> ExitCode {
    let eds = eds_load();
    let verdict = if eds <= EDS_LIMIT { "PASS" } else { "BELOW TARGET" };
    println!(
        "EDS of {EDS_OBJECTS} objects loads in {:.1} ms (limit {} ms): {verdict}",
        eds.as_secs_f64() * 1000.0,
        EDS_LIMIT.as_millis()
    );

    let Ok(pty) = drivescript::sim_server::PtyEndpoint::open() else {
        println!("SDO reads through an SLCAN pty: skipped, no pseudo-terminal");
        return ExitCode::SUCCESS;
    };
    let path = pty.path.clone();
    let node: Arc<Mutex<dyn drivescript::bus::FramePeer>> =
        Arc::new(Mutex::new(Cia402Node::new(NODE, SimConfig::default())));
    let adapter = Arc::new(Mutex::new(SlcanAdapter::new(node)));
    let clock: SharedClock = Arc::new(RealClock::new());
    let server = drivescript::sim_server::SimServer::new(adapter, clock);
    let stop = server.stop_flag();
    let mut master = pty.master;
    let serving = std::thread::spawn(move || server.serve(&mut master));

    // Alternating rounds, the best of each side: a machine busy with other work slows
    // whichever side it happens to hit, not the comparison.
    let python = !python_can_missing();
    let (mut ours, mut theirs) = (0.0f64, Ok(0.0f64));
    for _ in 0..ROUNDS {
        match drivescript_reads(&path) {
            Ok(rate) => ours = ours.max(rate),
            Err(e) => {
                eprintln!("drivescript's SDO reads failed: {e}");
                stop.store(true, std::sync::atomic::Ordering::SeqCst);
                return ExitCode::FAILURE;
            }
        }
        if python {
            theirs = match (theirs, python_can_reads(&path)) {
                (Ok(best), Ok(rate)) => Ok(best.max(rate)),
                (Err(e), _) | (_, Err(e)) => Err(e),
            };
        }
    }
    println!("drivescript: {ours:.0} SDO expedited reads/s through the SLCAN pty (best of {ROUNDS})");
    if !python {
        println!("python-can: skipped, not installed (python3 -m pip install python-can pyserial); no ratio");
    } else {
        match theirs {
            Ok(theirs) => {
                let ratio = ours / theirs;
                let verdict = if ratio >= 1.0 { "PASS" } else { "BELOW TARGET" };
                println!(
                    "python-can:  {theirs:.0} SDO expedited reads/s on the same node (best of {ROUNDS})"
                );
                println!("ratio drivescript / python-can: {ratio:.2} (target ≥ 1.0): {verdict}");
            }
            Err(e) => println!("python-can: the loop failed ({e}); no ratio"),
        }
    }
    stop.store(true, std::sync::atomic::Ordering::SeqCst);
    let _ = serving.join();
    ExitCode::SUCCESS
}
