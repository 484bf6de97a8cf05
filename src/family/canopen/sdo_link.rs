//! The CANopen SDO client link: one transfer at a time to one node over a shared CAN frame
//! bus, with reply timeouts, retries and stop-aware waits.
//!
//! Only frames with the identifier 0x580 + node are responses; everything else on the bus
//! (other nodes, other services) is passed over. The bus is locked for a whole transfer,
//! so the segments of two nodes' transfers never interleave. A response that breaks the
//! protocol (wrong toggle bit, unknown command) is answered with an abort, as CiA 301
//! asks, and the transfer is tried again; so is a transfer whose node fell silent (after
//! an abort with the timeout code when it was in the middle of its segments). A lost
//! adapter ends the transfer at once with the transport error: only reopening can help.
//! Must not know object names, units or states; how objects are named in messages and what
//! to check when a node is silent come from the family ([`SdoNotation`]).

use super::codec::{
    request_id, response_id, AbortCode, NmtCommand, NmtState, SdoClient, SdoRequest, SdoStep, Uploaded,
    NMT_ID,
};
use super::node_watch::{NodeNews, NodeWatch};
use crate::bus::{CanFrame, FrameBus, SharedFrameBus, TransportError};
use crate::clock::SharedClock;
use crate::drive::AccessError;
use crate::link::{
    AttemptFailure, CoreLink, Direction, ExchangeText, LinkCore, Refusal, ReplyWait, RetryPlan,
};
use std::time::Duration;

/// A stop request does not cut short the first part of a response wait (see the SD2
/// link): a node that answers at all has answered by then.
const STOP_GRACE: Duration = Duration::from_millis(20);
/// Frames already waiting before a transfer starts are dropped, at most this many (a busy
/// bus must not keep the link draining forever).
const DRAIN_MAX: usize = 64;
/// A family's words for its objects and its silent nodes.
#[derive(Debug, Clone, Copy)]
pub struct SdoNotation {
    /// `index 0x6041, subindex 0`, or a vendor's `C00099 (index 0x5F9C, subindex 0)`.
    pub object_text: fn(u16, u8) -> String,
    /// What to check when the node does not answer; also the family's `no_reply_advice`.
    pub no_reply_hint: &'static str,
}

/// CiA 301's own words: objects by index and subindex.
pub const CIA_301_NOTATION: SdoNotation = SdoNotation {
    object_text: index_text,
    no_reply_hint: "check the node id (--address), the bit rate, the CAN wiring and termination, and that the adapter is open on the right bus",
};

/// `index 0x6041, subindex 0`.
pub fn index_text(index: u16, subindex: u8) -> String {
    format!("index 0x{index:04X}, subindex {subindex}")
}

/// How the link waits and retries.
#[derive(Debug, Clone, Copy)]
pub struct SdoLinkConfig {
    /// Longest wait for each response.
    pub reply_timeout: Duration,
    /// Further attempts of a whole transfer after a timeout or a protocol error.
    pub retries: u32,
    pub notation: SdoNotation,
}

impl Default for SdoLinkConfig {
    fn default() -> Self {
        SdoLinkConfig {
            reply_timeout: Duration::from_secs(1),
            retries: 2,
            notation: CIA_301_NOTATION,
        }
    }
}

pub struct SdoLink {
    bus: SharedFrameBus,
    node: u8,
    config: SdoLinkConfig,
    /// Clock, observer, stop requests, counters and the listening every link shares.
    core: LinkCore,
    /// The node's heartbeat and EMCY frames seen between and during transfers.
    watch: NodeWatch,
}

/// A response that breaks the protocol: the frame and why.
type Refused = Refusal<CanFrame, String>;

impl SdoLink {
    pub fn new(bus: SharedFrameBus, clock: SharedClock, node: u8, config: SdoLinkConfig) -> Self {
        SdoLink {
            bus,
            node,
            config,
            core: LinkCore::new(clock, STOP_GRACE),
            watch: NodeWatch::new(node),
        }
    }

    pub fn node(&self) -> u8 {
        self.node
    }

    pub fn port(&self) -> &str {
        self.bus.name()
    }

    /// Opens the bus again after the adapter was lost.
    pub fn reopen(&mut self) -> Result<(), AccessError> {
        self.core.event("reopening the CAN adapter");
        self.bus.lock().reopen()?;
        Ok(())
    }

