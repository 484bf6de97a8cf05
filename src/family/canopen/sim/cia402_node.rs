//! The simulated CiA 402 drive as a CANopen node on a frame bus: the shared SDO server in
//! front of the objects of its EDS, NMT commands (0x000), its boot-up message and
//! heartbeat (0x700 + node, every 0x1017 ms) and an EMCY frame (0x80 + node) when the
//! drive trips, when its fault is reset and when one is injected without a trip. Frames it produces on its own are sent with the
//! next frame it receives, stamped with the time they were due (the bus is lazy in virtual
//! time). No clock of its own.

use super::cia402_objects::{Cia402Objects, HEARTBEAT_TIME};
use super::node_emcy::{emcy_frame, injected_emcy};
use super::sdo_server::{SdoLogged, SdoServer};
use crate::bus::{CanFrame, FramePeer};
use crate::family::canopen::codec::SdoRequest;
use crate::family::canopen::codec::{heartbeat_id, NmtCommand, NmtState, NMT_ID};
use crate::sim::{SimConfig, SimCore, SimFront};
use std::time::Duration;

/// Heartbeats owed after a long quiet spell are not all sent: only the latest few.
const HEARTBEAT_CATCH_UP: u32 = 8;

#[derive(Debug)]
pub struct Cia402Node {
    core: SimCore<SdoLogged>,
    node: u8,
    objects: Cia402Objects,
    server: SdoServer,
    nmt: NmtState,
    /// When the next heartbeat is due; `None` before the boot-up message went out.
    next_heartbeat: Option<Duration>,
    /// From then on the node sends no heartbeat (an injected fault: a node whose
    /// communication died while the adapter is fine).
    heartbeat_stops_at: Option<Duration>,
    /// From then on the node sends nothing at all, heartbeat and SDO responses alike (an
    /// injected fault: a node that lost its power or its cable on a healthy bus).
    silent_at: Option<Duration>,
    /// The error code the last EMCY frame carried.
    emcy_code: u16,
}

impl Cia402Node {
    /// A drive just powered up at `node` (1..=127), pre-operational.
    pub fn new(node: u8, config: SimConfig) -> Self {
        Cia402Node {
            core: SimCore::new(config),
            node,
            objects: Cia402Objects::from_node_eds(node),
            server: SdoServer::default(),
            nmt: NmtState::PreOperational,
            next_heartbeat: None,
            heartbeat_stops_at: None,
            silent_at: None,
            emcy_code: 0,
        }
    }

    /// The requests decoded, with the time each arrived (the latest ones, bounded).
    pub fn received(&self) -> &[(Duration, SdoRequest)] {
        self.core.requests()
    }

    pub fn nmt_state(&self) -> NmtState {
        self.nmt
    }

    /// From `at` on the node sends no heartbeat.
    pub fn stop_heartbeat_at(&mut self, at: Duration) {
        self.heartbeat_stops_at = Some(at);
    }

    /// From `at` on the node sends nothing: no heartbeat, no SDO response.
    pub fn go_silent_at(&mut self, at: Duration) {
        self.silent_at = Some(at);
        self.heartbeat_stops_at = Some(self.heartbeat_stops_at.map_or(at, |s| s.min(at)));
    }

    fn heartbeat(&self, at: Duration) -> (Duration, CanFrame) {
        let state = if self.next_heartbeat.is_none() {
            NmtState::BootUp
        } else {
            self.nmt
        };
        (at, one_byte(heartbeat_id(self.node), state.byte()))
    }

    /// The boot-up message, then every heartbeat due up to `now`.
    fn heartbeats(&mut self, now: Duration, out: &mut Vec<(Duration, CanFrame)>) {
        let period = Duration::from_millis(self.objects.int((HEARTBEAT_TIME.0, 0)).max(0) as u64);
        let faults = &self.core.faults;
        let stopped = |at: Duration| self.heartbeat_stops_at.is_some_and(|s| at >= s) || faults.is_silent(at);
        let mut next = match self.next_heartbeat {
            Some(next) => next,
            None => {
                out.push(self.heartbeat(now));
                self.next_heartbeat = Some(now + period);
                return;
            }
        };
        if period.is_zero() {
            self.next_heartbeat = Some(now);
            return;
        }
        if next + period * HEARTBEAT_CATCH_UP < now {
            let behind = (now - next).as_nanos() / period.as_nanos();
            next += period * (behind as u32).saturating_sub(HEARTBEAT_CATCH_UP);
        }
        while next <= now {
            if !stopped(next) {
                out.push(self.heartbeat(next));
            }
            next += period;
        }
        self.next_heartbeat = Some(next);
    }

    /// An EMCY frame when the drive's error code changed.
    fn emcy(&mut self, now: Duration, out: &mut Vec<(Duration, CanFrame)>) {
        let code = self.core.model.drive_error();
        if code == self.emcy_code || self.nmt == NmtState::Stopped {
            return;
        }
        self.emcy_code = code;
        out.push((now, emcy_frame(self.node, code)));
    }

