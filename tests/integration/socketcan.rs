//! SocketCAN end to end where the kernel lets this test create a virtual CAN interface
//! (`ip link add dev NAME type vcan`, which needs the vcan module and the right to add
//! links): a simulated 9400 node answers on one socket, drivescript reads through another
//! with `--can socketcan:NAME`. Where the interface cannot be created the test says so
//! and why, and passes: it cannot prove anything there.

#![cfg(target_os = "linux")]

use crate::support::{assert_has, cli, drivescript, stderr, stdout};
use drivescript::bus::{FrameBus, FramePeer, SocketCanBus};
use drivescript::family::lenze_9400::sim::Lenze9400Simulator;
use drivescript::sim::SimConfig;
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A vcan interface for this test, deleted when dropped.
struct Vcan(String);

impl Vcan {
    /// The interface, or why it cannot be made here.
    fn create() -> Result<Vcan, String> {
        let name = format!("vcands{}", std::process::id() % 100_000);
        let ip = |args: &[&str]| -> Result<(), String> {
            let out = Command::new("ip")
                .args(args)
                .output()
                .map_err(|e| format!("`ip` cannot be run: {e}"))?;
            if out.status.success() {
                Ok(())
            } else {
                Err(format!(
                    "`ip {}` failed: {}",
                    args.join(" "),
                    String::from_utf8_lossy(&out.stderr).trim()
                ))
            }
        };
        ip(&["link", "add", "dev", &name, "type", "vcan"])?;
        let vcan = Vcan(name.clone());
        ip(&["link", "set", "up", &name])?;
        Ok(vcan)
    }
}

impl Drop for Vcan {
    fn drop(&mut self) {
        let _ = Command::new("ip").args(["link", "del", &self.0]).output();
    }
}

#[test]
fn socketcan_reaches_a_simulated_node_on_a_virtual_can_interface() {
    let vcan = match Vcan::create() {
        Ok(v) => v,
        Err(why) => {
            println!("SKIPPED socketcan_reaches_a_simulated_node_on_a_virtual_can_interface: cannot create a vcan interface here ({why})");
            return;
        }
    };
    let mut node_bus = SocketCanBus::open(&vcan.0).expect("the node's socket");
    let stop = Arc::new(AtomicBool::new(false));
    let node_stop = stop.clone();
    let node = std::thread::spawn(move || {
        let mut sim = Lenze9400Simulator::new(12, SimConfig::default());
        let started = Instant::now();
        while !node_stop.load(Ordering::SeqCst) {
            let Ok(frame) = node_bus.receive(Duration::from_millis(50)) else {
                continue;
            };
            for (_, reply) in sim.receive(&frame, started.elapsed()) {
                let _ = node_bus.send(&reply);
            }
        }
    });
    let can = format!("socketcan:{}", vcan.0);
    let out = drivescript(
        &[
            "read",
            "ident",
            "C00061",
            "--drive",
            "lenze-9400",
            "--address",
            "12",
            "--can",
            &can,
        ],
        "",
    );
    stop.store(true, Ordering::SeqCst);
    let _ = node.join();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_has(&stdout(&out), &["05.00.12.07", "43"]);
}

#[test]
fn a_missing_interface_is_a_clear_error_before_anything_is_sent() {
    let out = cli(
        &[
            "read",
            "ident",
            "--drive",
            "lenze-9400",
            "--can",
            "socketcan:nosuchcan7",
        ],
        3,
    );
    assert_has(&out.stderr, &["nosuchcan7"]);
}
