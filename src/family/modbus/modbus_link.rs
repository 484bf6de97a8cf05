//! The Modbus link: one request, one checked reply, over any byte transport, framed as RTU
//! (slave address and CRC; a serial line or a raw serial server) or as Modbus TCP (MBAP
//! header with a transaction id).
//!
//! RTU: before a request the line has been silent for 3.5 characters (1.75 ms above
//! 19 200 bit/s), counted from the last byte sent or received. A write to slave 0
//! (broadcast) is sent once and gets no reply. A reply is cut from the stream by its
//! PDU's length; one with a bad CRC, from another slave or not answering the request
//! (wrong function, wrong echo) is a bad reply and the request is sent again, as is one
//! that did not come. An echo of the request (a half-duplex adapter) is skipped, except
//! that a write single register is answered with its own bytes: a lone copy is the reply
//! (an echo's later reply is dropped as stale input before the next request). Register
//! writes set values, so repeating one after a lost reply does the same as sending it once.
//! An exception reply answers the request (the drive refused), except 06 "server device
//! busy" (and 05 "acknowledge" to a read, which carries no values): the request is sent
//! again after a pause of one reply timeout, as the specification asks ("retransmit the
//! message later"); a slave still busy at the last attempt is the answer, which the access
//! layer reports as the slave's refusal with its own text (not as noise on the line). A
//! write answered 05 was accepted: the slave carries it out (section 7).
//! TCP: a reply carries its request's transaction id: one that answers an earlier attempt of
//! the same exchange (a slow server) is the answer, one of an earlier exchange is dropped.
//! RTU has no such number: the link core waits for the replies that attempts which went
//! unanswered still owe, and drops them, before the next exchange.
//! Must not know object names, units or states.

use super::codec::{mbap, rtu, ExceptionCode, Request, Response};
use crate::bus::{SharedTransport, Transport, TransportError};
use crate::clock::SharedClock;
use crate::drive::AccessError;
use crate::link::{AttemptFailure, CoreLink, Direction, ExchangeText, LinkCore, Refusal, RetryPlan};
use std::time::Duration;

