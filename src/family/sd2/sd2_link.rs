//! The SD2 DNC link: one request, one checked reply, over any transport.
//!
//! Master/slave: the PC sends a block, the addressed drive answers with one block and
//! never talks unprompted. So before every request, input is discarded (a late reply to an
//! earlier attempt must not be taken for this one), and a reply is accepted only if it
//! answers this request. Requests seen on the line (RS485 adapters that echo what they
//! send) are skipped. Must not know object names, units or states.

use super::link_config::LinkConfig;
use crate::bus::{SharedTransport, Transport, TransportError};
use crate::clock::SharedClock;
use crate::drive::AccessError;
use crate::family::sd2::codec::{
    check_reply, Body, Cyclic, Data, DecodeError, ErrorCode, FrameExtractor, Framing, Telegram,
};
use crate::hex::to_hex;
use crate::link::{
    AttemptFailure, CoreLink, Direction, ExchangeText, LinkCore, Refusal, RetryPlan, Unanswered,
};
use std::time::Duration;

/// A stop request does not cut short the first part of a reply wait: a drive that is
/// answering at all has answered by then (250 µs turnaround plus the reply's wire time),
/// so the telegram under way finishes and its answer is not lost.
const STOP_GRACE: Duration = Duration::from_millis(20);
/// What to check when the drive does not answer; also the family's `no_reply_advice`.
pub(super) const NO_REPLY_HINT: &str = "check the cable, the baud rate, the drive's DNC address (address switch), and that its control channel is set to the serial interface";

pub struct Sd2Link {
    /// Shared with the other drives on the same line; locked for one whole exchange.
    transport: SharedTransport,
    end: LineEnd,
}

/// This end of the line: everything an exchange uses besides the line itself. Kept apart
/// from the line's handle so that an exchange locks the line through the link's own
/// handle, without another handle (and its counts) for each of a long run's millions.
struct LineEnd {
    config: LinkConfig,
    extractor: FrameExtractor,
    /// Clock, observer, stop requests, counters and the listening every link shares.
    core: LinkCore,
    /// The request being sent, kept between exchanges: a long run sends millions.
    request_bytes: Vec<u8>,
    /// The reply to the last exchange, written where it is read: the retry loop and its
    /// results then carry no telegram.
    reply: Telegram,
}

/// A reply that does not answer: its bytes and why.
type Refused = Refusal<Vec<u8>, DecodeError>;

impl Sd2Link {
    pub fn new(transport: SharedTransport, clock: SharedClock, config: LinkConfig) -> Self {
        Sd2Link {
            transport,
            end: LineEnd {
                core: LinkCore::new(clock, STOP_GRACE),
                config,
                extractor: FrameExtractor::new(Framing::Replies),
                request_bytes: Vec::new(),
                reply: Telegram::read_request(0, 0, 0, 0),
            },
        }
    }

    /// Closes and opens the port again after it failed; what arrived before is dropped.
    pub fn reopen(&mut self) -> Result<(), AccessError> {
        self.end.extractor.clear();
        self.end.core.event("reopening the port");
        self.transport.reopen()?;
        Ok(())
    }

    pub fn port(&self) -> &str {
        self.transport.name()
    }

    pub fn config(&self) -> &LinkConfig {
        &self.end.config
    }

    /// Sends `request` and returns the reply that answers it, retrying on timeouts and on
    /// corrupt or mismatched replies up to `config.retries` times.
    pub fn transact(&mut self, request: &Telegram) -> Result<Telegram, AccessError> {
        self.exchange(request)?;
        Ok(self.end.reply)
    }

    /// [`transact`](Self::transact), with the reply left in `self.end.reply`.
    fn exchange(&mut self, request: &Telegram) -> Result<(), AccessError> {
        let end = &mut self.end;
        let mut bytes = std::mem::take(&mut end.request_bytes);
        bytes.clear();
        request.encode_into(&mut bytes, end.config.write_length);
        let c = &end.config;
        let plan = RetryPlan::new(c.retries, c.settle, c.reply_timeout);
        let result = {
            let mut line = self.transport.lock();
            let t: &mut dyn Transport = line.as_mut();
            end.send_and_await(&plan, t, request, &bytes)
        };
        let result = result.map_err(|unanswered| {
            let text = ExchangeText {
                port: self.transport.name().to_string(),
                address: request.dest.to_string(),
                request: describe_request(request, &bytes),
                hint: NO_REPLY_HINT.to_string(),
            };
            unanswered.into_error(text, plan.reply_timeout, |r| {
                (to_hex(&r.reply), r.problem.to_string())
            })
        });
        self.end.request_bytes = bytes;
        result
    }

