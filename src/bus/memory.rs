//! An in-memory transport wired to an in-process peer (the simulated drive).
//!
//! The peer answers in bytes, exactly like a drive on a wire; the transport only adds the
//! timing: replies become readable at the time the peer says (plus emulated wire time), and
//! reads wait on the shared [`Clock`], so with a virtual clock a timeout costs no real time.
//! It must not interpret the bytes.

use super::{Transport, TransportError};
use crate::clock::SharedClock;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// Bytes sent back by a [`Peer`], readable from time `at` (clock time) on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PeerReply {
    pub at: Duration,
    pub bytes: Vec<u8>,
}

/// Something that answers bytes with bytes: the simulated drive.
pub trait Peer: Send {
    /// `bytes` have fully arrived at clock time `now`; returns what the peer sends back.
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply>;

    /// `receive` for a peer in this process that can refuse a request as a failed line
    /// would (a replayed capture with no answer for it); the transport passes the refusal on.
    fn exchange(&mut self, bytes: &[u8], now: Duration) -> Result<Vec<PeerReply>, TransportError> {
        Ok(self.receive(bytes, now))
    }

    /// [`Peer::exchange`] into `out`, which a transport reuses for the millions of
    /// exchanges of a long run; a peer may build its replies there directly, in the byte
    /// buffers of replies already read ([`PeerReplies::buffer`]).
    fn exchange_into(
        &mut self,
        bytes: &[u8],
        now: Duration,
        out: &mut PeerReplies,
    ) -> Result<(), TransportError> {
        out.list.extend(self.exchange(bytes, now)?);
        Ok(())
    }

    /// Whether the line to the peer is there at `now`. A peer that can lose its line (the
    /// simulated drive with an injected lost link) says no for a while; the transport then
    /// fails as a port whose device went away does.
    fn reachable(&self, _now: Duration) -> bool {
        true
    }

    /// Until when the line, up at `now`, stays up for certain (a lost link ahead starts
    /// then); a transport asks [`Peer::reachable`] again only after it. `now` itself by
    /// default: it asks every time.
    fn up_until(&self, now: Duration) -> Duration {
        now
    }

    /// What the peer sends on its own by clock time `now` (a CAN node's heartbeat behind
    /// a simulated adapter); nothing by default.
    fn poll(&mut self, _now: Duration) -> Vec<PeerReply> {
        Vec::new()
    }
}

/// The replies of a peer to one write, and the byte buffers of replies read before, to be
/// filled again.
#[derive(Debug, Default)]
pub struct PeerReplies {
    list: Vec<PeerReply>,
    spare: Vec<Vec<u8>>,
}

/// Buffers kept for reuse: a peer answers a write with one or two replies.
const SPARE_BUFFERS: usize = 4;

impl PeerReplies {
    /// An empty buffer for a reply's bytes.
    pub fn buffer(&mut self) -> Vec<u8> {
        let mut bytes = self.spare.pop().unwrap_or_default();
        bytes.clear();
        bytes
    }

    pub fn push(&mut self, reply: PeerReply) {
        self.list.push(reply);
    }

    /// The replies, in the order the peer gave them.
    pub fn into_list(self) -> Vec<PeerReply> {
        self.list
    }

    fn recycle(&mut self, bytes: Vec<u8>) {
        if self.spare.len() < SPARE_BUFFERS {
            self.spare.push(bytes);
        }
    }
}

/// Emulated time on the wire: how long a byte takes at a baud rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireTime {
    pub baud: u32,
    /// Bits per character including start, parity and stop bits: 10 for 8N1.
    pub bits_per_byte: u32,
}

impl WireTime {
    pub fn new_8n1(baud: u32) -> Self {
        WireTime {
            baud,
            bits_per_byte: 10,
        }
    }

    /// Time that `n` bytes occupy the line.
    pub fn of(&self, n: usize) -> Duration {
        if self.baud == 0 {
            return Duration::ZERO;
        }
        let bits = n as u128 * u128::from(self.bits_per_byte);
        Duration::from_nanos(u64::try_from(bits * 1_000_000_000 / u128::from(self.baud)).unwrap_or(u64::MAX))
    }
}