    /// Reads an object (expedited or segmented, as the node chooses).
    pub fn upload(&mut self, index: u16, subindex: u8) -> Result<Uploaded, AccessError> {
        let step = self.transfer("read", index, subindex, &|| {
            Some(SdoClient::upload(index, subindex))
        })?;
        match step {
            SdoStep::Uploaded(u) => Ok(u),
            other => Err(self.unexpected("read", index, subindex, &other)),
        }
    }

    /// Writes an object: expedited up to 4 bytes, segmented beyond.
    pub fn download(&mut self, index: u16, subindex: u8, data: &[u8]) -> Result<(), AccessError> {
        if SdoClient::download(index, subindex, data).is_none() {
            return Err(AccessError::Encode(format!(
                "an SDO write carries 1 to {} bytes, not {}",
                super::codec::MAX_TRANSFER,
                data.len()
            )));
        }
        let step = self.transfer("write", index, subindex, &|| {
            SdoClient::download(index, subindex, data)
        })?;
        match step {
            SdoStep::Downloaded => Ok(()),
            other => Err(self.unexpected("write", index, subindex, &other)),
        }
    }

    fn transfer(
        &mut self,
        operation: &'static str,
        index: u16,
        subindex: u8,
        start: &dyn Fn() -> Option<(SdoClient, SdoRequest)>,
    ) -> Result<SdoStep, AccessError> {
        let Some(first) = start() else {
            return Err(AccessError::Encode(
                "the value does not fit an SDO transfer".into(),
            ));
        };
        let first_frame = self.frame_of(&first.1);
        let shared = self.bus.clone();
        let mut guard = shared.lock();
        let bus: &mut dyn FrameBus = guard.as_mut();
        let plan = RetryPlan {
            reply_word: "response",
            line_word: "CAN adapter",
            ..RetryPlan::new(self.config.retries, Duration::ZERO, self.config.reply_timeout)
        };
        let step = plan
            .run(self, bus, |link, bus, number| {
                // Each attempt is the whole transfer again, from its first request.
                let (mut client, request) = first.clone();
                if number == 1 {
                    link.drain_owed(bus)?;
                }
                link.drain(bus).map_err(AttemptFailure::Transport)?;
                link.attempt(bus, &mut client, request)
            })
            .map_err(|unanswered| {
                // A node whose heartbeat went silent as well is lost, not merely silent to
                // this request: said as the heartbeat loss it is (the link is lost).
                if let Some(why) = self.watch.silent(self.core.clock.now()) {
                    return self.lost(format!(
                        "{why}; {} went unanswered as well",
                        self.describe(operation, index, subindex, Some(&first_frame))
                    ));
                }
                let text = ExchangeText {
                    port: self.bus.name().to_string(),
                    address: self.address(),
                    request: self.describe(operation, index, subindex, Some(&first_frame)),
                    hint: self.config.notation.no_reply_hint.to_string(),
                };
                unanswered.into_error(text, plan.reply_timeout, |r| (r.reply.to_candump(), r.problem))
            })?;
        match step {
            // The node's answer: not retried.
            SdoStep::Aborted(code) => Err(self.refused(operation, index, subindex, code)),
            SdoStep::TooLong { problem, .. } => Err(AccessError::UnexpectedReply {
                port: self.bus.name().to_string(),
                address: self.address(),
                request: self.describe(operation, index, subindex, Some(&first_frame)),
                detail: format!(
                    "{problem}; the transfer was aborted (read a value this long with a CANopen tool)"
                ),
            }),
            step => Ok(step),
        }
    }