    /// Reads an object; a reply carrying an error code becomes [`AccessError::Refused`].
    pub fn read_object(&mut self, dest: u8, index: u16, subindex: u32) -> Result<Data, AccessError> {
        let request = Telegram::read_request(dest, self.end.config.master_address, index, subindex);
        self.exchange(&request)?;
        match self.end.reply.body {
            Body::ReadReply { error, data } if error.is_ok() => Ok(data),
            Body::ReadReply { error, .. } => Err(self.refused(dest, "read", index, subindex, error)),
            _ => Err(self.unexpected(&request)),
        }
    }

    /// Writes an object (1..=48 bytes).
    pub fn write_object(
        &mut self,
        dest: u8,
        index: u16,
        subindex: u32,
        data: &[u8],
    ) -> Result<(), AccessError> {
        let request = Telegram::write_request(dest, self.end.config.master_address, index, subindex, data)
            .map_err(|e| AccessError::Encode(e.to_string()))?;
        self.exchange(&request)?;
        match self.end.reply.body {
            Body::WriteReply { error } if error.is_ok() => Ok(()),
            Body::WriteReply { error } => Err(self.refused(dest, "write", index, subindex, error)),
            _ => Err(self.unexpected(&request)),
        }
    }

    /// Exchanges one cyclic telegram and returns the drive's process data.
    pub fn cyclic(&mut self, dest: u8, cyclic: Cyclic) -> Result<Cyclic, AccessError> {
        let request = Telegram {
            dest,
            source: self.end.config.master_address,
            body: Body::CyclicRequest(cyclic),
        };
        self.exchange(&request)?;
        match self.end.reply.body {
            Body::CyclicReply(c) => Ok(c),
            _ => Err(self.unexpected(&request)),
        }
    }

    fn refused(
        &self,
        dest: u8,
        operation: &'static str,
        index: u16,
        subindex: u32,
        code: ErrorCode,
    ) -> AccessError {
        AccessError::Refused {
            port: self.transport.name().to_string(),
            address: dest.to_string(),
            operation,
            object: format!("{index} (subindex {subindex})"),
            code: u32::from(code.0),
            text: code.to_string(),
        }
    }

    /// The last reply is of the wrong kind for `request`.
    fn unexpected(&self, request: &Telegram) -> AccessError {
        AccessError::UnexpectedReply {
            port: self.transport.name().to_string(),
            address: request.dest.to_string(),
            request: describe_request(request, &request.encode(self.end.config.write_length)),
            detail: format!("command 0x{:02x}", self.end.reply.command()),
        }
    }
}

impl LineEnd {
    /// Sends `bytes` (the encoded `request`) on `t` and waits for the reply that answers it
    /// (into `self.reply`), as `plan` says.
    fn send_and_await(
        &mut self,
        plan: &RetryPlan,
        t: &mut dyn Transport,
        request: &Telegram,
        bytes: &[u8],
    ) -> Result<(), Unanswered<Refused>> {
        plan.run(self, t, |end, t, attempt| {
            end.flush_input(t).map_err(AttemptFailure::Transport)?;
            t.write_all(bytes).map_err(AttemptFailure::Transport)?;
            end.core.stats.requests += 1;
            end.core.notify(Direction::Sent, bytes);
            end.await_reply(t, request)?;
            // Only a first attempt answered with nothing after it vouches for a clean
            // line: after a retry, the failed attempt's reply may still come.
            if attempt == 1 && end.extractor.pending().is_empty() {
                t.exchange_complete();
            }
            Ok(())
        })
    }

    fn flush_input(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        self.core.drop_stale_input(t, self.extractor.pending().len())?;
        self.extractor.clear();
        Ok(())
    }

