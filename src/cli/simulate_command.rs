//! `drivescript simulate`: serves the simulated drive on a pseudo-terminal or a TCP port so
//! any serial tool (or drivescript with `--port`/`--tcp`) can talk to it.

use super::stop_signals;
use crate::bus::{
    EchoingLine, FramePeer, FramePeerLine, Peer, PeerLine, SlcanAdapter, TcpTransport, WireTime,
};
use crate::clock::RealClock;
use crate::dictionary::Role;
use crate::family::{DriveAddress, Family, Registry, SimPeer, DEFAULT_DICTIONARY};
use crate::run::DNC_ADDRESS;
use crate::run::{COMMUNICATION, INVALID, PASSED};
use crate::sim::{SimConfig, SimSetting};
use crate::sim_server::SimServer;
use clap::Args;
use std::io::Write;
use std::net::TcpListener;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

#[derive(Debug, Args)]
/// Serve a simulated drive on a pseudo-terminal or a TCP port
///
/// Serve a simulated drive on a pseudo-terminal (--pty) or a TCP port (--tcp), until
/// Ctrl-C. The drive keeps its state between connections, like a real one behind a server.
pub struct SimulateArgs {
    /// The built-in dictionary whose drive family to simulate.
    #[arg(long, value_name = "DICTIONARY", default_value = DEFAULT_DICTIONARY)]
    drive: String,
    /// Serve on a new pseudo-terminal; its path is printed on the first line (Unix; Windows
    /// has none: serve with --tcp there).
    #[arg(long, conflicts_with_all = ["tcp", "slcan_pty"], required_unless_present_any = ["tcp", "slcan_pty"])]
    pty: bool,
    /// For a drive family on CAN (lenze-9400): serve the simulated node behind a simulated
    /// SLCAN adapter on a new pseudo-terminal; its path is printed on the first line, for
    /// `--can slcan:PATH`.
    #[arg(long, conflicts_with = "tcp")]
    slcan_pty: bool,
    /// Serve on this TCP address, e.g. 127.0.0.1:4001 (raw TCP, like ser2net).
    #[arg(long, value_name = "ADDR")]
    tcp: Option<String>,
    /// The simulated drive's address in its family's notation (as `run --address`);
    /// several, comma-separated (`0,1`, `dnc:2,dnc:3`), serve one simulated drive each on
    /// the one line, as drives on an RS485 line or nodes on a CAN bus.
    #[arg(long, value_name = "ADDRESS")]
    address: Option<String>,
    /// Raw DNC addresses, for families whose drives have one (SD2), comma-separated: `2,3`
    /// is `--address dnc:2,dnc:3`.
    #[arg(long = "dnc-address", value_name = "N,…", conflicts_with = "address")]
    dnc_address: Option<String>,
    /// Charge the time bytes take on a real line at --baud (8N1), so throughput can be
    /// measured honestly over a pseudo-terminal.
    #[arg(long)]
    wire_time: bool,
    /// Baud rate for --wire-time.
    #[arg(long, value_name = "N", default_value_t = 57_600)]
    baud: u32,
    /// Hand every byte the master sends back to it before the drive's answer, as a
    /// half-duplex RS485 adapter with echo on does (serial lines only).
    #[arg(long, conflicts_with = "slcan_pty")]
    echo: bool,
    /// Speed ramp of the simulated motor.
    #[arg(long, value_name = "RPM_PER_S", default_value_t = 2000.0)]
    ramp: f64,
    /// A setting of the simulated drive, NAME=VALUE, as `run --sim` takes it; may be
    /// repeated. Times (`emergency-at=20s:0x2310`) count from the server's start.
    #[arg(long = "sim", value_name = "NAME=VALUE", value_parser = SimSetting::parse)]
    sim: Vec<SimSetting>,
    /// Serve a capture instead of the simulated drive: a `--trace` file or a candump log
    /// answers each request with what the drive answered then (its drive is the one the
    /// trace's header names, else --drive). What the capture never answered gets no reply
    /// and is said on standard error.
    #[arg(long, value_name = "CAPTURE", conflicts_with_all = ["address", "dnc_address"])]
    replay: Option<std::path::PathBuf>,
}

