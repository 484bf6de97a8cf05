//! The Control Techniques ANSI link: one message, one checked reply, over any transport
//! shared with the other drives on the line (locked for a whole exchange).
//!
//! Before every message the link keeps the turnaround pause and discards stale input; a
//! reply counts only if it answers this message (the parameter read, ACK/NAK to a write).
//! Corrupt, mismatched and missing replies are retried; a NAK is the drive's answer and is
//! not. Writes to a group (`G.0`) or to every drive (`0.0`) get no reply by the protocol,
//! so they are sent once and never retried. Must not know object names, units or states.

use super::codec::{show_bytes, split, NodeAddress, Reply, Request, Sender, Split};
use super::link_config::CtLinkConfig;
use crate::bus::{SharedTransport, Transport, TransportError};
use crate::clock::SharedClock;
use crate::drive::AccessError;
use crate::hex::to_hex;
use crate::link::{Direction, LinkCore, LinkStats, ReplyWait, TelegramObserver};
use crate::stop_request::StopRequests;
use std::sync::Arc;
use std::time::Duration;

/// A stop request does not cut short the first part of a reply wait: a drive that answers
/// at all has answered by then, so the exchange under way finishes.
const STOP_GRACE: Duration = Duration::from_millis(20);
/// What to check when a Control Techniques drive stays silent.
const NO_REPLY_HINT: &str = "check the cable (RS485 A/B), the baud rate and parity (--baud, --parity: the drive's serial mode), the drive's serial address (--address G.U), and that the echo of the RS485 adapter is off";
/// What a NAK can mean; the drive does not say which.
const NAK_TEXT: &str = "the drive answered NAK: the value is out of range or invalid, the parameter is read-only or does not exist, or the message arrived damaged";

pub struct CtLink {
    transport: SharedTransport,
    config: CtLinkConfig,
    /// Clock, observer, stop requests, counters and the listening every link shares.
    core: LinkCore,
    pending: Vec<u8>,
    /// When the line was last busy (our message or the drive's reply).
    quiet_from: Duration,
}

/// Why one attempt did not produce a reply.
enum AttemptFailure {
    Timeout,
    Refused { bytes: Vec<u8>, problem: String },
    Interrupted,
    Transport(TransportError),
}

impl CtLink {
    pub fn new(transport: SharedTransport, clock: SharedClock, config: CtLinkConfig) -> Self {
        CtLink {
            transport,
            core: LinkCore::new(clock, STOP_GRACE),
            config,
            pending: Vec::new(),
            quiet_from: Duration::ZERO,
        }
    }

    pub fn set_observer(&mut self, observer: Box<dyn TelegramObserver>) {
        self.core.set_observer(observer);
    }

