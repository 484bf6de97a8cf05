//! SocketCAN end to end where the kernel lets this test create a virtual CAN interface
//! (`ip link add dev NAME type vcan`, which needs the vcan module and the right to add
//! links): a simulated 9400 node answers on one socket, drivescript reads through another
//! with `--can socketcan:NAME`; the generic `canopen` family runs the commissioning recipe
//! on a simulated CiA 402 node the same way. Where the interface cannot be created (no vcan
//! module, no right to add links: a container) the tests say so and why, and pass: they
//! cannot prove anything there.

#![cfg(target_os = "linux")]

use crate::lenze_9400::node_9400;
use crate::support::{assert_has, cli, drivescript, stderr, stdout, words};
use drivescript::bus::{FrameBus, FramePeer, SocketCanBus};
use drivescript::family::canopen::sim::Cia402Node;
use drivescript::family::lenze_9400::sim::Lenze9400Simulator;
use drivescript::sim::{SimConfig, SimulatedDrive};
use std::process::Command;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A vcan interface for this test, deleted when dropped.
struct Vcan(String);

impl Vcan {
    /// The interface, or why it cannot be made here.
    fn create() -> Result<Vcan, String> {
        // One per test of this process (tests run in parallel); at most 15 characters.
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let n = NEXT.fetch_add(1, Ordering::SeqCst) % 100;
        let name = format!("vcands{}x{n}", std::process::id() % 100_000);
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

impl Vcan {
    /// The interface, or `None` after saying why `test` cannot prove anything here.
    fn for_test(test: &str) -> Option<Vcan> {
        match Vcan::create() {
            Ok(v) => Some(v),
            Err(why) => {
                println!("SKIPPED {test}: cannot create a vcan interface here ({why})");
                None
            }
        }
    }
}

impl Drop for Vcan {
    fn drop(&mut self) {
        let _ = Command::new("ip").args(["link", "del", &self.0]).output();
    }
}

/// A simulated node answering on its own socket of the interface, in real time, with the
/// frames it sends on its own (a heartbeat).
struct Node<P> {
    stop: Arc<AtomicBool>,
    thread: std::thread::JoinHandle<P>,
}

impl<P: FramePeer + Send + 'static> Node<P> {
    fn serve(vcan: &Vcan, mut sim: P) -> Node<P> {
        let mut bus = SocketCanBus::open(&vcan.0).expect("the node's socket");
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = stop.clone();
        let thread = std::thread::spawn(move || {
            let started = Instant::now();
            while !stopped.load(Ordering::SeqCst) {
                let mut out = sim.poll(started.elapsed());
                if let Ok(frame) = bus.receive(Duration::from_millis(10)) {
                    out.extend(sim.receive(&frame, started.elapsed()));
                }
                for (_, frame) in out {
                    let _ = bus.send(&frame);
                }
            }
            sim
        });
        Node { stop, thread }
    }

    /// Stops the node and hands back its simulator.
    fn stop(self) -> P {
        self.stop.store(true, Ordering::SeqCst);
        self.thread.join().expect("the node thread")
    }
}

#[test]
fn socketcan_reaches_a_simulated_node_on_a_virtual_can_interface() {
    let Some(vcan) = Vcan::for_test("socketcan_reaches_a_simulated_node_on_a_virtual_can_interface") else {
        return;
    };
    let node = Node::serve(&vcan, Lenze9400Simulator::new(12, SimConfig::default()));
    let can = format!("socketcan:{}", vcan.0);
    let out = drivescript(
        &[&["read", "ident", "C00061"][..], &node_9400("12", &can)].concat(),
        "",
    );
    node.stop();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_has(&stdout(&out), &["05.00.12.07", "43"]);
}

/// The commissioning recipe with only `drive:` changed, on a simulated CiA 402 node (node 4)
/// answering on its own socket, with its heartbeat: started by NMT before it enables
/// operation, stopped and put back to pre-operational at the end.
#[test]
fn the_commissioning_recipe_runs_on_a_cia402_node_over_socketcan() {
    let Some(vcan) = Vcan::for_test("the_commissioning_recipe_runs_on_a_cia402_node_over_socketcan") else {
        return;
    };
    let node = Node::serve(&vcan, Cia402Node::new(4, SimConfig::default()));
    let dir = crate::support::scratch("socketcan-canopen");
    let recipe = crate::canopen::commissioning(&dir);
    let trace = dir.join("run.log");
    let can = format!("socketcan:{}", vcan.0);
    let out = drivescript(
        &[
            "run",
            recipe.to_str().expect("a UTF-8 path"),
            "--address",
            "4",
            "--can",
            &can,
            "--trace",
            trace.to_str().expect("a UTF-8 path"),
        ],
        "",
    );
    let sim = node.stop();
    assert_eq!(out.status.code(), Some(0), "{}{}", stdout(&out), stderr(&out));
    crate::support::assert_in_order(
        &stdout(&out),
        &[
            "ident = \"drivescript CiA 402 node\"",
            "sent NMT start (`000#0104`)",
            "go to operation_enabled",
            "node 4 back to pre-operational",
            "drive left in ready to switch on at 0 rpm",
            "PASSED",
        ],
    );
    assert_eq!(sim.control_words_written(), vec![6, 7, 15, 7, 6]);
    let trace = std::fs::read_to_string(&trace).expect("trace");
    crate::support::assert_in_order(
        &trace,
        &[
            "000#0104",
            "604#2B4060000F000000",
            "604#2B40600006000000",
            "000#8004",
        ],
    );
}

#[test]
fn a_missing_interface_is_a_clear_error_before_anything_is_sent() {
    let out = cli(
        &words("read ident --drive lenze-9400 --can socketcan:nosuchcan7"),
        3,
    );
    assert_has(&out.stderr, &["nosuchcan7"]);
}