/// A stop request does not cut short the first part of a reply wait, so the exchange under
/// way finishes (a 9600 bit/s reply of 9 bytes takes about 10 ms on the wire).
const STOP_GRACE: Duration = Duration::from_millis(30);
/// What to check when an inverter behind a Modbus TCP server stays silent; also the TCP
/// family's `no_reply_advice`. Nothing about serial lines: the link is a network connection.
pub(super) const NO_REPLY_HINT_TCP: &str = "check that the Modbus TCP server at --tcp HOST:PORT is the inverter's (port 502 by default) and not busy with another client, and the unit id (--address; behind a gateway, the inverter's slave address)";
/// What to check when an inverter on a serial line stays silent; also the RTU family's
/// `no_reply_advice`.
pub(super) const NO_REPLY_HINT: &str = "check the RS485 wiring (A/B, termination), the baud rate and parity (--baud, --parity; Modbus RTU defaults to 19200 8E1), that the inverter's protocol parameter selects Modbus RTU, and its slave address (--address 1..247)";

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Framing {
    Rtu,
    Tcp,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinkConfig {
    pub framing: Framing,
    pub reply_timeout: Duration,
    pub retries: u32,
    /// Before a retry the line is listened to for this long and what arrives is dropped.
    pub settle: Duration,
    /// RTU: the silence that separates frames (see [`rtu::frame_silence`]).
    pub silence: Duration,
}

impl Default for LinkConfig {
    fn default() -> Self {
        LinkConfig {
            framing: Framing::Rtu,
            reply_timeout: Duration::from_millis(500),
            retries: 2,
            settle: Duration::from_millis(20),
            silence: rtu::frame_silence(19_200, 11),
        }
    }
}

type Refused = Refusal<String, String>;

pub struct ModbusLink {
    transport: SharedTransport,
    config: LinkConfig,
    unit: u8,
    core: LinkCore,
    pending: Vec<u8>,
    transaction: u16,
    /// TCP: the transaction id of this exchange's first attempt; replies from it up to
    /// `transaction` answer the same request.
    first_transaction: u16,
    /// When the line last carried a byte (RTU's silence counts from here).
    last_activity: Option<Duration>,
    /// The last attempt was answered "busy": the next waits before it is sent.
    busy: bool,
}

impl ModbusLink {
    pub fn new(transport: SharedTransport, clock: SharedClock, unit: u8, config: LinkConfig) -> Self {
        ModbusLink {
            transport,
            config,
            unit,
            core: LinkCore::new(clock, STOP_GRACE),
            pending: Vec::new(),
            transaction: 0,
            first_transaction: 1,
            last_activity: None,
            busy: false,
        }
    }

    pub fn port(&self) -> String {
        self.transport.name().to_string()
    }

    pub fn unit(&self) -> u8 {
        self.unit
    }

    /// `slave 3` (RTU) or `unit 3` (TCP).
    pub fn shown_unit(&self) -> String {
        match self.config.framing {
            Framing::Rtu if self.unit == rtu::BROADCAST => "broadcast (slave 0)".into(),
            Framing::Rtu => format!("slave {}", self.unit),
            Framing::Tcp => format!("unit {}", self.unit),
        }
    }

    pub fn reopen(&mut self) -> Result<(), AccessError> {
        self.pending.clear();
        self.core.event("reopening the port");
        self.transport.reopen()?;
        Ok(())
    }

    /// Sends `request` and returns the reply that answers it (an exception included), or
    /// `None` for a broadcast, which no slave answers.
    pub fn exchange(&mut self, request: &Request) -> Result<Option<Response>, AccessError> {
        let pdu = request.encode().map_err(|e| AccessError::Encode(e.to_string()))?;
        let shared = self.transport.clone();
        let mut line = shared.lock();
        let t: &mut dyn Transport = line.as_mut();
        if self.config.framing == Framing::Rtu && self.unit == rtu::BROADCAST {
            if !request.writes() {
                return Err(AccessError::Encode(
                    "a broadcast (slave 0) gets no reply, so it cannot read; give --address 1..247".into(),
                ));
            }
            let frame = rtu::encode(self.unit, &pdu);
            self.send(t, &frame).map_err(AccessError::Transport)?;
            self.core.event("broadcast: no slave answers");
            return Ok(None);
        }
        let plan = RetryPlan {
            sequenced: self.config.framing == Framing::Tcp,
            ..RetryPlan::new(self.config.retries, self.config.settle, self.config.reply_timeout)
        };
        self.first_transaction = self.transaction.wrapping_add(1);
        self.busy = false;
        let attempts = plan.retries + 1;
        let result = plan.run_with_step(
            self,
            t,
            |link, _| {
                link.wait_while_busy();
                Ok(None)
            },
            |link, t, number| link.attempt(t, request, &pdu, number == attempts),
        );
        if result.is_ok() && self.pending.is_empty() {
            t.exchange_complete();
        }
        result.map(Some).map_err(|u| {
            let text = ExchangeText {
                port: self.port(),
                address: self.shown_unit(),
                request: describe(request, &pdu),
                hint: self.no_reply_hint().to_string(),
            };
            u.into_error(text, self.config.reply_timeout, |r| (r.reply, r.problem))
        })
    }

    /// After a "busy" answer: one reply timeout before the request goes again, in slices
    /// that a stop request ends.
    fn wait_while_busy(&mut self) {
        if !std::mem::take(&mut self.busy) {
            return;
        }
        let until = self.core.clock.now() + self.config.reply_timeout;
        self.core.event(&format!(
            "the slave is busy: asking again in {} ms",
            self.config.reply_timeout.as_millis()
        ));
        while self.core.clock.now() < until && !self.core.stop_pending() {
            // Time passes between the readings: `until` may be behind us by now.
            let slice = until
                .saturating_sub(self.core.clock.now())
                .min(Duration::from_millis(10));
            self.core.clock.sleep(slice);
        }
    }

    /// What to check when the inverter stays silent, for the framing in use.
    pub fn no_reply_hint(&self) -> &'static str {
        match self.config.framing {
            Framing::Rtu => NO_REPLY_HINT,
            Framing::Tcp => NO_REPLY_HINT_TCP,
        }
    }

    /// Waits out the inter-frame silence, then writes `frame`.
    fn send(&mut self, t: &mut dyn Transport, frame: &[u8]) -> Result<(), TransportError> {
        if self.config.framing == Framing::Rtu {
            if let Some(last) = self.last_activity {
                let quiet = last + self.config.silence;
                if self.core.clock.now() < quiet {
                    self.core.clock.sleep_until(quiet);
                }
            }
        }
        self.core.drop_stale_input(t, self.pending.len())?;
        self.pending.clear();
        t.write_all(frame)?;
        self.core.stats.requests += 1;
        self.core.notify(Direction::Sent, frame);
        self.last_activity = Some(self.core.clock.now() + t.still_sending());
        Ok(())
    }

    fn frame(&mut self, pdu: &[u8]) -> Vec<u8> {
        match self.config.framing {
            Framing::Rtu => rtu::encode(self.unit, pdu),
            Framing::Tcp => {
                self.transaction = self.transaction.wrapping_add(1);
                mbap::encode(self.transaction, self.unit, pdu)
            }
        }
    }

    fn attempt(
        &mut self,
        t: &mut dyn Transport,
        request: &Request,
        pdu: &[u8],
        last: bool,
    ) -> Result<Response, AttemptFailure<Refused>> {
        let frame = self.frame(pdu);
        self.send(t, &frame).map_err(AttemptFailure::Transport)?;
        let (sent, deadline) = self.core.reply_window(t, self.config.reply_timeout);
        let mut dropped = None;
        loop {
            match self.take_reply(request, &frame, last) {
                None => {}
                // A reply to another request is never this one's answer: it is dropped and
                // the line listened to on.
                Some(Err(AttemptFailure::Discarded(r))) => {
                    self.core.event(&format!(
                        "dropped a reply that answers another request: {}",
                        r.problem
                    ));
                    dropped = Some(r);
                    continue;
                }
                Some(result) => return result,
            }
            match self.core.read_reply(t, sent, deadline) {
                Ok(bytes) => {
                    if !bytes.is_empty() {
                        let bytes = bytes.to_vec();
                        self.pending.extend_from_slice(&bytes);
                        self.last_activity = Some(self.core.clock.now());
                    }
                }
                Err(wait) => return Err(AttemptFailure::after_wait(wait, dropped)),
            }
        }
    }

    /// The reply in what has come so far: `None` while it is incomplete.
    fn take_reply(
        &mut self,
        request: &Request,
        sent: &[u8],
        last: bool,
    ) -> Option<Result<Response, AttemptFailure<Refused>>> {
        // A write single register is answered with its own bytes, so one copy is the
        // reply; of two copies (an echoing adapter) the first is the echo.
        let echo_is_reply = matches!(request, Request::WriteSingle { .. });
        let copies = if echo_is_reply { 2 } else { 1 };
        if self.pending.len() >= copies * sent.len() && self.pending.starts_with(sent) {
            self.pending.drain(..sent.len());
            self.core.stats.echoes += 1;
            self.core.event("skipped the echo of the request");
        }
        let (unit, pdu, whole) = match self.config.framing {
            Framing::Rtu => match rtu::split(&self.pending, rtu::Sender::Slave) {
                rtu::Split::Incomplete => return None,
                rtu::Split::Noise(_) => {
                    let bytes = std::mem::take(&mut self.pending);
                    return Some(Err(self.bad(
                        &bytes,
                        "no Modbus reply starts like this".into(),
                        false,
                    )));
                }
                rtu::Split::Frame(n) => {
                    let whole: Vec<u8> = self.pending.drain(..n).collect();
                    self.core.notify(Direction::Received, &whole);
                    match rtu::decode(&whole) {
                        Ok((unit, pdu)) => (unit, pdu.to_vec(), whole),
                        Err(e) => return Some(Err(self.bad(&whole, e.to_string(), false))),
                    }
                }
            },
            Framing::Tcp => {
                let n = mbap::frame_len(&self.pending)?;
                if self.pending.len() < n {
                    return None;
                }
                let whole: Vec<u8> = self.pending.drain(..n).collect();
                self.core.notify(Direction::Received, &whole);
                // Ids count up by one per attempt (wrapping): this exchange's are the last few.
                let age = self.transaction.wrapping_sub(self.first_transaction);
                match mbap::decode(&whole) {
                    Ok(f) if self.transaction.wrapping_sub(f.transaction) > age => {
                        self.core.event(&format!(
                            "dropped a late reply (transaction {}, waiting for {})",
                            f.transaction, self.transaction
                        ));
                        return self.take_reply(request, sent, last);
                    }
                    Ok(f) => (f.unit, f.pdu.to_vec(), whole),
                    Err(e) => return Some(Err(self.bad(&whole, e.to_string(), false))),
                }
            }
        };
        if unit != self.unit {
            let what = match self.config.framing {
                Framing::Rtu => "slave",
                Framing::Tcp => "unit",
            };
            let problem = format!("it comes from {what} {unit}, not {what} {}", self.unit);
            return Some(Err(self.bad(&whole, problem, true)));
        }
        let response = match Response::decode(&pdu) {
            Ok(r) => r,
            Err(e) => return Some(Err(self.bad(&whole, e.to_string(), false))),
        };
        if let Err(expected) = request.check(&response) {
            return Some(Err(self.bad(&whole, format!("expected {expected}"), true)));
        }
        // A busy slave is to be asked again later (Application Protocol V1.1b3, 7: code 06);
        // so is one that acknowledged a read (05), which carries no values.
        if let Response::Exception { code, .. } = response {
            let later = code == ExceptionCode::SERVER_DEVICE_BUSY
                || (code == ExceptionCode::ACKNOWLEDGE && !request.writes());
            if later && !last {
                self.busy = true;
                return Some(Err(AttemptFailure::Bad(Refusal {
                    reply: format!("`{}`", crate::hex::to_hex(&whole)),
                    problem: code.to_string(),
                })));
            }
        }
        self.core.stats.replies += 1;
        Some(Ok(response))
    }

    fn bad(&mut self, bytes: &[u8], problem: String, mismatched: bool) -> AttemptFailure<Refused> {
        let refusal = Refusal {
            reply: format!("`{}`", crate::hex::to_hex(bytes)),
            problem,
        };
        if mismatched {
            self.core.stats.mismatched_replies += 1;
            AttemptFailure::Discarded(refusal)
        } else {
            self.core.stats.corrupt_replies += 1;
            AttemptFailure::Bad(refusal)
        }
    }
}

impl CoreLink for ModbusLink {
    crate::core_link_field!();
}

/// `` `03 D0 00 00 02` (read holding registers 0xD000, 2) ``.
fn describe(request: &Request, pdu: &[u8]) -> String {
    let what = match request {
        Request::Read { start, count, .. } => format!("0x{start:04X}, {count}"),
        Request::WriteSingle { address, value } => format!("0x{address:04X} = {value}"),
        Request::WriteMultiple { start, values } => format!("0x{start:04X}, {} value(s)", values.len()),
        Request::ReadWrite {
            read_start,
            write_start,
            ..
        } => {
            format!("read 0x{read_start:04X}, write 0x{write_start:04X}")
        }
    };
    format!(
        "`{}` ({} {what})",
        crate::hex::to_hex(pdu),
        request.function().name()
    )
}

#[cfg(test)]
#[path = "modbus_link_tests.rs"]
mod tests;
