//! Serves an in-process peer (the simulated drive) on a byte pipe — the far end of a
//! pseudo-terminal, or a TCP connection — so any serial tool, or drivescript itself with
//! `--port`/`--tcp`, can talk to it. Optionally charges the time bytes would take on a real
//! line. Must not interpret telegrams: the peer does that.

use crate::bus::{Peer, Transport, TransportError, WireTime};
use crate::clock::SharedClock;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How often the serve loop looks at the stop flag while the line is quiet.
const POLL: Duration = Duration::from_millis(50);

/// What one `serve` call did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ServeStats {
    pub bytes_in: u64,
    pub bytes_out: u64,
    pub replies: u64,
    /// Times the frames the peer sent on its own found nobody reading and were dropped.
    pub dropped_unread: u64,
}

pub struct SimServer {
    peer: Arc<Mutex<dyn Peer>>,
    clock: SharedClock,
    wire: Option<WireTime>,
    stop: Arc<AtomicBool>,
}

impl SimServer {
    pub fn new(peer: Arc<Mutex<dyn Peer>>, clock: SharedClock) -> Self {
        SimServer {
            peer,
            clock,
            wire: None,
            stop: Arc::new(AtomicBool::new(false)),
        }
    }

    /// Emulates a line at this rate: a request is complete only when its last byte would
    /// have arrived, and a reply is handed over when its last byte would have been sent.
    pub fn with_wire_time(mut self, wire: WireTime) -> Self {
        self.wire = Some(wire);
        self
    }

    /// Setting this flag ends `serve` within [`POLL`].
    pub fn stop_flag(&self) -> Arc<AtomicBool> {
        self.stop.clone()
    }

    /// Answers whatever arrives on `io` until the other side closes or the stop flag is set.
    pub fn serve(&self, io: &mut dyn Transport) -> Result<ServeStats, TransportError> {
        let mut stats = ServeStats::default();
        let mut buf = [0u8; 512];
        let mut input_busy_until = Duration::ZERO;
        let mut output_busy_until = Duration::ZERO;
        while !self.stop.load(Ordering::SeqCst) {
            // What the peer sends on its own (a CAN node's heartbeat) goes out as it is due.
            let own = match self.peer.lock() {
                Ok(mut peer) => peer.poll(self.clock.now()),
                Err(_) => Vec::new(),
            };
            for reply in own {
                match io.write_all(&reply.bytes) {
                    Ok(()) => stats.bytes_out += reply.bytes.len() as u64,
                    // Nobody reads the line (a client left the adapter open and went):
                    // what waits unread is dropped, as a real adapter's frames are lost,
                    // and the server stays for the next client.
                    Err(e) => {
                        if !io.discard_output()? {
                            return Err(e);
                        }
                        stats.dropped_unread += 1;
                    }
                }
            }
            let n = match io.read(&mut buf, POLL) {
                Ok(n) => n,
                Err(TransportError::Timeout { .. }) => continue,
                Err(TransportError::Closed { .. }) => break,
                Err(e) => return Err(e),
            };
            stats.bytes_in += n as u64;
            let now = self.clock.now();
            let arrived = match self.wire {
                Some(w) => now.max(input_busy_until) + w.of(n),
                None => now,
            };
            input_busy_until = arrived;
            let replies = match self.peer.lock() {
                Ok(mut peer) => peer.receive(&buf[..n], arrived),
                Err(_) => {
                    return Err(TransportError::Closed {
                        port: io.name().to_string(),
                    })
                }
            };
            for reply in replies {
                let done = match self.wire {
                    Some(w) => reply.at.max(output_busy_until) + w.of(reply.bytes.len()),
                    None => reply.at,
                };
                output_busy_until = done;
                self.clock.sleep_until(done);
                io.write_all(&reply.bytes)?;
                stats.bytes_out += reply.bytes.len() as u64;
                stats.replies += 1;
            }
        }
        Ok(stats)
    }
}

/// A pseudo-terminal whose far end is served: the path in `path` behaves like a serial
/// port with a drive on it.
#[cfg(unix)]
pub struct PtyEndpoint {
    /// The path to give other programs (`/dev/pts/N`).
    pub path: String,
    /// The near end, to pass to [`SimServer::serve`].
    pub master: crate::bus::SerialTransport,
    /// Kept open so the master does not see a hang-up while no program has the path open.
    _slave: serialport::TTYPort,
}