    /// One run of a transfer from its first request to its end.
    fn attempt(
        &mut self,
        bus: &mut dyn FrameBus,
        client: &mut SdoClient,
        first: SdoRequest,
    ) -> Result<SdoStep, AttemptFailure<Refused>> {
        let mut request = first;
        let mut started = false;
        loop {
            self.send(bus, &request).map_err(AttemptFailure::Transport)?;
            self.core.stats.requests += 1;
            let step = loop {
                let frame = match self.wait(bus) {
                    Ok(f) => f,
                    Err(ReplyWait::Transport(e)) => return Err(AttemptFailure::Transport(e)),
                    Err(end) => {
                        if started {
                            // The node is in the middle of the transfer: free it.
                            let _ = self.send(bus, &client.timeout_abort());
                        }
                        return Err(end.into());
                    }
                };
                match client.on_bytes(frame.data()) {
                    SdoStep::Ignored(why) => {
                        self.core.stats.mismatched_replies += 1;
                        self.core
                            .event(&format!("passed over {}: {why}", frame.to_candump()));
                    }
                    // The node's whole answer, ended here and reported by the caller.
                    SdoStep::TooLong { problem, abort } => {
                        self.send(bus, &abort).map_err(AttemptFailure::Transport)?;
                        break SdoStep::TooLong { problem, abort };
                    }
                    SdoStep::Failed { problem, abort } => {
                        if let Some(abort) = abort {
                            self.send(bus, &abort).map_err(AttemptFailure::Transport)?;
                        }
                        self.core.stats.corrupt_replies += 1;
                        return Err(AttemptFailure::Bad(Refusal {
                            reply: frame,
                            problem,
                        }));
                    }
                    step => break step,
                }
            };
            match step {
                SdoStep::Send(next) => {
                    started = true;
                    request = next;
                }
                done => return Ok(done),
            }
        }
    }

    /// Waits for the next frame from this node, passing over every other frame.
    fn wait(&mut self, bus: &mut dyn FrameBus) -> Result<CanFrame, ReplyWait> {
        let sent = self.core.clock.now();
        let deadline = sent + self.config.reply_timeout;
        let expected = response_id(self.node);
        loop {
            let slice = self.core.next_slice(sent, deadline).ok_or(ReplyWait::Timeout)?;
            match bus.receive(slice) {
                Ok(frame) if frame.id == expected && !frame.extended => {
                    self.core.notify_frame(Direction::Received, &frame);
                    return Ok(frame);
                }
                Ok(other) => self.see(&other),
                Err(TransportError::Timeout { .. }) => {
                    if let Some(end) = self.core.after_quiet(sent, deadline) {
                        return Err(end);
                    }
                }
                Err(e) => return Err(ReplyWait::Transport(e)),
            }
        }
    }

    /// Drops what arrived before this transfer (a late response to an earlier attempt).
    fn drain(&mut self, bus: &mut dyn FrameBus) -> Result<(), TransportError> {
        let mut dropped = 0;
        for _ in 0..DRAIN_MAX {
            match bus.receive(Duration::ZERO) {
                Ok(f) if f.id == response_id(self.node) => dropped += 1,
                Ok(other) => self.see(&other),
                Err(TransportError::Timeout { .. }) => break,
                Err(e) => return Err(e),
            }
        }
        if dropped > 0 {
            self.core
                .event(&format!("dropped {dropped} late response(s) before sending"));
        }
        Ok(())
    }

    /// Before a transfer: waits for the responses earlier attempts that went unanswered
    /// still owe (the link core keeps the count and how long) and drops them, so a late
    /// answer for the same object is never taken for this transfer's; the node's other
    /// frames are seen as always.
    fn drain_owed(&mut self, bus: &mut dyn FrameBus) -> Result<(), AttemptFailure<Refused>> {
        let started = self.core.clock.now();
        let mut dropped = 0;
        while let Some(until) = self.core.late_reply_until() {
            if self.core.stop_pending() {
                return Err(AttemptFailure::Interrupted);
            }
            // Time passes between the readings: `until` may be behind us by now.
            let slice = until
                .saturating_sub(self.core.clock.now())
                .min(Duration::from_millis(10));
            match bus.receive(slice) {
                Ok(f) if f.id == response_id(self.node) && !f.extended => {
                    self.core.notify_frame(Direction::Received, &f);
                    self.core.late_reply_came();
                    dropped += 1;
                }
                Ok(other) => self.see(&other),
                Err(TransportError::Timeout { .. }) => {}
                Err(e) => return Err(AttemptFailure::Transport(e)),
            }
        }
        if self.core.clock.now() > started {
            let ms = (self.core.clock.now() - started).as_millis();
            self.core.event(&format!(
                "waited {ms} ms for late responses to earlier attempts before sending; dropped {dropped}"
            ));
        }
        Ok(())
    }