/// A transport to a peer in the same process.
pub struct MemoryTransport {
    name: String,
    peer: Arc<Mutex<dyn Peer>>,
    clock: SharedClock,
    wire: Option<WireTime>,
    pending: VecDeque<PeerReply>,
    /// The peer's replies to the write under way (empty between writes) and buffers for
    /// the next ones.
    replies: PeerReplies,
    /// Until when the peer's line is up for certain, as the peer said at the last write:
    /// the reads of that write's replies need not lock the peer to ask.
    up_until: Duration,
}

impl MemoryTransport {
    pub fn new(name: impl Into<String>, peer: Arc<Mutex<dyn Peer>>, clock: SharedClock) -> Self {
        MemoryTransport {
            name: name.into(),
            peer,
            clock,
            wire: None,
            pending: VecDeque::new(),
            replies: PeerReplies::default(),
            up_until: Duration::ZERO,
        }
    }

    /// A line named `name` to `peer`, shared as links and the drives on one line take it.
    pub fn shared(
        name: impl Into<String>,
        peer: Arc<Mutex<dyn Peer>>,
        clock: SharedClock,
    ) -> super::SharedTransport {
        super::SharedTransport::new(Box::new(MemoryTransport::new(name, peer, clock)))
    }

    fn line_down(&self) -> TransportError {
        TransportError::Io {
            port: self.name.clone(),
            detail: "the device hung up (the simulated line is down)".into(),
        }
    }

    fn reachable(&self) -> bool {
        let now = self.clock.now();
        self.peer
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .reachable(now)
    }

    /// Makes every byte cost its time on the wire, in both directions.
    pub fn with_wire_time(mut self, wire: WireTime) -> Self {
        self.wire = Some(wire);
        self
    }
}

impl Transport for MemoryTransport {
    fn name(&self) -> &str {
        &self.name
    }

    fn write_all(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        if let Some(w) = self.wire {
            self.clock.sleep(w.of(bytes.len()));
        }
        let now = self.clock.now();
        self.replies.list.clear();
        {
            // A panic while the peer was answering (a test that injects one) must not cut
            // the safe stop off from it.
            let mut peer = self.peer.lock().unwrap_or_else(PoisonError::into_inner);
            if !peer.reachable(now) {
                return Err(self.line_down());
            }
            self.up_until = peer.up_until(now);
            peer.exchange_into(bytes, now, &mut self.replies)?;
        }
        for mut r in self.replies.list.drain(..) {
            if let Some(w) = self.wire {
                r.at += w.of(r.bytes.len());
            }
            self.pending.push_back(r);
        }
        Ok(())
    }

    fn reopen(&mut self) -> Result<(), TransportError> {
        let reachable = self.reachable();
        reopen_line(
            reachable,
            &self.name,
            "the simulated line is still down",
            &mut self.pending,
        )
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
        if self.clock.now() >= self.up_until && !self.reachable() {
            self.pending.clear();
            return Err(self.line_down());
        }
        let deadline = self.clock.now() + timeout;
        let Some(front) = self.pending.front_mut() else {
            self.clock.sleep_until(deadline);
            return Err(TransportError::Timeout {
                port: self.name.clone(),
                waited: timeout,
            });
        };
        if front.at > deadline {
            self.clock.sleep_until(deadline);
            return Err(TransportError::Timeout {
                port: self.name.clone(),
                waited: timeout,
            });
        }
        self.clock.sleep_until(front.at);
        let n = buf.len().min(front.bytes.len());
        buf[..n].copy_from_slice(&front.bytes[..n]);
        front.bytes.drain(..n);
        if front.bytes.is_empty() {
            if let Some(read) = self.pending.pop_front() {
                self.replies.recycle(read.bytes);
            }
        }
        Ok(n)
    }

    fn discard_input(&mut self) -> Result<usize, TransportError> {
        let now = self.clock.now();
        let mut dropped = 0;
        while self.pending.front().is_some_and(|r| r.at <= now) {
            if let Some(r) = self.pending.pop_front() {
                dropped += r.bytes.len();
            }
        }
        Ok(dropped)
    }
}

