//! A simulated SLCAN adapter in front of a simulated CAN node: speaks the adapter's side of
//! the Lawicel protocol on a byte stream (a pseudo-terminal) so that drivescript's SLCAN
//! bus, or any SLCAN tool, reaches the node. Acknowledges `Sn`/`O`/`C` with CR and each
//! transmit with `z` CR, refuses what it does not know with BELL, and hands received frames
//! over as `t…` lines with a 4-digit millisecond timestamp (as adapters do with time stamps
//! on). It must not interpret the frames.

use super::slcan_codec::{encode_frame, parse_line, SlcanEvent};
use super::{FramePeer, Peer, PeerReply};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

const BELL: &[u8] = b"\x07";
/// Longest command line the adapter takes before it drops the line.
const MAX_LINE: usize = 64;

pub struct SlcanAdapter {
    node: Arc<Mutex<dyn FramePeer>>,
    line: Vec<u8>,
    open: bool,
}

impl SlcanAdapter {
    pub fn new(node: Arc<Mutex<dyn FramePeer>>) -> Self {
        SlcanAdapter {
            node,
            line: Vec::new(),
            open: false,
        }
    }

    fn command(&mut self, line: &[u8], now: Duration) -> Vec<PeerReply> {
        let reply = |bytes: &[u8]| {
            vec![PeerReply {
                at: now,
                bytes: bytes.to_vec(),
            }]
        };
        match line {
            [b'S', b'0'..=b'8'] if !self.open => reply(b"\r"),
            b"O" if !self.open => {
                self.open = true;
                reply(b"\r")
            }
            b"C" if self.open => {
                self.open = false;
                reply(b"\r")
            }
            b"V" => reply(b"V1013\r"),
            b"N" => reply(b"NSIM1\r"),
            [b't' | b'T', ..] if self.open => {
                let SlcanEvent::Frame(frame) = parse_line(line) else {
                    return reply(BELL);
                };
                let mut out = reply(b"z\r");
                let answers = self
                    .node
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .receive(&frame, now);
                out.extend(answers.iter().map(received_line));
                out
            }
            _ => reply(BELL),
        }
    }
}

/// A frame from the bus as the adapter passes it on: `tIIILDD…` with a timestamp.
fn received_line((at, f): &(Duration, crate::bus::CanFrame)) -> PeerReply {
    let mut bytes = encode_frame(f);
    bytes.pop();
    let stamp = (at.as_millis() % 60_000) as u16;
    bytes.extend_from_slice(format!("{stamp:04X}\r").as_bytes());
    PeerReply { at: *at, bytes }
}

impl Peer for SlcanAdapter {
    fn poll(&mut self, now: Duration) -> Vec<PeerReply> {
        if !self.open {
            return Vec::new();
        }
        let own = self.node.lock().unwrap_or_else(PoisonError::into_inner).poll(now);
        own.iter().map(received_line).collect()
    }

    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        let mut replies = Vec::new();
        for &b in bytes {
            match b {
                b'\r' => {
                    let line = std::mem::take(&mut self.line);
                    replies.extend(self.command(&line, now));
                }
                b'\n' => {}
                _ if self.line.len() >= MAX_LINE => {}
                _ => self.line.push(b),
            }
        }
        replies
    }

    fn reachable(&self, now: Duration) -> bool {
        self.node
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .reachable(now)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::{CanFrame, FrameBus, MemoryTransport, SlcanBus};
    use crate::clock::RealClock;

    struct Echo;
    impl FramePeer for Echo {
        fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
            vec![(now, CanFrame::new(frame.id - 0x80, frame.data()).unwrap())]
        }
    }

    fn answer(adapter: &mut SlcanAdapter, text: &[u8]) -> String {
        adapter
            .receive(text, Duration::from_millis(0x1A2F))
            .into_iter()
            .map(|r| String::from_utf8_lossy(&r.bytes).into_owned())
            .collect()
    }

    #[test]
    fn the_adapter_side_of_the_protocol() {
        let mut a = SlcanAdapter::new(Arc::new(Mutex::new(Echo)));
        assert_eq!(answer(&mut a, b"t6011AA\r"), "\x07", "closed: refused");
        assert_eq!(answer(&mut a, b"S6\r"), "\r");
        assert_eq!(answer(&mut a, b"O\r"), "\r");
        assert_eq!(answer(&mut a, b"S6\r"), "\x07", "no bit rate change while open");
        assert_eq!(answer(&mut a, b"t6011AA\r"), "z\rt5811AA1A2F\r");
        assert_eq!(answer(&mut a, b"X\r"), "\x07");
        assert_eq!(answer(&mut a, b"C\r"), "\r");
    }

    #[test]
    fn the_slcan_bus_opens_and_exchanges_through_the_simulated_adapter() {
        let adapter = Arc::new(Mutex::new(SlcanAdapter::new(Arc::new(Mutex::new(Echo)))));
        let transport = MemoryTransport::new("memory", adapter, RealClock::shared());
        let mut bus = SlcanBus::open(Box::new(transport), 500_000).unwrap();
        assert_eq!(bus.name(), "memory, SLCAN at 500 kbit/s");
        bus.send(&CanFrame::new(0x605, &[1, 2, 3]).unwrap()).unwrap();
        let reply = bus.receive(Duration::from_millis(200)).unwrap();
        assert_eq!((reply.id, reply.data()), (0x585, &[1u8, 2, 3][..]));
        assert!(bus.receive(Duration::from_millis(20)).unwrap_err().is_timeout());
        assert!(SlcanBus::open(
            Box::new(MemoryTransport::new(
                "memory",
                Arc::new(Mutex::new(SlcanAdapter::new(Arc::new(Mutex::new(Echo))))),
                RealClock::shared()
            )),
            83_333
        )
        .err()
        .unwrap()
        .to_string()
        .contains("500k"));
    }
}