    /// The injected EMCY frames due by `now` (a stopped node sends none); the drive's
    /// state is left as it is.
    fn injected_emcy(&mut self, now: Duration, out: &mut Vec<(Duration, CanFrame)>) {
        let due = injected_emcy(&mut self.core, self.node, now);
        if self.nmt != NmtState::Stopped {
            out.extend(due);
        }
    }

    fn nmt_command(&mut self, frame: &CanFrame, now: Duration, out: &mut Vec<(Duration, CanFrame)>) {
        let data = frame.data();
        let (Some(&cs), Some(&target)) = (data.first(), data.get(1)) else {
            return;
        };
        if data.len() != 2 || (target != 0 && target != self.node) {
            return;
        }
        match NmtCommand::from_byte(cs) {
            Some(NmtCommand::Start) => self.nmt = NmtState::Operational,
            Some(NmtCommand::Stop) => self.nmt = NmtState::Stopped,
            Some(NmtCommand::EnterPreOperational) => self.nmt = NmtState::PreOperational,
            Some(NmtCommand::ResetNode | NmtCommand::ResetCommunication) => {
                self.nmt = NmtState::PreOperational;
                self.next_heartbeat = None;
                self.heartbeats(now, out);
            }
            None => {}
        }
        self.objects.set_operational(self.nmt == NmtState::Operational);
    }
}

/// A frame of one data byte (`id` is 0x700 + a node of 1..=127, always 11 bits).
fn one_byte(id: u32, byte: u8) -> CanFrame {
    CanFrame::new(id, &[byte]).unwrap_or_else(|| CanFrame::standard8(id, [byte, 0, 0, 0, 0, 0, 0, 0]))
}

impl FramePeer for Cia402Node {
    fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
        self.core.panic_if_due(now);
        self.core.advance_to(now);
        if self.silent_at.is_some_and(|s| now >= s) {
            return Vec::new();
        }
        let mut out = Vec::new();
        self.heartbeats(now, &mut out);
        self.emcy(now, &mut out);
        self.injected_emcy(now, &mut out);
        if !frame.extended && frame.id == NMT_ID {
            self.nmt_command(frame, now, &mut out);
        } else if self.nmt != NmtState::Stopped {
            // CiA 301: a stopped node answers NMT only, no SDO.
            out.extend(
                self.server
                    .receive(frame, now, self.node, &mut self.core, &mut self.objects),
            );
        }
        out.sort_by_key(|(at, _)| *at);
        out
    }

    crate::sim_frame_line_core!();

    fn poll(&mut self, until: Duration) -> Vec<(Duration, CanFrame)> {
        let mut out = Vec::new();
        if self.core.faults.line_up(until) {
            self.heartbeats(until, &mut out);
            self.injected_emcy(until, &mut out);
            out.sort_by_key(|(at, _)| *at);
        }
        out
    }
}

impl SimFront for Cia402Node {
    crate::sim_front_core!(SdoLogged);
    fn describe_drive(&self) -> String {
        format!("simulated CiA 402 drive at CAN node {} (from its EDS)", self.node)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(id: u32, data: &[u8]) -> CanFrame {
        CanFrame::new(id, data).unwrap()
    }

    fn sent(node: &mut Cia402Node, f: &CanFrame, ms: u64) -> Vec<String> {
        crate::bus::candump_replies(node, f, Duration::from_millis(ms))
    }

    /// CiA 301 on the wire: boot-up into pre-operational, start, stop (no SDO, heartbeat
    /// 0x04), pre-operational again, reset node (boot-up again); commands to other nodes
    /// are not this node's.
    #[test]
    fn the_node_honours_nmt_commands() {
        let mut node = Cia402Node::new(5, SimConfig::default());
        let read = frame(0x605, &[0x40, 0x41, 0x60, 0, 0, 0, 0, 0]);
        let first = sent(&mut node, &read, 0);
        assert_eq!(first[0], "705#00", "the boot-up message first: {first:?}");
        assert!(first[1].starts_with("585#4B416000"), "{first:?}");
        assert_eq!(node.nmt_state(), NmtState::PreOperational);
        sent(&mut node, &frame(0x000, &[0x01, 0x06]), 10);
        assert_eq!(
            node.nmt_state(),
            NmtState::PreOperational,
            "another node's command"
        );
        sent(&mut node, &frame(0x000, &[0x01, 0x05]), 20);
        assert_eq!(node.nmt_state(), NmtState::Operational);
        assert_eq!(sent(&mut node, &read, 150), ["705#05", "585#4B41600040020000"]);
        sent(&mut node, &frame(0x000, &[0x02, 0x05]), 160);
        assert_eq!(node.nmt_state(), NmtState::Stopped);
        assert_eq!(sent(&mut node, &read, 250), ["705#04"], "stopped: no SDO answer");
        sent(&mut node, &frame(0x000, &[0x80, 0x00]), 260);
        assert_eq!(node.nmt_state(), NmtState::PreOperational, "node 0: every node");
        assert_eq!(sent(&mut node, &read, 270).len(), 1, "SDO again");
        let reset = sent(&mut node, &frame(0x000, &[0x81, 0x05]), 280);
        assert_eq!(reset, ["705#00"], "a reset node boots again");
    }
}
