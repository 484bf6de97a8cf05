//! The Lenze 931 link: one request line, one checked reply line, over any transport.
//!
//! RS232 point to point; the PC asks, the drive answers one line. Before every request,
//! input is discarded (a late reply to an earlier attempt must not be taken for this one).
//! An echo of the request (a converter or terminal that echoes) is skipped, stray LF is
//! dropped, and a line that is garbage or too long is a bad reply, with the reason.
//!
//! Retries: a read is sent again after a timeout or a bad reply. A write (`OW`) whose
//! reply was lost is never sent again blind: the object is read back first, and the write
//! is repeated only when the drive does not hold the value; when the read-back fails too,
//! the link stops and says that the outcome is unknown. Service commands that must not run
//! twice (`SAVE!`, `SEP!`, `INIT!`, `RESET!`, `BAUD`) and SDO writes are sent once.
//! Must not know object names, units or states.

use super::codec::{check_reply, DecodeError, LineExtractor, ObjectCommand, Reply, Request};
use crate::bus::{SharedTransport, Transport, TransportError};
use crate::clock::SharedClock;
use crate::drive::AccessError;
use crate::link::{
    AttemptFailure, CoreLink, Direction, ExchangeText, LinkCore, Refusal, RetryPlan, Unanswered,
};
use std::time::Duration;

/// A stop request does not cut short the first part of a reply wait, so the exchange under
/// way finishes (a 9600-baud reply of 14 characters takes about 15 ms on the wire).
const STOP_GRACE: Duration = Duration::from_millis(30);
/// What to check when a 931 stays silent.
/// What to check when the drive does not answer; also the family's `no_reply_advice`.
pub(super) const NO_REPLY_HINT: &str = "check the RS232 cable (TxD/RxD crossed), the baud rate (the 931 ships at 9600 8N1) and that the drive is powered";

/// How the link waits and retries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinkConfig {
    /// How long to wait for a reply line.
    pub reply_timeout: Duration,
    /// Further attempts after a timeout or a bad reply (writes: only after a read-back).
    pub retries: u32,
    /// Before a retry the line is listened to for this long and whatever arrives is
    /// dropped: the protocol has no sequence numbers.
    pub settle: Duration,
}

impl Default for LinkConfig {
    fn default() -> Self {
        LinkConfig {
            reply_timeout: Duration::from_secs(1),
            retries: 2,
            settle: Duration::from_millis(30),
        }
    }
}

pub struct LenzeLink {
    transport: SharedTransport,
    config: LinkConfig,
    extractor: LineExtractor,
    /// Clock, observer, stop requests, counters and the listening every link shares.
    core: LinkCore,
}

/// A reply line that does not answer: the line and why.
type Refused = Refusal<String, DecodeError>;

/// Why a request that changes the drive is sent only once.
const SENT_ONCE: &str =
    "it is not sent again, because doing it twice is not the same as once; check the drive before repeating it";

impl LenzeLink {
    pub fn new(transport: SharedTransport, clock: SharedClock, config: LinkConfig) -> Self {
        LenzeLink {
            transport,
            core: LinkCore::new(clock, STOP_GRACE),
            config,
            extractor: LineExtractor::new(),
        }
    }

    pub fn port(&self) -> &str {
        self.transport.name()
    }

    /// Closes and opens the port again after it failed; what arrived before is dropped.
    pub fn reopen(&mut self) -> Result<(), AccessError> {
        self.extractor.clear();
        self.core.event("reopening the port");
        self.transport.reopen()?;
        Ok(())
    }

    /// Sends `request` and returns the reply that answers it, retrying as the module docs
    /// say. The line is locked for the whole exchange, read-backs included.
    pub fn exchange(&mut self, request: &Request) -> Result<Reply, AccessError> {
        let shared = self.transport.clone();
        let mut line = shared.lock();
        let t: &mut dyn Transport = line.as_mut();
        match request {
            Request::Write { object, value } => self.write(t, request, *object, *value),
            r if r.changes_the_drive() => self.exchange_once(t, request),
            _ => self.read(t, request),
        }
    }