    /// Waits for the reply that answers `request` and keeps it in `self.reply`.
    fn await_reply(
        &mut self,
        t: &mut dyn Transport,
        request: &Telegram,
    ) -> Result<(), AttemptFailure<Refused>> {
        let (sent, deadline) = self.core.reply_window(t, self.config.reply_timeout);
        let mut dropped = None;
        loop {
            while let Some(block) = self.extractor.next_block() {
                if block.skipped > 0 {
                    self.core
                        .event(&format!("skipped {} byte(s) of line noise", block.skipped));
                }
                self.core.notify(Direction::Received, block.bytes);
                let telegram = match block.telegram {
                    Ok(t) => t,
                    Err(problem) => {
                        self.core.stats.corrupt_replies += 1;
                        return Err(AttemptFailure::Bad(Refusal {
                            reply: block.bytes.to_vec(),
                            problem,
                        }));
                    }
                };
                if !telegram.is_reply() {
                    // Our own request echoed by a half-duplex adapter, or another master.
                    continue;
                }
                if let Err(problem) = check_reply(request, &telegram) {
                    // Another request's answer (most often a late one): never this one's.
                    self.core.stats.mismatched_replies += 1;
                    self.core.event(&format!(
                        "dropped a reply that answers another request: {problem}"
                    ));
                    dropped = Some(Refusal {
                        reply: block.bytes.to_vec(),
                        problem,
                    });
                    continue;
                }
                self.reply = telegram;
                return Ok(());
            }
            match self.core.read_reply(t, sent, deadline) {
                Ok(bytes) => self.extractor.push(bytes),
                Err(wait) => return Err(AttemptFailure::after_wait(wait, dropped)),
            }
        }
    }
}

impl CoreLink for LineEnd {
    crate::core_link_field!();
}

impl CoreLink for Sd2Link {
    fn core(&mut self) -> &mut LinkCore {
        &mut self.end.core
    }
    fn core_ref(&self) -> &LinkCore {
        &self.end.core
    }
}