    /// Lets stop requests end reply waits and retries early (see [`STOP_GRACE`]).
    pub fn set_stop_requests(&mut self, stop: Arc<StopRequests>) {
        self.core.set_stop_requests(stop);
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

    pub fn config(&self) -> &CtLinkConfig {
        &self.config
    }

    /// Closes and opens the port again after it failed; what arrived before is dropped.
    pub fn reopen(&mut self) -> Result<(), AccessError> {
        self.pending.clear();
        self.core.event("reopening the port");
        self.transport.reopen()?;
        Ok(())
    }

    /// Sends `request` and returns the reply that answers it; `None` for a write to a
    /// group or every drive, which no drive answers.
    pub fn transact(&mut self, request: &Request) -> Result<Option<Reply>, AccessError> {
        let bytes = request.encode().map_err(AccessError::Encode)?;
        let target = target_of(request);
        let shared = self.transport.clone();
        let mut line = shared.lock();
        let t: &mut dyn Transport = line.as_mut();
        if target.is_some_and(NodeAddress::is_broadcast) {
            self.send(t, &bytes)?;
            self.core
                .event("group or global write: no drive answers, so it is sent once and not repeated");
            self.quiet_from = self.core.clock.now();
            return Ok(None);
        }
        let attempts = self.config.retries + 1;
        let mut last_refused: Option<(Vec<u8>, String)> = None;
        for attempt in 1..=attempts {
            if attempt > 1 {
                if self.core.stop_pending() {
                    return Err(self.interrupted(request, &bytes));
                }
                self.core.stats.retries += 1;
                self.core.settle(t, self.config.settle)?;
                self.core
                    .event(&format!("retry {} of {}", attempt - 1, self.config.retries));
            }
            self.send(t, &bytes)?;
            match self.await_reply(t, request) {
                Ok(reply) => {
                    self.core.stats.replies += 1;
                    self.quiet_from = self.core.clock.now();
                    return Ok(Some(reply));
                }
                Err(AttemptFailure::Timeout) => {
                    self.core.stats.timeouts += 1;
                    let ms = self.config.reply_timeout.as_millis();
                    self.core.event(&format!("no reply within {ms} ms"));
                }
                Err(AttemptFailure::Refused { bytes, problem }) => {
                    self.core.event(&format!("reply refused: {problem}"));
                    last_refused = Some((bytes, problem));
                }
                Err(AttemptFailure::Transport(e)) => {
                    self.core.event(&format!("transport failed: {e}"));
                    return Err(AccessError::Transport(e));
                }
                Err(AttemptFailure::Interrupted) => {
                    self.core.event("stop requested while waiting for the reply");
                    return Err(self.interrupted(request, &bytes));
                }
            }
        }
        let port = self.transport.name().to_string();
        let address = address_text(request);
        let request_text = describe(request, &bytes);
        Err(match last_refused {
            Some((reply, problem)) => AccessError::BadReply {
                port,
                address,
                request: request_text,
                reply: format!("`{}` ({})", to_hex(&reply), show_bytes(&reply)),
                problem,
                attempts,
            },
            None => AccessError::NoReply {
                port,
                address,
                request: request_text,
                attempts,
                timeout_ms: self.config.reply_timeout.as_millis(),
                hint: NO_REPLY_HINT.to_string(),
            },
        })
    }

    /// The turnaround pause, stale input dropped, then the message.
    fn send(&mut self, t: &mut dyn Transport, bytes: &[u8]) -> Result<(), AccessError> {
        self.core
            .clock
            .sleep_until(self.quiet_from + self.config.turnaround);
        let dropped = t.discard_input()? + self.pending.len();
        self.pending.clear();
        if dropped > 0 {
            self.core
                .event(&format!("discarded {dropped} stale byte(s) before sending"));
        }
        t.write_all(bytes)?;
        self.core.stats.requests += 1;
        self.core.notify(Direction::Sent, bytes);
        Ok(())
    }

    fn await_reply(&mut self, t: &mut dyn Transport, request: &Request) -> Result<Reply, AttemptFailure> {
        let sent = self.core.clock.now();
        let deadline = sent + t.still_sending() + self.config.reply_timeout;
        loop {
            loop {
                match split(&self.pending, Sender::Drive) {
                    Split::Incomplete => break,
                    Split::Noise(n) => {
                        self.pending.drain(..n);
                        self.core.event(&format!("skipped {n} byte(s) of line noise"));
                    }
                    Split::Message(n) => {
                        let bytes: Vec<u8> = self.pending.drain(..n).collect();
                        self.core.notify(Direction::Received, &bytes);
                        return match Reply::decode(&bytes) {
                            Ok(reply) => match answers(request, &reply) {
                                Ok(()) => Ok(reply),
                                Err(problem) => {
                                    self.core.stats.mismatched_replies += 1;
                                    Err(AttemptFailure::Refused { bytes, problem })
                                }
                            },
                            Err(problem) => {
                                self.core.stats.corrupt_replies += 1;
                                Err(AttemptFailure::Refused {
                                    bytes,
                                    problem: problem.to_string(),
                                })
                            }
                        };
                    }
                }
            }
            match self.core.read_reply(t, sent, deadline) {
                Ok(bytes) => self.pending.extend_from_slice(bytes),
                Err(ReplyWait::Timeout) => return Err(AttemptFailure::Timeout),
                Err(ReplyWait::Interrupted) => return Err(AttemptFailure::Interrupted),
                Err(ReplyWait::Transport(e)) => return Err(AttemptFailure::Transport(e)),
            }
        }
    }

    fn interrupted(&self, request: &Request, bytes: &[u8]) -> AccessError {
        AccessError::Interrupted {
            port: self.transport.name().to_string(),
            address: address_text(request),
            request: describe(request, bytes),
        }
    }
}

/// Whether `reply` is an answer to `request`: a read gets the value of the same parameter
/// or EOT, a short read (ACK, NAK, BS) a value or EOT, a write ACK or NAK.
fn answers(request: &Request, reply: &Reply) -> Result<(), String> {
    match (request, reply) {
        (Request::Read { parameter, .. }, Reply::Value { parameter: got, .. }) if got != parameter => {
            Err(format!("reply for parameter {got}, expected {parameter}"))
        }
        (Request::Read { .. }, Reply::Value { .. } | Reply::NoSuchParameter) => Ok(()),
        (Request::Write { .. }, Reply::Accepted | Reply::Refused) => Ok(()),
        (Request::Read { .. }, other) => {
            Err(format!("{} to a read (expected the value or EOT)", kind(other)))
        }
        (Request::Write { .. }, other) => Err(format!("{} to a write (expected ACK or NAK)", kind(other))),
        // A short command's answer is a normal read reply: a value, or EOT for a parameter
        // the drive does not have.
        (_, Reply::Value { .. } | Reply::NoSuchParameter) => Ok(()),
        (_, other) => Err(format!("{} to a short read command", kind(other))),
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
mod tests {
    use super::*;
    use crate::bus::{MemoryTransport, Peer, PeerReply};
    use crate::clock::{Clock, VirtualClock};
    use crate::family::ct_ansi::codec::{DataValue, Parameter};
    use std::collections::VecDeque;
    use std::sync::Mutex;

    /// Answers each message with the next scripted reply (None = silence).
    struct Scripted {
        replies: VecDeque<Option<Vec<u8>>>,
        received: Vec<Vec<u8>>,
    }

    impl Peer for Scripted {
        fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
            self.received.push(bytes.to_vec());
            match self.replies.pop_front().flatten() {
                Some(bytes) => vec![PeerReply {
                    at: now + Duration::from_millis(1),
                    bytes,
                }],
                None => vec![],
            }
        }
    }

    fn link(script: Vec<Option<Vec<u8>>>) -> (CtLink, Arc<Mutex<Scripted>>, Arc<VirtualClock>) {
        let clock = Arc::new(VirtualClock::new());
        let peer = Arc::new(Mutex::new(Scripted {
            replies: script.into(),
            received: vec![],
        }));
        let transport = MemoryTransport::new("scripted", peer.clone(), clock.clone());
        let link = CtLink::new(
            SharedTransport::new(Box::new(transport)),
            clock.clone(),
            CtLinkConfig::default(),
        );
        (link, peer, clock)
    }

    fn read_121() -> Request {
        Request::Read {
            address: NodeAddress::new(1, 2).unwrap(),
            parameter: Parameter::new(1, 21).unwrap(),
        }
    }

    fn value_reply(menu: u8, param: u8, digits: i64) -> Vec<u8> {
        Reply::Value {
            parameter: Parameter::new(menu, param).unwrap(),
            value: DataValue::new(digits, 1),
        }
        .encode()
        .unwrap()
    }

    #[test]
    fn a_read_returns_the_exact_value() {
        let (mut l, peer, _) = link(vec![Some(b"\x020121-47.6\x037".to_vec())]);
        let reply = l.transact(&read_121()).unwrap();
        assert_eq!(
            reply,
            Some(Reply::Value {
                parameter: Parameter::new(1, 21).unwrap(),
                value: DataValue::new(-476, 1)
            })
        );
        assert_eq!(peer.lock().unwrap().received[0], b"\x0411220121\x05");
    }

    #[test]
    fn a_damaged_reply_is_retried_and_a_lost_one_after_the_timeout() {
        let mut bad = value_reply(1, 21, 15005);
        let last = bad.len() - 1;
        bad[last] ^= 0x01;
        let (mut l, peer, clock) = link(vec![Some(bad), None, Some(value_reply(1, 21, 15005))]);
        assert!(l.transact(&read_121()).unwrap().is_some());
        assert_eq!(peer.lock().unwrap().received.len(), 3);
        assert_eq!(
            (l.stats().corrupt_replies, l.stats().timeouts, l.stats().retries),
            (1, 1, 2)
        );
        assert!(clock.now() >= Duration::from_secs(1));
    }

    #[test]
    fn a_reply_for_another_parameter_is_refused_then_reported() {
        let other = || Some(value_reply(1, 22, 1));
        let (mut l, _, _) = link(vec![other(), other(), other()]);
        let e = l.transact(&read_121()).unwrap_err().to_string();
        assert!(e.contains("reply for parameter #1.22, expected #1.21"), "{e}");
        assert!(e.contains("EOT 11220121 ENQ: read #1.21"), "{e}");
    }

    #[test]
    fn silence_names_port_drive_and_message() {
        let (mut l, peer, _) = link(vec![None, None, None]);
        let e = l.transact(&read_121()).unwrap_err();
        assert!(e.is_no_reply());
        let text = e.to_string();
        assert!(text.starts_with("no reply from drive 1.2 on scripted"), "{text}");
        assert!(text.contains("3 attempt(s)"), "{text}");
        assert_eq!(peer.lock().unwrap().received.len(), 3);
    }

    #[test]
    fn a_group_write_gets_no_reply_and_is_sent_once() {
        let (mut l, peer, clock) = link(vec![None, None, None]);
        let write = Request::Write {
            address: Some(NodeAddress::new(1, 0).unwrap()),
            parameter: Parameter::new(1, 21).unwrap(),
            value: DataValue::new(15005, 1),
        };
        assert_eq!(l.transact(&write).unwrap(), None);
        assert_eq!(peer.lock().unwrap().received.len(), 1);
        assert_eq!(l.stats().retries, 0);
        // No reply wait at all: only the turnaround before the message.
        assert!(clock.now() < Duration::from_millis(10), "{:?}", clock.now());
    }

    #[test]
    fn a_nak_is_the_drives_answer_and_not_retried() {
        let (mut l, peer, _) = link(vec![Some(vec![0x15])]);
        let write = Request::Write {
            address: Some(NodeAddress::new(1, 2).unwrap()),
            parameter: Parameter::new(1, 21).unwrap(),
            value: DataValue::new(15005, 1),
        };
        assert_eq!(l.transact(&write).unwrap(), Some(Reply::Refused));
        assert_eq!(peer.lock().unwrap().received.len(), 1);
    }

    #[test]
    fn the_turnaround_pause_separates_messages() {
        let (mut l, _, clock) = link(vec![Some(value_reply(1, 21, 1)), Some(value_reply(1, 21, 1))]);
        l.transact(&read_121()).unwrap();
        let first = clock.now();
        l.transact(&read_121()).unwrap();
        // Turnaround (2 ms) plus the drive's 1 ms answer.
        assert_eq!(clock.now() - first, Duration::from_millis(3));
    }
}