    fn plan(&self, retries: u32) -> RetryPlan {
        RetryPlan::new(retries, self.config.settle, self.config.reply_timeout)
    }

    fn read(&mut self, t: &mut dyn Transport, request: &Request) -> Result<Reply, AccessError> {
        self.plan(self.config.retries)
            .run(self, t, |link, t, _| link.attempt(t, request))
            .map_err(|u| self.unanswered(u, request, None))
    }

    fn exchange_once(&mut self, t: &mut dyn Transport, request: &Request) -> Result<Reply, AccessError> {
        self.plan(0)
            .run(self, t, |link, t, _| link.attempt(t, request))
            .map_err(|u| self.unanswered(u, request, Some(SENT_ONCE)))
    }

    /// A write, repeated only after a read-back showed that the drive does not hold the
    /// value (see the module docs).
    fn write(
        &mut self,
        t: &mut dyn Transport,
        request: &Request,
        object: u16,
        value: u32,
    ) -> Result<Reply, AccessError> {
        let plan = self.plan(self.config.retries);
        let read_back = Request::read(ObjectCommand::Read, object);
        plan.run_with_step(
            self,
            t,
            |link, t| link.read_back(t, &plan, request, &read_back, object, value),
            |link, t, _| link.attempt(t, request),
        )
        .map_err(|u| self.unanswered(u, request, None))
    }

    /// After a write whose reply was lost: `Some` when the drive holds the value (the write
    /// took effect), `None` when the write is to be sent again.
    fn read_back(
        &mut self,
        t: &mut dyn Transport,
        plan: &RetryPlan,
        request: &Request,
        read_back: &Request,
        object: u16,
        value: u32,
    ) -> Result<Option<Reply>, AccessError> {
        self.core.settle(t, self.config.settle)?;
        self.core.event(&format!(
            "the reply to {} was lost: reading object 0x{object:04X} back before sending the write again",
            request.text()
        ));
        let result = self.attempt(t, read_back);
        plan.record(&mut self.core, &result);
        let why = match result {
            Ok(Reply::Value { value: held, .. }) if held == value => {
                self.core.event(&format!(
                    "object 0x{object:04X} holds 0x{held:08X}: the write took effect; not sent again"
                ));
                return Ok(Some(Reply::Ok));
            }
            Ok(Reply::Value { value: held, .. }) => {
                self.core.event(&format!(
                    "object 0x{object:04X} holds 0x{held:08X}, not 0x{value:08X}: sending the write again"
                ));
                return Ok(None);
            }
            Ok(other) => format!(
                "the read-back {} was answered with {}",
                read_back.text(),
                other.text()
            ),
            Err(AttemptFailure::Timeout { .. }) => {
                format!("the read-back {} got no reply either", read_back.text())
            }
            Err(AttemptFailure::Bad(r) | AttemptFailure::Discarded(r)) => format!(
                "the read-back {} got the bad reply {:?} ({})",
                read_back.text(),
                r.reply,
                r.problem
            ),
            Err(AttemptFailure::Transport(e)) => return Err(AccessError::Transport(e)),
            Err(AttemptFailure::Interrupted) => {
                return Err(self.unanswered(Unanswered::Interrupted, request, None))
            }
        };
        Err(self.unknown_outcome(request, &why))
    }

    fn attempt(
        &mut self,
        t: &mut dyn Transport,
        request: &Request,
    ) -> Result<Reply, AttemptFailure<Refused>> {
        let bytes = request.encode();
        self.flush_input(t).map_err(AttemptFailure::Transport)?;
        t.write_all(&bytes).map_err(AttemptFailure::Transport)?;
        self.core.stats.requests += 1;
        self.core.notify(Direction::Sent, &bytes);
        self.await_reply(t, request)
    }