    /// A frame that is not this transfer's: the node's heartbeat or EMCY is noted, and
    /// what is worth a line goes to the trace and the events.
    fn see(&mut self, frame: &CanFrame) {
        let now = self.core.clock.now();
        if let Some(NodeNews::Said(text)) = self.watch.see(frame, now) {
            self.core.notify_frame(Direction::Received, frame);
            self.core.event(&text);
        }
    }

    /// Takes what is waiting on the bus and says why the node is lost, if it is.
    fn watch_bus(&mut self, bus: &mut dyn FrameBus) -> Result<Option<String>, TransportError> {
        self.drain(bus)?;
        Ok(self.watch.lost(self.core.clock.now()))
    }

    /// Between transfers (while a run waits): the node's heartbeat is looked at; a lost
    /// one is the link lost. Returns how long until it is worth looking again.
    pub fn check_node(&mut self) -> Result<Option<Duration>, AccessError> {
        let shared = self.bus.clone();
        let mut guard = shared.lock();
        if let Some(why) = self.watch_bus(guard.as_mut())? {
            return Err(self.lost(why));
        }
        Ok(self.watch.period())
    }

    /// The NMT state the node's heartbeat last showed (`None`: none seen), after taking
    /// what waits on the bus; a lost node is the link lost, as in [`Self::check_node`].
    pub fn nmt_state(&mut self) -> Result<Option<NmtState>, AccessError> {
        self.check_node()?;
        Ok(self.watch.state())
    }

    /// Sends the NMT command `command` to this node alone (`000#cs node`); never to every
    /// node (node 0). Unconfirmed by CiA 301: the node's next heartbeat shows the state.
    pub fn send_nmt(&mut self, command: NmtCommand) -> Result<(), AccessError> {
        let frame = CanFrame::new(NMT_ID, &[command.byte(), self.node])
            .ok_or_else(|| AccessError::Encode("an NMT command is 2 bytes".into()))?;
        let shared = self.bus.clone();
        let mut guard = shared.lock();
        guard.send(&frame)?;
        self.core.notify_frame(Direction::Sent, &frame);
        Ok(())
    }

    /// The fault the node reported by EMCY since the last call (see [`NodeWatch`]).
    pub fn reported_fault(&mut self) -> Option<String> {
        self.watch.take_reported()
    }

    fn lost(&self, why: String) -> AccessError {
        AccessError::Transport(TransportError::Io {
            port: self.bus.name().to_string(),
            detail: why,
        })
    }

    fn frame_of(&self, request: &SdoRequest) -> CanFrame {
        CanFrame::standard8(request_id(self.node), request.encode())
    }

    fn send(&mut self, bus: &mut dyn FrameBus, request: &SdoRequest) -> Result<(), TransportError> {
        let frame = self.frame_of(request);
        bus.send(&frame)?;
        self.core.notify_frame(Direction::Sent, &frame);
        Ok(())
    }

    fn address(&self) -> String {
        format!("node {}", self.node)
    }

    fn refused(&self, operation: &'static str, index: u16, subindex: u8, code: AbortCode) -> AccessError {
        AccessError::Refused {
            port: self.bus.name().to_string(),
            address: self.address(),
            operation,
            object: self.object_text(index, subindex),
            code: code.0,
            text: format!("SDO abort {code}"),
        }
    }

    fn unexpected(&self, operation: &'static str, index: u16, subindex: u8, step: &SdoStep) -> AccessError {
        AccessError::UnexpectedReply {
            port: self.bus.name().to_string(),
            address: self.address(),
            request: self.describe(operation, index, subindex, None),
            detail: format!("the transfer ended as {step:?}"),
        }
    }
}

impl CoreLink for SdoLink {
    crate::core_link_field!();
}

impl SdoLink {
    /// The object in the family's words: `C00099 (index 0x5F9C, subindex 0)`.
    pub fn object_text(&self, index: u16, subindex: u8) -> String {
        (self.config.notation.object_text)(index, subindex)
    }

    /// `` `60C#409C5F0000000000` (read C00099 (index 0x5F9C, subindex 0)) ``.
    fn describe(&self, operation: &str, index: u16, subindex: u8, first: Option<&CanFrame>) -> String {
        let what = format!("{operation} {}", self.object_text(index, subindex));
        match first {
            Some(f) => format!("`{}` ({what})", f.to_candump()),
            None => what,
        }
    }
}

#[cfg(test)]
#[path = "sdo_link_tests.rs"]
mod tests;
