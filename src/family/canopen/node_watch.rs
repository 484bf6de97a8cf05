//! What a CANopen link learns about its node from the frames around its SDO transfers:
//! the heartbeat (0x700 + node) with the NMT state it carries, and EMCY frames (0x80 +
//! node). A node whose heartbeat was seen and then stays away for three of its periods is
//! lost, as CiA 301's heartbeat consumer says. An EMCY frame with an error code (not the
//! error reset 0x0000) is a fault the node reported, kept until it is taken, whether or not
//! the statusword shows it. Pure: frames and times in, verdicts out.

use super::codec::{emcy_id, error_code_text, heartbeat_id, Emcy, NmtState};
use crate::bus::CanFrame;
use std::time::Duration;

/// A heartbeat consumer waits this many producer periods before it calls the node lost.
const PERIODS_TO_LOSS: u32 = 3;
/// ... and at least this long: frames reach a loaded host in bursts (an SLCAN adapter's
/// USB packets, the scheduler), so a short period alone would call a healthy node lost.
const LEAST_WAIT: Duration = Duration::from_millis(500);
/// Heartbeats seen before the period is trusted.
const HEARTBEATS_TO_TRUST: u32 = 3;

/// What one frame said about the node, for the link's events and trace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NodeNews {
    /// Worth a line: a boot-up, a changed NMT state, an EMCY.
    Said(String),
    /// A heartbeat like the one before.
    Quiet,
}

#[derive(Debug, Clone, Default)]
pub struct NodeWatch {
    node: u8,
    /// The first heartbeat seen since the node booted, and how many since.
    first_heartbeat: Option<Duration>,
    heartbeats: u32,
    last_heartbeat: Option<Duration>,
    state: Option<NmtState>,
    /// The first EMCY with an error code since the last look, with its words.
    reported: Option<String>,
}

impl NodeWatch {
    pub fn new(node: u8) -> Self {
        NodeWatch {
            node,
            ..NodeWatch::default()
        }
    }

    /// Takes a frame seen at `now`; `None` when it is not this node's heartbeat or EMCY.
    pub fn see(&mut self, frame: &CanFrame, now: Duration) -> Option<NodeNews> {
        if frame.extended {
            return None;
        }
        if frame.id == heartbeat_id(self.node) {
            let state = NmtState::from_byte(*frame.data().first()?);
            if state == Some(NmtState::BootUp) || self.first_heartbeat.is_none() {
                self.first_heartbeat = Some(now);
                self.heartbeats = 0;
            }
            self.heartbeats += 1;
            self.last_heartbeat = Some(now);
            let changed = state != self.state;
            self.state = state;
            return Some(match (changed, state) {
                (_, Some(NmtState::BootUp)) => {
                    NodeNews::Said(format!("node {} booted (boot-up message)", self.node))
                }
                (true, Some(s)) => NodeNews::Said(format!("node {} is {} (heartbeat)", self.node, s.name())),
                _ => NodeNews::Quiet,
            });
        }
        if frame.id == emcy_id(self.node) {
            let e = Emcy::decode(frame.data())?;
            if e.is_reset() {
                return Some(NodeNews::Said(format!("node {} EMCY: error reset", self.node)));
            }
            let what = format!(
                "EMCY 0x{:04X} {} (error register 0x{:02X})",
                e.code,
                error_code_text(e.code),
                e.register
            );
            let said = format!("node {} {what}", self.node);
            self.reported.get_or_insert(said.clone());
            return Some(NodeNews::Said(said));
        }
        None
    }

    /// The fault the node reported by EMCY since the last call: `node 5 EMCY 0x3210 DC
    /// link over-voltage (error register 0x01)`; the first one when there were several.
    pub fn take_reported(&mut self) -> Option<String> {
        self.reported.take()
    }

    /// The NMT state the node's last heartbeat or boot-up message carried.
    pub fn state(&self) -> Option<NmtState> {
        self.state
    }

    /// Why the node counts as lost at `now`, if it does: its heartbeat was seen and has
    /// been away for three periods, or it says it is stopped (no SDO then).
    pub fn lost(&self, now: Duration) -> Option<String> {
        if self.state == Some(NmtState::Stopped) {
            return Some(format!(
                "node {} reports NMT state stopped in its heartbeat, in which it serves no SDO",
                self.node
            ));
        }
        let (last, period) = (self.last_heartbeat?, self.period()?);
        let away = now.saturating_sub(last);
        (away > (period * PERIODS_TO_LOSS).max(LEAST_WAIT)).then(|| {
            format!(
                "the heartbeat of node {} stopped: none for {} ms after one every {} ms (a heartbeat consumer gives up after {PERIODS_TO_LOSS} periods, at least {} ms)",
                self.node,
                away.as_millis(),
                period.as_millis(),
                LEAST_WAIT.as_millis()
            )
        })
    }

