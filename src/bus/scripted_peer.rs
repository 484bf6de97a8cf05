//! A peer for the link tests of the byte families: it answers each request with the next
//! scripted reply its delay later (`None` is silence) and keeps each request with the
//! time it came, so a test can see retries, gaps and what was sent. Test-only: every run
//! talks to a real line or the simulator.

use super::{Peer, PeerReply};
use crate::clock::VirtualClock;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use std::time::Duration;

pub struct ScriptedPeer {
    replies: VecDeque<Option<(Duration, Vec<u8>)>>,
    /// Each request as it came, with the clock time it had fully arrived.
    pub received: Vec<(Duration, Vec<u8>)>,
}

impl ScriptedPeer {
    /// A peer that answers `delay` after each request with the next of `replies`.
    pub fn new(
        replies: impl IntoIterator<Item = Option<Vec<u8>>>,
        delay: Duration,
    ) -> Arc<Mutex<ScriptedPeer>> {
        ScriptedPeer::timed(replies.into_iter().map(|r| r.map(|bytes| (delay, bytes))))
    }

    /// A peer that answers each request with the next of `replies`, each its own delay later.
    pub fn timed(replies: impl IntoIterator<Item = Option<(Duration, Vec<u8>)>>) -> Arc<Mutex<ScriptedPeer>> {
        Arc::new(Mutex::new(ScriptedPeer {
            replies: replies.into_iter().collect(),
            received: vec![],
        }))
    }

    /// A line named `scripted` to `peer`, on a virtual clock the test moves on, as a link
    /// test opens it.
    pub fn line(peer: &Arc<Mutex<ScriptedPeer>>) -> (super::SharedTransport, Arc<VirtualClock>) {
        let clock = Arc::new(VirtualClock::new());
        let line = super::MemoryTransport::shared("scripted", peer.clone(), clock.clone());
        (line, clock)
    }

    /// The requests in the order they came.
    pub fn sent(&self) -> Vec<Vec<u8>> {
        self.received.iter().map(|(_, bytes)| bytes.clone()).collect()
    }
}

impl Peer for ScriptedPeer {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        self.received.push((now, bytes.to_vec()));
        match self.replies.pop_front().flatten() {
            Some((delay, bytes)) => vec![PeerReply {
                at: now + delay,
                bytes,
            }],
            None => vec![],
        }
    }
}
