//! An in-process CAN bus to a simulated node: frames sent are handed to the peer at the
//! clock's time, and the peer's frames become receivable at the time it says. Reads wait on
//! the shared clock, so a timeout costs no real time with a virtual clock. It must not
//! interpret the frames.

use super::{CanFrame, FrameBus, TransportError};
use crate::clock::SharedClock;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// Something that answers frames with frames: a simulated CAN node.
pub trait FramePeer: Send {
    /// `frame` was on the bus at clock time `now`; returns the frames the node sends back,
    /// each with the clock time it is on the bus.
    fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)>;

    /// `receive` for a node in this process that can refuse a frame as a failed adapter
    /// would (a replayed capture with no answer for it); the bus passes the refusal on.
    fn exchange(
        &mut self,
        frame: &CanFrame,
        now: Duration,
    ) -> Result<Vec<(Duration, CanFrame)>, TransportError> {
        Ok(self.receive(frame, now))
    }

    /// Whether the adapter to the node is there at `now` (see `Peer::reachable`): a
    /// simulated node with an injected lost line says no for a while, and the bus then
    /// fails as an unplugged adapter does.
    fn reachable(&self, _now: Duration) -> bool {
        true
    }

    /// The frames the node sends on its own (a heartbeat) up to clock time `until`, each
    /// with its time; none by default.
    fn poll(&mut self, _until: Duration) -> Vec<(Duration, CanFrame)> {
        Vec::new()
    }
}

pub struct MemoryFrameBus {
    name: String,
    peer: Arc<Mutex<dyn FramePeer>>,
    clock: SharedClock,
    pending: VecDeque<(Duration, CanFrame)>,
}

impl MemoryFrameBus {
    pub fn new(name: impl Into<String>, peer: Arc<Mutex<dyn FramePeer>>, clock: SharedClock) -> Self {
        MemoryFrameBus {
            name: name.into(),
            peer,
            clock,
            pending: VecDeque::new(),
        }
    }
}

impl FrameBus for MemoryFrameBus {
    fn name(&self) -> &str {
        &self.name
    }

    fn send(&mut self, frame: &CanFrame) -> Result<(), TransportError> {
        let now = self.clock.now();
        let replies = {
            let mut peer = self.peer.lock().unwrap_or_else(PoisonError::into_inner);
            if !peer.reachable(now) {
                return Err(self.adapter_lost());
            }
            peer.exchange(frame, now)?
        };
        self.pending.extend(replies);
        Ok(())
    }

    fn receive(&mut self, timeout: Duration) -> Result<CanFrame, TransportError> {
        if !self.reachable() {
            self.pending.clear();
            return Err(self.adapter_lost());
        }
        let deadline = self.clock.now().saturating_add(timeout);
        let own = self
            .peer
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .poll(deadline);
        if !own.is_empty() {
            self.pending.extend(own);
            self.pending.make_contiguous().sort_by_key(|(at, _)| *at);
        }
        match self.pending.front() {
            Some(&(at, _)) if at <= deadline => {
                self.clock.sleep_until(at);
                self.pending
                    .pop_front()
                    .map(|(_, f)| f)
                    .ok_or_else(|| TransportError::Timeout {
                        port: self.name.clone(),
                        waited: timeout,
                    })
            }
            _ => {
                self.clock.sleep_until(deadline);
                Err(TransportError::Timeout {
                    port: self.name.clone(),
                    waited: timeout,
                })
            }
        }
    }

    fn reopen(&mut self) -> Result<(), TransportError> {
        let reachable = self.reachable();
        let still_down = "the simulated CAN adapter is still gone";
        super::memory::reopen_line(reachable, &self.name, still_down, &mut self.pending)
    }
}

impl MemoryFrameBus {
    /// Whether the simulated adapter is there now (a fault can take it away for a while).
    fn reachable(&self) -> bool {
        let peer = self.peer.lock().unwrap_or_else(PoisonError::into_inner);
        peer.reachable(self.clock.now())
    }

    fn adapter_lost(&self) -> TransportError {
        TransportError::Io {
            port: self.name.clone(),
            detail: "the CAN adapter went away (the simulated line is down)".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::VirtualClock;

    /// Answers every frame on 0x600 + n with the same data on 0x580 + n, 1 ms later.
    struct Echo;
    impl FramePeer for Echo {
        fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
            match CanFrame::new(frame.id - 0x600 + 0x580, frame.data()) {
                Some(reply) if (0x600..0x680).contains(&frame.id) => {
                    vec![(now + Duration::from_millis(1), reply)]
                }
                _ => Vec::new(),
            }
        }
    }

    #[test]
    fn frames_go_to_the_node_and_its_answers_come_back_in_time() {
        let clock: SharedClock = Arc::new(VirtualClock::new());
        let mut bus = MemoryFrameBus::new("memory", Arc::new(Mutex::new(Echo)), clock.clone());
        bus.send(&CanFrame::new(0x601, &[1, 2]).unwrap()).unwrap();
        let reply = bus.receive(Duration::from_millis(100)).unwrap();
        assert_eq!((reply.id, reply.data()), (0x581, &[1u8, 2][..]));
        assert_eq!(clock.now(), Duration::from_millis(1));
        assert!(bus.receive(Duration::from_millis(100)).unwrap_err().is_timeout());
        assert_eq!(clock.now(), Duration::from_millis(101));
    }
}
