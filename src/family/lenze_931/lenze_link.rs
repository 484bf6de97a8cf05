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
use crate::link::{Direction, LinkCore, LinkStats, ReplyWait, TelegramObserver};
use crate::stop_request::StopRequests;
use std::sync::Arc;
use std::time::Duration;

/// A stop request does not cut short the first part of a reply wait, so the exchange under
/// way finishes (a 9600-baud reply of 14 characters takes about 15 ms on the wire).
const STOP_GRACE: Duration = Duration::from_millis(30);
/// What to check when a 931 stays silent.
const NO_REPLY_HINT: &str = "check the RS232 cable (TxD/RxD crossed), the baud rate (the 931 ships at 9600 8N1) and that the drive is powered";

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

/// Why one attempt did not produce a reply.
enum AttemptFailure {
    Timeout,
    Bad { line: String, problem: DecodeError },
    Interrupted,
    Transport(TransportError),
}

impl LenzeLink {
    pub fn new(transport: SharedTransport, clock: SharedClock, config: LinkConfig) -> Self {
        LenzeLink {
            transport,
            core: LinkCore::new(clock, STOP_GRACE),
            config,
            extractor: LineExtractor::new(),
        }
    }

    pub fn set_stop_requests(&mut self, stop: Arc<StopRequests>) {
        self.core.set_stop_requests(stop);
    }

    pub fn set_observer(&mut self, observer: Box<dyn TelegramObserver>) {
        self.core.set_observer(observer);
    }

    pub fn port(&self) -> &str {
        self.transport.name()
    }

    pub fn clock(&self) -> &SharedClock {
        &self.core.clock
    }