pub fn run(args: &SimulateArgs, registry: &Registry) -> i32 {
    // A replayed trace names its own drive.
    let recorded = args.replay.as_deref().and_then(crate::run::recorded_drive);
    let drive = match recorded {
        Some(name) if args.drive == DEFAULT_DICTIONARY => name,
        _ => args.drive.clone(),
    };
    let family = match registry.dictionary(&drive) {
        Ok((family, _)) => family,
        Err(e) => {
            eprintln!("error: {e}");
            return INVALID;
        }
    };
    if let Err(e) = crate::run::check_sim_settings(&args.sim, registry, &[family.as_ref()]) {
        eprintln!("error: {e}");
        return INVALID;
    }
    // Several addresses (`0,1`, `dnc:2,dnc:3`): one simulated drive each, all on the one
    // line, each answering at its own address.
    let given = match &args.dnc_address {
        Some(list) => match DNC_ADDRESS.addresses(registry, family.as_ref(), list) {
            Ok(addresses) => Some(addresses),
            Err(e) => {
                eprintln!("error: {e}");
                return INVALID;
            }
        },
        None => args.address.clone(),
    };
    let texts: Vec<Option<&str>> = match given.as_deref() {
        Some(list) => list.split(',').map(|a| Some(a.trim())).collect(),
        None => vec![None],
    };
    let mut addresses = Vec::new();
    for text in texts {
        match family.parse_drive_address(text) {
            Ok(a) if addresses.iter().any(|b: &DriveAddress| b.number == a.number) => {
                eprintln!("error: --address names {} twice", a.shown);
                return INVALID;
            }
            Ok(a) => addresses.push(a),
            Err(e) => {
                eprintln!("error: {e}");
                return INVALID;
            }
        }
    }
    let mut config = SimConfig {
        ramp_rpm_per_s: args.ramp,
        ..SimConfig::default()
    };
    args.sim.iter().for_each(|s| s.apply(&mut config));
    let mut descriptions = Vec::new();
    let mut bytes: Vec<Arc<Mutex<dyn Peer>>> = Vec::new();
    let mut frames: Vec<Arc<Mutex<dyn FramePeer>>> = Vec::new();
    if let Some(capture) = &args.replay {
        let mut captured = match crate::run::captured_drive(registry, family.as_ref(), capture) {
            Ok(c) => c,
            Err(e) => {
                eprint!("{e}");
                return INVALID;
            }
        };
        captured.on_refusal(Box::new(|e| eprintln!("{e}")));
        let captured = Arc::new(Mutex::new(captured));
        match family.bus_kind() {
            crate::bus::BusKind::Bytes => bytes.push(captured),
            crate::bus::BusKind::Frames => frames.push(captured),
        }
        descriptions.push(format!(
            "a replay of {} (nothing is sent to any drive)",
            capture.display()
        ));
    }
    for address in addresses.iter().filter(|_| args.replay.is_none()) {
        let device = family.simulator(address, config.clone());
        {
            let mut drive = device.drive.lock().unwrap_or_else(PoisonError::into_inner);
            // A server can run for days and nobody reads its log.
            drive.set_logging(false);
            descriptions.push(drive.describe());
        }
        match device.peer {
            SimPeer::Bytes(p) => bytes.push(p),
            SimPeer::Frames(p) => frames.push(p),
        }
    }
    let mut description = descriptions.join(" and ");
    if args.echo {
        description.push_str(", behind an RS485 adapter that echoes");
    }
    let peer: Arc<Mutex<dyn Peer>> = match (frames.is_empty(), args.slcan_pty) {
        (true, false) if bytes.len() == 1 => bytes.remove(0),
        (true, false) => Arc::new(Mutex::new(PeerLine(bytes))),
        (false, true) => {
            let node: Arc<Mutex<dyn FramePeer>> = if frames.len() == 1 {
                frames.remove(0)
            } else {
                Arc::new(Mutex::new(FramePeerLine(frames)))
            };
            Arc::new(Mutex::new(SlcanAdapter::new(node)))
        }
        (false, false) => {
            eprintln!(
                "error: the {} family's simulated drive speaks CAN frames; serve it with --slcan-pty (--pty and --tcp serve byte streams)",
                family.id()
            );
            return INVALID;
        }
        (true, true) => {
            eprintln!(
                "error: the {} family talks over a serial line, not CAN; serve it with --pty or --tcp",
                family.id()
            );
            return INVALID;
        }
    };
    let peer: Arc<Mutex<dyn Peer>> = if args.echo {
        Arc::new(Mutex::new(EchoingLine(peer)))
    } else {
        peer
    };
    let mut server = SimServer::new(peer, RealClock::shared());
    if args.wire_time {
        server = server.with_wire_time(WireTime::new_8n1(args.baud));
    }
    let requests = stop_signals::install(false);
    let stop = server.stop_flag();
    let watcher_stop = stop.clone();
    std::thread::spawn(move || {
        while requests.count_at(Duration::ZERO) == 0 {
            requests.wait_real(Duration::from_secs(1));
        }
        watcher_stop.store(true, Ordering::SeqCst);
    });
    let wire = if args.wire_time {
        format!(", wire time at {} bit/s", args.baud)
    } else {
        String::new()
    };

    let hint = try_hint(
        args,
        &drive,
        registry,
        family.as_ref(),
        given.as_deref(),
        &addresses,
    );
    if args.pty || args.slcan_pty {
        serve_pty(&server, &description, &wire, &hint)
    } else if let Some(addr) = &args.tcp {
        serve_tcp(&server, addr, &description, &wire, &hint, &stop)
    } else {
        eprintln!("error: give --pty or --tcp ADDR");
        INVALID
    }
}

