//! The Control Techniques ANSI link: one message, one checked reply, over any transport
//! shared with the other drives on the line (locked for a whole exchange).
//!
//! Before every message the link keeps the turnaround pause and discards stale input; a
//! reply counts only if it answers this message (the parameter read, ACK/NAK to a write).
//! Corrupt, mismatched and missing replies are retried; a NAK is the drive's answer and is
//! not. Writes to a group (`G.0`) or to every drive (`0.0`) get no reply by the protocol,
//! so they are sent once and never retried. Must not know object names, units or states.
//!
//! Echo: a half-duplex RS485 adapter may hand our own message back before the drive's
//! answer. An exact echo is skipped and counted (see [`super::echo`]); an echo that breaks
//! off is dropped up to the byte that differs. The one ambiguous case is a lone `EOT` after
//! a message that starts with EOT: the drive's answer to a read of a missing parameter, or
//! the first byte of the echo. The link learns from the line: once an echo was seen, the
//! EOT is the echo's start; once a reply came with nothing before it, it is the drive's;
//! until then it is the drive's only when nothing follows it for `echo_wait` after the
//! message has left.

use super::codec::{
    show_bytes, split, DecodeError, NodeAddress, Parameter, Reply, Request, Sender, Split, EOT,
};
use super::echo::{match_echo, EchoMatch};
use super::link_config::{CtLinkConfig, BAUD_CHANGE_WAIT};
use crate::bus::{SharedTransport, Transport, TransportError};
use crate::clock::SharedClock;
use crate::drive::AccessError;
use crate::hex::to_hex;
use crate::link::{
    AttemptFailure, CoreLink, Direction, ExchangeText, LinkCore, Refusal, ReplyWait, RetryPlan,
};
use std::time::Duration;

/// A stop request does not cut short the first part of a reply wait: a drive that answers
/// at all has answered by then, so the exchange under way finishes.
const STOP_GRACE: Duration = Duration::from_millis(20);
/// What to check when a Control Techniques drive stays silent.
/// What to check when the drive does not answer; also the family's `no_reply_advice`.
pub(super) const NO_REPLY_HINT: &str = "check the cable (RS485 A/B), the baud rate and parity (--baud, --parity: the drive's serial mode) and the drive's serial address (--address G.U)";
/// What a NAK can mean; the drive does not say which.
const NAK_TEXT: &str = "the drive answered NAK: the value is out of range or invalid, the parameter is read-only or does not exist, or the message arrived damaged";

#[path = "ct_reply_wait.rs"]
mod reply_wait;
use reply_wait::EchoSeen;

pub struct CtLink {
    transport: SharedTransport,
    config: CtLinkConfig,
    /// Clock, observer, stop requests, counters and the listening every link shares.
    core: LinkCore,
    pending: Vec<u8>,
    /// When the line was last busy (our message or the drive's reply).
    quiet_from: Duration,
    /// What the line was seen to do: `Some(true)` it echoes our messages, `Some(false)` a
    /// reply came with nothing before it, `None` not known yet.
    line_echoes: Option<bool>,
    /// How much of the echo of its message the last attempt saw, for the no-reply message.
    attempt_echo: Option<EchoSeen>,
    /// The write that changed the drive's baud rate: from then on nothing is sent.
    rate_changed: Option<String>,
}

/// A reply that does not answer: its bytes and why.
type Refused = Refusal<Vec<u8>, ReplyProblem>;

impl CtLink {
    pub fn new(transport: SharedTransport, clock: SharedClock, config: CtLinkConfig) -> Self {
        CtLink {
            transport,
            core: LinkCore::new(clock, STOP_GRACE),
            config,
            pending: Vec::new(),
            quiet_from: Duration::ZERO,
            line_echoes: None,
            attempt_echo: None,
            rate_changed: None,
        }
    }

    pub fn port(&self) -> &str {
        self.transport.name()
    }

    pub fn config(&self) -> &CtLinkConfig {
        &self.config
    }

    /// Closes and opens the port again after it failed; what arrived before is dropped.
    pub fn reopen(&mut self) -> Result<(), AccessError> {
        self.pending.clear();
        self.line_echoes = None;
        self.core.event("reopening the port");
        self.transport.reopen()?;
        Ok(())
    }

