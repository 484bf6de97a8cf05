//! Several in-process peers on one line, as drives on an RS485 line or nodes on a CAN bus:
//! whatever is sent reaches every peer, and each answers (or not) for itself. The line is
//! there while every peer's is. It must not interpret the bytes or frames.

use super::{CanFrame, FramePeer, Peer, PeerReply};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// Byte peers on one line.
pub struct PeerLine(pub Vec<Arc<Mutex<dyn Peer>>>);

impl Peer for PeerLine {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        let mut replies: Vec<PeerReply> = self
            .0
            .iter()
            .flat_map(|p| {
                p.lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .receive(bytes, now)
            })
            .collect();
        replies.sort_by_key(|r| r.at);
        replies
    }

    fn reachable(&self, now: Duration) -> bool {
        self.0
            .iter()
            .all(|p| p.lock().unwrap_or_else(PoisonError::into_inner).reachable(now))
    }

    fn up_until(&self, now: Duration) -> Duration {
        self.0
            .iter()
            .map(|p| p.lock().unwrap_or_else(PoisonError::into_inner).up_until(now))
            .min()
            .unwrap_or(Duration::MAX)
    }
}

/// A line behind a half-duplex RS485 adapter with echo on: every byte the master sends
/// comes back to it as it arrives, before any answer of the peers behind.
pub struct EchoingLine(pub Arc<Mutex<dyn Peer>>);

impl Peer for EchoingLine {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        let mut replies = vec![PeerReply {
            at: now,
            bytes: bytes.to_vec(),
        }];
        replies.extend(
            self.0
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .receive(bytes, now),
        );
        replies
    }

    fn reachable(&self, now: Duration) -> bool {
        self.0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .reachable(now)
    }

    fn up_until(&self, now: Duration) -> Duration {
        self.0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .up_until(now)
    }
}

/// Frame peers (CAN nodes) on one bus.
pub struct FramePeerLine(pub Vec<Arc<Mutex<dyn FramePeer>>>);

impl FramePeer for FramePeerLine {
    fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
        let mut frames: Vec<(Duration, CanFrame)> = self
            .0
            .iter()
            .flat_map(|p| {
                p.lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .receive(frame, now)
            })
            .collect();
        frames.sort_by_key(|(at, _)| *at);
        frames
    }

    fn reachable(&self, now: Duration) -> bool {
        self.0
            .iter()
            .all(|p| p.lock().unwrap_or_else(PoisonError::into_inner).reachable(now))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Echo(u8);
    impl Peer for Echo {
        fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
            if bytes.first() == Some(&self.0) {
                vec![PeerReply {
                    at: now + Duration::from_millis(u64::from(self.0)),
                    bytes: vec![self.0, 0xAA],
                }]
            } else {
                Vec::new()
            }
        }
    }

    #[test]
    fn every_peer_hears_the_line_and_only_the_addressed_one_answers() {
        let mut line = PeerLine(vec![Arc::new(Mutex::new(Echo(2))), Arc::new(Mutex::new(Echo(3)))]);
        let replies = line.receive(&[3, 1], Duration::ZERO);
        assert_eq!(replies.len(), 1);
        assert_eq!(replies[0].bytes, vec![3, 0xAA]);
        assert!(line.receive(&[4], Duration::ZERO).is_empty());
        assert!(line.reachable(Duration::ZERO));
    }

    #[test]
    fn an_echoing_line_hands_the_bytes_back_before_the_answer() {
        let mut line = EchoingLine(Arc::new(Mutex::new(Echo(3))));
        let now = Duration::from_millis(7);
        let replies = line.receive(&[3, 1], now);
        assert_eq!((replies[0].at, replies[0].bytes.clone()), (now, vec![3, 1]));
        assert_eq!(replies[1].bytes, vec![3, 0xAA]);
        assert_eq!(
            line.receive(&[4], now).len(),
            1,
            "the echo even when nobody answers"
        );
    }
}