    fn await_reply(
        &mut self,
        t: &mut dyn Transport,
        request: &Request,
    ) -> Result<Reply, AttemptFailure<Refused>> {
        let (sent, deadline) = self.core.reply_window(t, self.config.reply_timeout);
        let echo = request.text();
        // An SDO write is answered with its own text: the first copy is taken as the reply.
        let echo_possible = !matches!(request, Request::SdoWrite { .. });
        let mut dropped = None;
        loop {
            while let Some(line) = self.extractor.next_line() {
                if !line.bytes.is_empty() {
                    let mut shown = line.bytes.clone();
                    shown.push(super::codec::CR);
                    self.core.notify(Direction::Received, &shown);
                }
                let text = match line.text {
                    Ok(text) => text,
                    Err(problem) => {
                        self.core.stats.corrupt_replies += 1;
                        let shown = String::from_utf8_lossy(&line.bytes).into_owned();
                        return Err(AttemptFailure::Bad(Refusal {
                            reply: shown,
                            problem,
                        }));
                    }
                };
                if echo_possible && text == echo {
                    self.core.event("skipped the echo of the request");
                    continue;
                }
                let reply = match Reply::parse_for(request, &text) {
                    Ok(r) => r,
                    Err(problem) => {
                        self.core.stats.corrupt_replies += 1;
                        return Err(AttemptFailure::Bad(Refusal { reply: text, problem }));
                    }
                };
                if let Err(problem) = check_reply(request, &reply) {
                    // Another request's answer (most often a late one): never this one's.
                    self.core.stats.mismatched_replies += 1;
                    self.core.event(&format!(
                        "dropped a reply that answers another request: {problem}"
                    ));
                    dropped = Some(Refusal { reply: text, problem });
                    continue;
                }
                return Ok(reply);
            }
            match self.core.read_reply(t, sent, deadline) {
                Ok(bytes) => self.extractor.push(bytes),
                Err(wait) => return Err(AttemptFailure::after_wait(wait, dropped)),
            }
        }
    }

    fn flush_input(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        self.core.drop_stale_input(t, self.extractor.pending())?;
        self.extractor.clear();
        Ok(())
    }

    /// The error of an exchange that got no answer; `note` says why it was not repeated.
    fn unanswered(
        &self,
        unanswered: Unanswered<Refused>,
        request: &Request,
        note: Option<&str>,
    ) -> AccessError {
        let text = ExchangeText {
            port: self.port().to_string(),
            address: "RS232".into(),
            request: describe(request),
            hint: match note {
                Some(n) => format!("{n}; {NO_REPLY_HINT}"),
                None => NO_REPLY_HINT.to_string(),
            },
        };
        unanswered.into_error(text, self.config.reply_timeout, |r| {
            let problem = match note {
                Some(n) => format!("{}; {n}", r.problem),
                None => r.problem.to_string(),
            };
            (format!("{:?}", r.reply), problem)
        })
    }

    /// A write whose reply was lost and whose read-back failed: whether the drive holds
    /// the value is unknown, and the write is not repeated blind.
    fn unknown_outcome(&self, request: &Request, why: &str) -> AccessError {
        AccessError::NoReply {
            port: self.port().to_string(),
            address: "RS232".into(),
            request: describe(request),
            attempts: 1,
            timeout_ms: self.config.reply_timeout.as_millis(),
            hint: format!(
                "{why}, so whether the drive stored the value is unknown and the write was not sent again; read the object before writing it again; {NO_REPLY_HINT}"
            ),
        }
    }
}

impl CoreLink for LenzeLink {
    crate::core_link_field!();
}

/// `` `OR:0011` (read object 0x0011) ``.
fn describe(request: &Request) -> String {
    format!("`{}` ({})", request.text(), request.describe())
}

#[cfg(test)]
#[path = "lenze_link_tests.rs"]
mod tests;