/// `00 09 02 01 0d 43 00 00 00 00 00 a3 (read object 67)`.
fn describe_request(request: &Telegram, bytes: &[u8]) -> String {
    let what = match request.body {
        Body::ReadRequest { index, subindex } => format!("read object {index}/{subindex}"),
        Body::WriteRequest { index, subindex, .. } => format!("write object {index}/{subindex}"),
        Body::CyclicRequest(_) => "cyclic telegram".to_string(),
        _ => "reply".to_string(),
    };
    format!("`{}` ({what})", to_hex(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::{MemoryTransport, ScriptedPeer, SharedTransport};
    use crate::clock::{Clock, VirtualClock};
    use crate::family::sd2::codec::WriteLength;
    use crate::link::TelegramObserver;
    use crate::stop_request::StopRequests;
    use std::sync::{Arc, Mutex};
    use std::time::Duration;

    fn status_reply(source: u8) -> Vec<u8> {
        Telegram {
            dest: 1,
            source,
            body: Body::ReadReply {
                error: ErrorCode::OK,
                data: Data::new(&[0x37, 0x02]).unwrap(),
            },
        }
        .encode(WriteLength::Captured)
    }

    fn link(
        script: Vec<Option<(Duration, Vec<u8>)>>,
    ) -> (Sd2Link, Arc<Mutex<ScriptedPeer>>, Arc<VirtualClock>) {
        let peer = ScriptedPeer::timed(script);
        let (line, clock) = ScriptedPeer::line(&peer);
        (
            Sd2Link::new(line, clock.clone(), LinkConfig::default()),
            peer,
            clock,
        )
    }

    const FAST: Duration = Duration::from_micros(100);

    /// A transport whose writes are still on the line for `sending` after they return.
    struct StillSending(MemoryTransport, Duration);

    impl Transport for StillSending {
        fn name(&self) -> &str {
            self.0.name()
        }
        fn write_all(&mut self, bytes: &[u8]) -> Result<(), crate::bus::TransportError> {
            self.0.write_all(bytes)
        }
        fn still_sending(&self) -> Duration {
            self.1
        }
        fn read(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, crate::bus::TransportError> {
            self.0.read(buf, timeout)
        }
        fn discard_input(&mut self) -> Result<usize, crate::bus::TransportError> {
            self.0.discard_input()
        }
        fn reopen(&mut self) -> Result<(), crate::bus::TransportError> {
            self.0.reopen()
        }
    }

    /// A read answered 30 ms after the request left, with a reply timeout of 20 ms: in time
    /// only when the request itself took 15 ms on the line.
    fn late_reply(sending: Duration) -> Result<Telegram, AccessError> {
        let clock = Arc::new(VirtualClock::new());
        let peer = ScriptedPeer::timed(vec![Some((Duration::from_millis(30), status_reply(2)))]);
        let transport = StillSending(MemoryTransport::new("scripted", peer, clock.clone()), sending);
        let config = LinkConfig {
            reply_timeout: Duration::from_millis(20),
            retries: 0,
            ..LinkConfig::default()
        };
        let mut link = Sd2Link::new(SharedTransport::new(Box::new(transport)), clock, config);
        link.transact(&Telegram::read_request(2, 1, 67, 0))
    }

    /// A stop request while the request is still on the line does not cut the wait for
    /// its answer: the grace counts from when the request has left, as the reply timeout.
    #[test]
    fn the_stop_grace_starts_when_the_request_is_off_the_line() {
        let clock = Arc::new(VirtualClock::new());
        let peer = ScriptedPeer::timed(vec![Some((Duration::from_millis(45), status_reply(2)))]);
        let transport = StillSending(
            MemoryTransport::new("scripted", peer, clock.clone()),
            Duration::from_millis(40),
        );
        let mut link = Sd2Link::new(
            SharedTransport::new(Box::new(transport)),
            clock,
            LinkConfig::default(),
        );
        let stop = Arc::new(StopRequests::new());
        stop.schedule(Duration::from_millis(25), crate::stop_request::StopSignal::INT);
        link.set_stop_requests(stop);
        assert!(link.transact(&Telegram::read_request(2, 1, 67, 0)).is_ok());
    }

    #[test]
    fn the_reply_timeout_starts_when_the_request_is_off_the_line() {
        assert!(late_reply(Duration::from_millis(15)).is_ok());
        assert!(matches!(
            late_reply(Duration::ZERO),
            Err(AccessError::NoReply { .. })
        ));
    }

    #[test]
    fn a_read_returns_the_data() {
        let (mut l, peer, _) = link(vec![Some((FAST, status_reply(2)))]);
        let data = l.read_object(2, 67, 0).unwrap();
        assert_eq!(data.as_slice(), &[0x37, 0x02]);
        let sent = peer.lock().unwrap().sent();
        assert_eq!(to_hex(&sent[0]), "00 09 02 01 0d 43 00 00 00 00 00 a3");
        assert_eq!(l.stats().retries, 0);
    }

    #[test]
    fn a_lost_reply_is_retried_after_the_timeout() {
        let (mut l, peer, clock) = link(vec![None, Some((FAST, status_reply(2)))]);
        assert!(l.read_object(2, 67, 0).is_ok());
        assert_eq!(peer.lock().unwrap().received.len(), 2);
        assert_eq!(l.stats().timeouts, 1);
        assert_eq!(l.stats().retries, 1);
        assert!(clock.now() >= Duration::from_secs(1));
    }

    #[test]
    fn every_attempt_lost_names_port_drive_and_telegram() {
        let (mut l, peer, clock) = link(vec![None, None, None]);
        let e = l.read_object(2, 67, 0).unwrap_err();
        assert!(e.is_no_reply());
        let text = e.to_string();
        assert!(text.contains("no reply from drive 2 on scripted"), "{text}");
        assert!(
            text.contains("`00 09 02 01 0d 43 00 00 00 00 00 a3` (read object 67/0)"),
            "{text}"
        );
        assert!(text.contains("3 attempt(s), 1000 ms each"), "{text}");
        assert_eq!(peer.lock().unwrap().received.len(), 3);
        // Three timeouts and two settle periods.
        assert_eq!(clock.now(), Duration::from_millis(3040));
    }

    #[test]
    fn a_corrupt_reply_is_retried_without_waiting_the_timeout() {
        let mut bad = status_reply(2);
        let last = bad.len() - 1;
        bad[last] ^= 0xff;
        let (mut l, _, clock) = link(vec![Some((FAST, bad)), Some((FAST, status_reply(2)))]);
        assert!(l.read_object(2, 67, 0).is_ok());
        assert_eq!(l.stats().corrupt_replies, 1);
        // Only the settle time, not the 1 s reply timeout.
        assert!(clock.now() < Duration::from_millis(25), "{:?}", clock.now());
    }

    #[test]
    fn a_reply_from_the_wrong_drive_is_refused_then_reported() {
        let (mut l, _, _) = link(vec![
            Some((FAST, status_reply(4))),
            Some((FAST, status_reply(4))),
            Some((FAST, status_reply(4))),
        ]);
        let e = l.read_object(2, 67, 0).unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, AccessError::BadReply { .. }), "{text}");
        assert!(text.contains("source address expected 2, got 4"), "{text}");
        assert_eq!(l.stats().mismatched_replies, 3);
    }

    #[test]
    fn a_late_reply_to_an_earlier_attempt_is_discarded() {
        // First reply arrives after the timeout; the retry must not take it as its own.
        let late = Telegram {
            dest: 1,
            source: 2,
            body: Body::ReadReply {
                error: ErrorCode::OK,
                data: Data::new(&[0xAA, 0xAA]).unwrap(),
            },
        }
        .encode(WriteLength::Captured);
        let (mut l, _, _) = link(vec![
            Some((Duration::from_millis(1001), late)),
            Some((Duration::from_millis(5), status_reply(2))),
        ]);
        let data = l.read_object(2, 67, 0).unwrap();
        assert_eq!(data.as_slice(), &[0x37, 0x02]);
    }

    #[test]
    fn an_echo_of_our_own_request_is_skipped() {
        let mut echo_then_reply = Telegram::read_request(2, 1, 67, 0).encode(WriteLength::Captured);
        echo_then_reply.extend(status_reply(2));
        let (mut l, _, _) = link(vec![Some((FAST, echo_then_reply))]);
        assert!(l.read_object(2, 67, 0).is_ok());
    }

    #[test]
    fn a_drive_error_code_is_typed_and_explained() {
        let refused = Telegram {
            dest: 1,
            source: 2,
            body: Body::WriteReply {
                error: ErrorCode(0x8A),
            },
        }
        .encode(WriteLength::Captured);
        let (mut l, _, _) = link(vec![Some((FAST, refused))]);
        let e = l.write_object(2, 67, 0, &[0, 0]).unwrap_err();
        assert!(matches!(e, AccessError::Refused { code: 0x8A, .. }), "{e}");
        assert_eq!(
            e.to_string(),
            "drive 2 on scripted refused to write object 67 (subindex 0): 0x8A attempt to write a read-only object"
        );
    }

    #[test]
    fn observer_sees_both_directions() {
        #[derive(Default)]
        struct Log(Arc<Mutex<Vec<String>>>);
        impl TelegramObserver for Log {
            fn telegram(&mut self, _: Duration, d: Direction, bytes: &[u8]) {
                self.0
                    .lock()
                    .unwrap()
                    .push(format!("{} {}", d.tag(), to_hex(bytes)));
            }
            fn event(&mut self, _: Duration, text: &str) {
                self.0.lock().unwrap().push(text.to_string());
            }
        }
        let lines = Arc::new(Mutex::new(vec![]));
        let (mut l, _, _) = link(vec![None, Some((FAST, status_reply(2)))]);
        l.set_observer(Box::new(Log(lines.clone())));
        l.read_object(2, 67, 0).unwrap();
        let lines = lines.lock().unwrap();
        assert_eq!(lines[0], "TX 00 09 02 01 0d 43 00 00 00 00 00 a3");
        assert_eq!(lines[1], "no reply within 1000 ms");
        assert_eq!(lines[2], "retry 1 of 2");
        assert_eq!(lines[4], format!("RX {}", to_hex(&status_reply(2))));
    }
}