    /// Sends `request` and returns the reply that answers it; `None` for a write to a
    /// group or every drive, which no drive answers.
    pub fn transact(&mut self, request: &Request) -> Result<Option<Reply>, AccessError> {
        if let Some(write) = &self.rate_changed {
            return Err(self.line_changed(request, format!(
                "{write} changed the drive's baud rate, so drivescript sends nothing more at the rate the port was opened with; restart drivescript with --baud set to the new rate"
            )));
        }
        let baud_write = match *request {
            Request::Write { parameter, value, .. } if Some(parameter) == self.config.baud_parameter => {
                Some(format!("the write of {parameter} = {value}"))
            }
            _ => None,
        };
        let reply = match (self.exchange(request), &baud_write) {
            // Whether the drive took it is not known: the next messages go out at the old
            // rate, which is right if it did not.
            (Err(AccessError::NoReply { port, address, request, attempts, timeout_ms, hint }), Some(write)) => {
                return Err(AccessError::NoReply {
                    port,
                    address,
                    request,
                    attempts,
                    timeout_ms,
                    hint: format!("{hint}; if {write} reached the drive, it now talks at the new baud rate: then restart drivescript with --baud set to it"),
                })
            }
            (result, _) => result?,
        };
        let (Some(write), None | Some(Reply::Accepted)) = (baud_write, reply) else {
            return Ok(reply);
        };
        // The drive answered at the old rate (or a group did not answer); it needs the wait
        // before it talks at the new one.
        // From when the write has left the line (a group write's bytes may still be on it).
        let from = self.quiet_from.max(self.core.clock.now());
        self.core.clock.sleep_until(from + BAUD_CHANGE_WAIT);
        self.quiet_from = self.core.clock.now();
        let ms = BAUD_CHANGE_WAIT.as_millis();
        self.core.event(&format!(
            "{write} was accepted: waited {ms} ms for the drive's new baud rate; nothing more is sent at the old one"
        ));
        let text = format!(
            "{write} was accepted{}, and drivescript waited {ms} ms as the drive needs after a baud-rate change: the drive now talks at the rate that value selects, not at the rate the port was opened with. Nothing more is sent to it; restart drivescript with --baud set to the new rate",
            if reply.is_none() { " (a group or global write: no drive answers)" } else { " (ACK)" }
        );
        self.rate_changed = Some(write);
        Err(self.line_changed(request, text))
    }

    fn line_changed(&self, request: &Request, text: String) -> AccessError {
        AccessError::LineChanged {
            port: self.transport.name().to_string(),
            address: address_text(request),
            text,
        }
    }

    /// One message and the reply that answers it, with the retries.
    fn exchange(&mut self, request: &Request) -> Result<Option<Reply>, AccessError> {
        let bytes = request.encode().map_err(|e| AccessError::Encode(e.to_string()))?;
        let target = target_of(request);
        let shared = self.transport.clone();
        let mut line = shared.lock();
        let t: &mut dyn Transport = line.as_mut();
        if target.is_some_and(NodeAddress::is_broadcast) {
            self.send(t, &bytes)?;
            self.core
                .event("group or global write: no drive answers, so it is sent once and not repeated");
            // The line is quiet once the message has left it and, where the adapter may echo,
            // once its echo is back too; the next message's discard then takes the whole echo,
            // whose tail would otherwise read like a value reply of the same parameter.
            let echo = match self.line_echoes {
                Some(false) => Duration::ZERO,
                _ => self.config.echo_wait,
            };
            self.quiet_from = self.core.clock.now() + t.still_sending() + echo;
            return Ok(None);
        }
        let c = &self.config;
        let plan = RetryPlan::new(c.retries, c.settle, c.reply_timeout);
        plan.run(self, t, |link, t, _| {
            link.send(t, &bytes).map_err(AttemptFailure::Transport)?;
            match link.await_reply(t, request, &bytes) {
                Ok(reply) => {
                    link.quiet_from = link.core.clock.now();
                    Ok(Some(reply))
                }
                Err(AttemptFailure::Interrupted) => {
                    // The next message (the safe stop's) waits for the line: the drive may
                    // still answer this one.
                    link.quiet_from = link.quiet_from.max(link.core.clock.now() + t.still_sending());
                    Err(AttemptFailure::Interrupted)
                }
                Err(failure) => Err(failure),
            }
        })
        .map_err(|unanswered| {
            let text = ExchangeText {
                port: self.transport.name().to_string(),
                address: address_text(request),
                request: describe(request, &bytes),
                hint: self.no_reply_hint(),
            };
            unanswered.into_error(text, plan.reply_timeout, |r| {
                (
                    format!("`{}` ({})", to_hex(&r.reply), show_bytes(&r.reply)),
                    r.problem.to_string(),
                )
            })
        })
    }