    pub fn stats(&self) -> LinkStats {
        self.core.stats
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

    fn read(&mut self, t: &mut dyn Transport, request: &Request) -> Result<Reply, AccessError> {
        let attempts = self.config.retries + 1;
        let mut last_bad = None;
        for attempt in 1..=attempts {
            if attempt > 1 {
                self.before_retry(t, request, attempt)?;
            }
            match self.attempt(t, request) {
                Ok(reply) => return Ok(reply),
                Err(AttemptFailure::Bad { line, problem }) => last_bad = Some((line, problem)),
                Err(AttemptFailure::Timeout) => {}
                Err(f) => return Err(self.fatal(f, request)),
            }
        }
        Err(self.gave_up(request, attempts, last_bad, None))
    }

    fn exchange_once(&mut self, t: &mut dyn Transport, request: &Request) -> Result<Reply, AccessError> {
        match self.attempt(t, request) {
            Ok(reply) => Ok(reply),
            Err(AttemptFailure::Bad { line, problem }) => Err(self.gave_up(
                request,
                1,
                Some((line, problem)),
                Some("it is not sent again, because doing it twice is not the same as once; check the drive before repeating it"),
            )),
            Err(AttemptFailure::Timeout) => Err(self.gave_up(
                request,
                1,
                None,
                Some("it is not sent again, because doing it twice is not the same as once; check the drive before repeating it"),
            )),
            Err(f) => Err(self.fatal(f, request)),
        }
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
        let attempts = self.config.retries + 1;
        let mut last_bad = None;
        let read_back = Request::read(ObjectCommand::Read, object);
        for attempt in 1..=attempts {
            if attempt > 1 {
                self.before_retry(t, request, attempt)?;
            }
            match self.attempt(t, request) {
                Ok(reply) => return Ok(reply),
                Err(AttemptFailure::Bad { line, problem }) => last_bad = Some((line, problem)),
                Err(AttemptFailure::Timeout) => {}
                Err(f) => return Err(self.fatal(f, request)),
            }
            if attempt == attempts {
                break;
            }
            self.core.settle(t, self.config.settle)?;
            self.core.event(&format!(
                "the reply to {} was lost: reading object 0x{object:04X} back before sending the write again",
                request.text()
            ));
            match self.attempt(t, &read_back) {
                Ok(Reply::Value { value: held, .. }) if held == value => {
                    self.core.event(&format!(
                        "object 0x{object:04X} holds 0x{held:08X}: the write took effect; not sent again"
                    ));
                    return Ok(Reply::Ok);
                }
                Ok(Reply::Value { value: held, .. }) => {
                    self.core.event(&format!("object 0x{object:04X} holds 0x{held:08X}, not 0x{value:08X}: sending the write again"));
                }
                Ok(other) => {
                    return Err(self.unknown_outcome(
                        request,
                        &format!(
                            "the read-back {} was answered with {}",
                            read_back.text(),
                            other.text()
                        ),
                    ));
                }
                Err(AttemptFailure::Timeout) => {
                    return Err(self.unknown_outcome(
                        request,
                        &format!("the read-back {} got no reply either", read_back.text()),
                    ));
                }
                Err(AttemptFailure::Bad { line, problem }) => {
                    return Err(self.unknown_outcome(
                        request,
                        &format!(
                            "the read-back {} got the bad reply {line:?} ({problem})",
                            read_back.text()
                        ),
                    ));
                }
                Err(f) => return Err(self.fatal(f, request)),
            }
        }
        Err(self.gave_up(request, attempts, last_bad, None))
    }

    fn before_retry(
        &mut self,
        t: &mut dyn Transport,
        request: &Request,
        attempt: u32,
    ) -> Result<(), AccessError> {
        if self.core.stop_pending() {
            return Err(self.interrupted(request));
        }
        self.core.stats.retries += 1;
        self.core.settle(t, self.config.settle)?;
        self.core
            .event(&format!("retry {} of {}", attempt - 1, self.config.retries));
        Ok(())
    }

    fn attempt(&mut self, t: &mut dyn Transport, request: &Request) -> Result<Reply, AttemptFailure> {
        let bytes = request.encode();
        if let Err(e) = self.flush_input(t) {
            return Err(AttemptFailure::Transport(e));
        }
        t.write_all(&bytes).map_err(AttemptFailure::Transport)?;
        self.core.stats.requests += 1;
        self.core.notify(Direction::Sent, &bytes);
        let result = self.await_reply(t, request);
        match &result {
            Ok(_) => self.core.stats.replies += 1,
            Err(AttemptFailure::Timeout) => {
                self.core.stats.timeouts += 1;
                let ms = self.config.reply_timeout.as_millis();
                self.core.event(&format!("no reply within {ms} ms"));
            }
            Err(AttemptFailure::Bad { problem, .. }) => self.core.event(&format!("reply refused: {problem}")),
            Err(AttemptFailure::Transport(e)) => self.core.event(&format!("transport failed: {e}")),
            Err(AttemptFailure::Interrupted) => self.core.event("stop requested while waiting for the reply"),
        }
        result
    }

    fn await_reply(&mut self, t: &mut dyn Transport, request: &Request) -> Result<Reply, AttemptFailure> {
        // The reply timeout and the stop grace count from when the request has left the line.
        let sent = self.core.clock.now() + t.still_sending();
        let deadline = sent + self.config.reply_timeout;
        let echo = request.text();
        // An SDO write is answered with its own text: the first copy is taken as the reply.
        let echo_possible = !matches!(request, Request::SdoWrite { .. });
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
                        return Err(AttemptFailure::Bad { line: shown, problem });
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
                        return Err(AttemptFailure::Bad { line: text, problem });
                    }
                };
                if let Err(problem) = check_reply(request, &reply) {
                    self.core.stats.mismatched_replies += 1;
                    return Err(AttemptFailure::Bad { line: text, problem });
                }
                return Ok(reply);
            }
            match self.core.read_reply(t, sent, deadline) {
                Ok(bytes) => self.extractor.push(bytes),
                Err(ReplyWait::Timeout) => return Err(AttemptFailure::Timeout),
                Err(ReplyWait::Interrupted) => return Err(AttemptFailure::Interrupted),
                Err(ReplyWait::Transport(e)) => return Err(AttemptFailure::Transport(e)),
            }
        }
    }

    fn flush_input(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let dropped = t.discard_input()? + self.extractor.pending();
        self.extractor.clear();
        if dropped > 0 {
            self.core
                .event(&format!("discarded {dropped} stale byte(s) before sending"));
        }
        Ok(())
    }

    fn fatal(&mut self, failure: AttemptFailure, request: &Request) -> AccessError {
        match failure {
            AttemptFailure::Transport(e) => AccessError::Transport(e),
            _ => self.interrupted(request),
        }
    }

    fn interrupted(&self, request: &Request) -> AccessError {
        AccessError::Interrupted {
            port: self.port().to_string(),
            address: "RS232".into(),
            request: describe(request),
        }
    }

    fn gave_up(
        &self,
        request: &Request,
        attempts: u32,
        last_bad: Option<(String, DecodeError)>,
        note: Option<&str>,
    ) -> AccessError {
        let port = self.port().to_string();
        match last_bad {
            Some((line, problem)) => AccessError::BadReply {
                port,
                address: "RS232".into(),
                request: describe(request),
                reply: format!("{line:?}"),
                problem: match note {
                    Some(n) => format!("{problem}; {n}"),
                    None => problem.to_string(),
                },
                attempts,
            },
            None => AccessError::NoReply {
                port,
                address: "RS232".into(),
                request: describe(request),
                attempts,
                timeout_ms: self.config.reply_timeout.as_millis(),
                hint: match note {
                    Some(n) => format!("{n}; {NO_REPLY_HINT}"),
                    None => NO_REPLY_HINT.to_string(),
                },
            },
        }
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

/// `` `OR:0011` (read object 0x0011) ``.
fn describe(request: &Request) -> String {
    format!("`{}` ({})", request.text(), request.describe())
}

#[cfg(test)]
#[path = "lenze_link_tests.rs"]
mod tests;