/// The command that talks to the simulated drive as served, without its endpoint: every
/// flag it needs besides `--port`/`--tcp`/`--can` (the dictionary, the first drive's
/// address and the baud rate of `--wire-time` where they are not the defaults), so that
/// copying it reaches this drive and not the default family's at its default address.
fn try_hint(
    args: &SimulateArgs,
    drive: &str,
    registry: &Registry,
    family: &dyn Family,
    given: Option<&str>,
    addresses: &[DriveAddress],
) -> String {
    let mut flags = String::new();
    if drive != DEFAULT_DICTIONARY {
        flags.push_str(&format!(" --drive {drive}"));
    }
    let default = family.parse_drive_address(None).ok().map(|a| a.number);
    let first = given.and_then(|list| list.split(',').next()).map(str::trim);
    if let (Some(text), Some(a)) = (first, addresses.first()) {
        if Some(a.number) != default {
            flags.push_str(&format!(" --address {text}"));
        }
    }
    if args.wire_time && args.baud != family.serial_settings().baud {
        flags.push_str(&format!(" --baud {}", args.baud));
    }
    // `state` only where the dictionary says how to read the state; every built-in
    // dictionary has `ident`.
    let has_state = registry
        .load_dictionary(drive)
        .is_ok_and(|d| d.role(Role::StatusWord).is_some());
    let command = if has_state { "state" } else { "read ident" };
    if args.slcan_pty {
        format!("drivescript {command}{flags} --can slcan:")
    } else if args.tcp.is_some() {
        format!("drivescript {command}{flags}")
    } else {
        format!("drivescript {command}{flags} --port ")
    }
}

#[cfg(unix)]
fn serve_pty(server: &SimServer, description: &str, wire: &str, hint: &str) -> i32 {
    let pty = match crate::sim_server::PtyEndpoint::open() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return COMMUNICATION;
        }
    };
    // The path alone on the first line, so scripts can read it.
    println!("{}", pty.path);
    eprintln!("{description} on {}{wire}; Ctrl-C to stop", pty.path);
    eprintln!("try: {hint}{}", pty.path);
    let _ = std::io::stdout().flush();
    let mut master = pty.master;
    match server.serve(&mut master) {
        Ok(stats) => {
            eprintln!(
                "stopped after {} replies ({} bytes received, {} bytes sent)",
                stats.replies, stats.bytes_in, stats.bytes_out
            );
            PASSED
        }
        Err(e) => {
            eprintln!("error: {e}");
            COMMUNICATION
        }
    }
}

#[cfg(not(unix))]
fn serve_pty(_: &SimServer, _: &str, _: &str, _: &str) -> i32 {
    eprintln!("error: Windows has no pseudo-terminals for --pty or --slcan-pty; serve on TCP instead: drivescript simulate --tcp 127.0.0.1:4001");
    INVALID
}

fn serve_tcp(
    server: &SimServer,
    addr: &str,
    description: &str,
    wire: &str,
    hint: &str,
    stop: &std::sync::atomic::AtomicBool,
) -> i32 {
    let listener = match TcpListener::bind(addr) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: cannot listen on {addr}: {e}; choose a free port, e.g. 127.0.0.1:4001");
            return INVALID;
        }
    };
    let local = listener
        .local_addr()
        .map(|a| a.to_string())
        .unwrap_or_else(|_| addr.to_string());
    println!("{local}");
    eprintln!("{description} on tcp {local}{wire}; Ctrl-C to stop");
    eprintln!("try: {hint} --tcp {local}");
    let _ = std::io::stdout().flush();
    if listener.set_nonblocking(true).is_err() {
        eprintln!("error: cannot poll the listening socket");
        return COMMUNICATION;
    }
    while !stop.load(Ordering::SeqCst) {
        match listener.accept() {
            Ok((stream, peer)) => {
                let _ = stream.set_nonblocking(false);
                let mut transport = match TcpTransport::from_stream(stream, format!("tcp client {peer}")) {
                    Ok(t) => t,
                    Err(e) => {
                        eprintln!("warning: {e}");
                        continue;
                    }
                };
                eprintln!("client {peer} connected");
                match server.serve(&mut transport) {
                    Ok(stats) => eprintln!("client {peer} left after {} replies", stats.replies),
                    Err(e) => eprintln!("client {peer}: {e}"),
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(50))
            }
            Err(e) => {
                eprintln!("error: accepting on {local}: {e}");
                return COMMUNICATION;
            }
        }
    }
    PASSED
}