    /// The turnaround pause, stale input dropped, then the message.
    fn send(&mut self, t: &mut dyn Transport, bytes: &[u8]) -> Result<(), TransportError> {
        self.core
            .clock
            .sleep_until(self.quiet_from + self.config.turnaround);
        self.core.drop_stale_input(t, self.pending.len())?;
        self.pending.clear();
        t.write_all(bytes)?;
        self.core.stats.requests += 1;
        self.core.notify(Direction::Sent, bytes);
        Ok(())
    }
}

impl CoreLink for CtLink {
    crate::core_link_field!();
}

/// Why a reply does not answer the message (the problem of a `Refusal`, shown as it is).
#[derive(Debug, thiserror::Error)]
pub(super) enum ReplyProblem {
    #[error("reply for parameter {got}, expected {expected}")]
    OtherParameter { got: Parameter, expected: Parameter },
    #[error("{reply} to a read (expected the value or EOT)")]
    ToRead { reply: &'static str },
    #[error("{reply} to a write (expected ACK or NAK)")]
    ToWrite { reply: &'static str },
    #[error("{reply} to a short read command")]
    ToShortRead { reply: &'static str },
    /// Not a valid message at all.
    #[error(transparent)]
    Corrupt(#[from] DecodeError),
}

/// Whether `reply` is an answer to `request`: a read gets the value of the same parameter
/// or EOT, a short read (ACK, NAK, BS) a value or EOT, a write ACK or NAK.
fn answers(request: &Request, reply: &Reply) -> Result<(), ReplyProblem> {
    match (request, reply) {
        (Request::Read { parameter, .. }, Reply::Value { parameter: got, .. }) if got != parameter => {
            Err(ReplyProblem::OtherParameter {
                got: *got,
                expected: *parameter,
            })
        }
        (Request::Read { .. }, Reply::Value { .. } | Reply::NoSuchParameter) => Ok(()),
        (Request::Write { .. }, Reply::Accepted | Reply::Refused) => Ok(()),
        (Request::Read { .. }, other) => Err(ReplyProblem::ToRead { reply: kind(other) }),
        (Request::Write { .. }, other) => Err(ReplyProblem::ToWrite { reply: kind(other) }),
        // A short command's answer is a normal read reply: a value, or EOT for a parameter
        // the drive does not have.
        (_, Reply::Value { .. } | Reply::NoSuchParameter) => Ok(()),
        (_, other) => Err(ReplyProblem::ToShortRead { reply: kind(other) }),
    }
}

fn kind(reply: &Reply) -> &'static str {
    match reply {
        Reply::Value { .. } => "a value",
        Reply::Accepted => "ACK",
        Reply::Refused => "NAK",
        Reply::NoSuchParameter => "EOT",
    }
}

fn target_of(request: &Request) -> Option<NodeAddress> {
    match *request {
        Request::Read { address, .. } => Some(address),
        Request::Write { address, .. } => address,
        _ => None,
    }
}

fn address_text(request: &Request) -> String {
    target_of(request).map_or_else(|| "(addressed last)".to_string(), |a| a.to_string())
}

/// `` `04 31 31 …` (EOT 11220121 ENQ: read #1.21) ``.
fn describe(request: &Request, bytes: &[u8]) -> String {
    let what = match request {
        Request::Read { parameter, .. } => format!("read {parameter}"),
        Request::Write { parameter, value, .. } => format!("write {parameter} = {value}"),
        Request::ReadAgain => "read again".into(),
        Request::ReadNext => "read next".into(),
        Request::ReadPrevious => "read previous".into(),
    };
    format!("`{}` ({}: {what})", to_hex(bytes), show_bytes(bytes))
}

/// The refusal text of a NAK, for object access.
pub fn nak_text() -> &'static str {
    NAK_TEXT
}

#[cfg(test)]
#[path = "ct_link_tests.rs"]
mod tests;