    /// Why a node that does not answer an SDO request is more than silent to it, if it is:
    /// its heartbeat, seen before, has been away for longer than two of its periods as
    /// well (the node, or the bus to it, is gone; CiA 301's consumer would call it lost a
    /// period later).
    pub fn silent(&self, now: Duration) -> Option<String> {
        let (last, period) = (self.last_heartbeat?, self.period()?);
        let away = now.saturating_sub(last);
        (away > period * 2).then(|| {
            format!(
                "heartbeat loss: the last heartbeat of node {} came {} ms ago (one every {} ms before)",
                self.node,
                away.as_millis(),
                period.as_millis()
            )
        })
    }

    /// The producer's period as seen: the mean gap between the heartbeats since boot-up
    /// (bursts average out), once enough were seen. Also how often a waiting link looks.
    pub fn period(&self) -> Option<Duration> {
        if self.heartbeats < HEARTBEATS_TO_TRUST {
            return None;
        }
        let span = self.last_heartbeat?.checked_sub(self.first_heartbeat?)?;
        Some(span / (self.heartbeats - 1)).filter(|p| !p.is_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ms(n: u64) -> Duration {
        Duration::from_millis(n)
    }

    fn hb(state: u8) -> CanFrame {
        CanFrame::new(0x705, &[state]).unwrap()
    }

    #[test]
    fn a_heartbeat_that_stops_is_a_lost_node() {
        let mut w = NodeWatch::new(5);
        assert_eq!(
            w.see(&hb(0x00), ms(0)),
            Some(NodeNews::Said("node 5 booted (boot-up message)".into()))
        );
        assert!(matches!(w.see(&hb(0x7F), ms(100)), Some(NodeNews::Said(_))));
        assert_eq!(w.see(&hb(0x7F), ms(200)), Some(NodeNews::Quiet));
        assert_eq!(w.period(), Some(ms(100)));
        assert_eq!(w.lost(ms(700)), None, "at least 500 ms");
        let why = w.lost(ms(701)).unwrap();
        assert!(
            why.contains("heartbeat of node 5 stopped: none for 501 ms after one every 100 ms"),
            "{why}"
        );
        // A slow producer: three of its periods.
        let mut slow = NodeWatch::new(5);
        for t in [0, 1000, 2000] {
            slow.see(&hb(0x05), ms(t));
        }
        assert_eq!(slow.lost(ms(5000)), None);
        assert!(slow.lost(ms(5001)).is_some());
        assert_eq!(w.see(&CanFrame::new(0x706, &[0x7F]).unwrap(), ms(300)), None);
    }

    #[test]
    fn a_heartbeat_away_for_two_periods_makes_a_silent_node_a_heartbeat_loss() {
        let mut w = NodeWatch::new(5);
        assert_eq!(w.silent(ms(10_000)), None, "no heartbeat seen: nothing to say");
        for t in [0, 100, 200] {
            w.see(&hb(0x05), ms(t));
        }
        assert_eq!(w.silent(ms(400)), None);
        let why = w.silent(ms(450)).unwrap();
        assert!(
            why.contains(
                "heartbeat loss: the last heartbeat of node 5 came 250 ms ago (one every 100 ms before)"
            ),
            "{why}"
        );
    }

    #[test]
    fn no_heartbeat_seen_is_no_verdict_and_stopped_is_lost() {
        let mut w = NodeWatch::new(5);
        assert_eq!(w.lost(ms(100_000)), None);
        w.see(&hb(0x04), ms(0));
        assert!(w.lost(ms(1)).unwrap().contains("stopped"));
    }

    #[test]
    fn emcy_frames_say_their_code() {
        let mut w = NodeWatch::new(5);
        let f = CanFrame::standard8(0x85, [0x10, 0x32, 0x01, 0, 0, 0, 0, 0]);
        assert_eq!(
            w.see(&f, ms(0)),
            Some(NodeNews::Said(
                "node 5 EMCY 0x3210 DC link over-voltage (error register 0x01)".into()
            ))
        );
        // A second one before the look: the first is the fault; a reset takes nothing back.
        w.see(
            &CanFrame::standard8(0x85, [0x10, 0x43, 0x09, 0, 0, 0, 0, 0]),
            ms(1),
        );
        w.see(&CanFrame::standard8(0x85, [0; 8]), ms(2));
        assert_eq!(
            w.take_reported().as_deref(),
            Some("node 5 EMCY 0x3210 DC link over-voltage (error register 0x01)")
        );
        assert_eq!(w.take_reported(), None);
        // An error reset alone is no fault; another node's EMCY is not this node's.
        w.see(&CanFrame::standard8(0x85, [0; 8]), ms(3));
        w.see(
            &CanFrame::standard8(0x86, [0x10, 0x32, 0x01, 0, 0, 0, 0, 0]),
            ms(4),
        );
        assert_eq!(w.take_reported(), None);
    }
}