/// The reopen of a simulated line: refused, saying `still_down`, while its peer is
/// unreachable; otherwise what was waiting to be read is dropped, as a port reopened loses it.
pub(super) fn reopen_line<T>(
    reachable: bool,
    name: &str,
    still_down: &str,
    pending: &mut VecDeque<T>,
) -> Result<(), TransportError> {
    if !reachable {
        return Err(TransportError::Open {
            port: name.to_string(),
            detail: still_down.into(),
        });
    }
    pending.clear();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::{Clock, VirtualClock};

    struct Echo {
        delay: Duration,
    }
    impl Peer for Echo {
        fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
            vec![PeerReply {
                at: now + self.delay,
                bytes: bytes.to_vec(),
            }]
        }
    }

    fn transport(delay_ms: u64) -> (MemoryTransport, Arc<VirtualClock>) {
        let clock = Arc::new(VirtualClock::new());
        let peer: Arc<Mutex<dyn Peer>> = Arc::new(Mutex::new(Echo {
            delay: Duration::from_millis(delay_ms),
        }));
        (MemoryTransport::new("echo", peer, clock.clone()), clock)
    }

    /// Answers after 5 ms; its line goes down at 2 ms, as the simulator's lost link.
    struct LosesItsLine;
    impl Peer for LosesItsLine {
        fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
            vec![PeerReply {
                at: now + Duration::from_millis(5),
                bytes: bytes.to_vec(),
            }]
        }
        fn reachable(&self, now: Duration) -> bool {
            now < Duration::from_millis(2)
        }
        fn up_until(&self, _now: Duration) -> Duration {
            Duration::from_millis(2)
        }
    }

    /// The reads after a write ask the peer again once the time it vouched for is over.
    #[test]
    fn a_line_lost_between_request_and_reply_fails_the_read() {
        let clock = Arc::new(VirtualClock::new());
        let peer: Arc<Mutex<dyn Peer>> = Arc::new(Mutex::new(LosesItsLine));
        let mut t = MemoryTransport::new("losing", peer, clock.clone());
        t.write_all(&[1]).unwrap();
        let mut buf = [0u8; 4];
        clock.advance(Duration::from_millis(1));
        assert!(t.discard_input().is_ok());
        clock.advance(Duration::from_millis(2));
        assert!(matches!(
            t.read(&mut buf, Duration::from_secs(1)),
            Err(TransportError::Io { .. })
        ));
    }

    #[test]
    fn reply_arrives_at_the_peers_time() {
        let (mut t, clock) = transport(3);
        t.write_all(&[1, 2, 3]).unwrap();
        let mut buf = [0u8; 2];
        assert_eq!(t.read(&mut buf, Duration::from_secs(1)).unwrap(), 2);
        assert_eq!(clock.now(), Duration::from_millis(3));
        assert_eq!(t.read(&mut buf, Duration::from_secs(1)).unwrap(), 1);
        assert_eq!(buf[0], 3);
    }

    #[test]
    fn late_reply_times_out_and_costs_the_timeout() {
        let (mut t, clock) = transport(1500);
        t.write_all(&[9]).unwrap();
        let mut buf = [0u8; 8];
        let err = t.read(&mut buf, Duration::from_secs(1)).unwrap_err();
        assert!(matches!(err, TransportError::Timeout { .. }));
        assert_eq!(clock.now(), Duration::from_secs(1));
        // Still pending, readable later.
        assert_eq!(t.read(&mut buf, Duration::from_secs(1)).unwrap(), 1);
    }

    #[test]
    fn discard_drops_only_what_has_arrived() {
        let (mut t, clock) = transport(5);
        t.write_all(&[1, 2]).unwrap();
        assert_eq!(t.discard_input().unwrap(), 0);
        clock.advance(Duration::from_millis(5));
        assert_eq!(t.discard_input().unwrap(), 2);
    }

    #[test]
    fn wire_time_is_charged_both_ways() {
        let (t, clock) = transport(0);
        let mut t = t.with_wire_time(WireTime::new_8n1(57_600));
        t.write_all(&[0; 12]).unwrap();
        let mut buf = [0u8; 64];
        t.read(&mut buf, Duration::from_secs(1)).unwrap();
        // 24 bytes x 10 bits / 57600 bit/s
        assert_eq!(clock.now(), WireTime::new_8n1(57_600).of(24));
        assert_eq!(WireTime::new_8n1(57_600).of(24).as_micros(), 4166);
    }
}