#[cfg(unix)]
impl PtyEndpoint {
    pub fn open() -> Result<Self, TransportError> {
        let (master, slave) = serialport::TTYPort::pair().map_err(|e| TransportError::Open {
            port: "a new pseudo-terminal".into(),
            detail: e.to_string(),
        })?;
        // serialport opens the pair without close-on-exec; a child process started meanwhile
        // (by this program or a test harness) would keep the pseudo-terminal alive after we
        // close it, and a drive that "goes away" would never hang up.
        for fd in [
            std::os::fd::AsRawFd::as_raw_fd(&master),
            std::os::fd::AsRawFd::as_raw_fd(&slave),
        ] {
            // SAFETY: setting a descriptor flag on descriptors this function owns.
            unsafe {
                libc::fcntl(fd, libc::F_SETFD, libc::FD_CLOEXEC);
            }
        }
        let path = serialport::SerialPort::name(&slave).unwrap_or_default();
        if path.is_empty() {
            return Err(TransportError::Open {
                port: "a new pseudo-terminal".into(),
                detail: "the system gave no path for it".into(),
            });
        }
        let master = crate::bus::SerialTransport::from_port(master, format!("pseudo-terminal {path}"));
        Ok(PtyEndpoint {
            path,
            master,
            _slave: slave,
        })
    }
}

// Every test here needs a pseudo-terminal.
#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use crate::bus::PeerReply;
    use crate::clock::RealClock;

    struct Echo;
    impl Peer for Echo {
        fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
            vec![PeerReply {
                at: now,
                bytes: bytes.iter().map(|b| b ^ 0xff).collect(),
            }]
        }
    }

    /// A server of `peer` on a new pseudo-terminal, serving in its own thread.
    struct Served {
        path: String,
        stop: Arc<AtomicBool>,
        handle: std::thread::JoinHandle<Result<ServeStats, TransportError>>,
        _slave: serialport::TTYPort,
    }

    fn served(peer: impl Peer + 'static) -> Served {
        let pty = PtyEndpoint::open().unwrap();
        let mut master = pty.master;
        let server = SimServer::new(Arc::new(Mutex::new(peer)), RealClock::shared());
        let stop = server.stop_flag();
        let handle = std::thread::spawn(move || server.serve(&mut master));
        Served {
            path: pty.path,
            stop,
            handle,
            _slave: pty._slave,
        }
    }

    impl Served {
        /// Stops the server; what it counted.
        fn stop(self) -> ServeStats {
            self.stop.store(true, Ordering::SeqCst);
            self.handle.join().unwrap().unwrap()
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_pty_path_answers_like_a_port() {
        let server = served(Echo);
        let mut port = crate::bus::SerialTransport::open(&server.path, Default::default()).unwrap();
        port.write_all(&[0x00, 0x0f]).unwrap();
        let mut got = Vec::new();
        let mut buf = [0u8; 8];
        while got.len() < 2 {
            let n = port.read(&mut buf, Duration::from_secs(2)).unwrap();
            got.extend_from_slice(&buf[..n]);
        }
        assert_eq!(got, vec![0xff, 0xf0]);
        assert_eq!(server.stop().replies, 1);
    }

    /// Sends `left` bytes of its own in chunks, as a CAN node sends its heartbeats.
    struct Chatty {
        left: Arc<std::sync::atomic::AtomicUsize>,
    }
    impl Peer for Chatty {
        fn poll(&mut self, now: Duration) -> Vec<PeerReply> {
            let n = self.left.load(Ordering::SeqCst).min(1024);
            self.left.fetch_sub(n, Ordering::SeqCst);
            vec![PeerReply {
                at: now,
                bytes: vec![0x55; n],
            }]
        }
        fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
            Echo.receive(bytes, now)
        }
    }

    /// A client that left the line without reading (an SLCAN adapter left open) used to end
    /// the server once the pseudo-terminal was full; now the unread bytes are dropped and
    /// the next client is served.
    #[cfg(unix)]
    #[test]
    fn a_line_nobody_reads_does_not_end_the_server() {
        // Well beyond what a pseudo-terminal holds in raw mode (about 16 KiB on Linux).
        let left = Arc::new(std::sync::atomic::AtomicUsize::new(40 * 1024));
        let server = served(Chatty { left: left.clone() });
        let started = std::time::Instant::now();
        while left.load(Ordering::SeqCst) > 0 && !server.handle.is_finished() {
            assert!(
                started.elapsed() < Duration::from_secs(30),
                "the peer's bytes were not taken"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        if server.handle.is_finished() {
            panic!("the server ended: {:?}", server.handle.join());
        }
        let mut port = crate::bus::SerialTransport::open(&server.path, Default::default()).unwrap();
        port.discard_input().unwrap();
        port.write_all(&[0x00, 0x0f]).unwrap();
        let mut got = Vec::new();
        let mut buf = [0u8; 256];
        while !got.ends_with(&[0xff, 0xf0]) {
            let n = port.read(&mut buf, Duration::from_secs(2)).unwrap();
            got.extend(buf[..n].iter().filter(|b| **b != 0x55));
        }
        let stats = server.stop();
        assert!(stats.dropped_unread >= 1, "{stats:?}");
    }
}
