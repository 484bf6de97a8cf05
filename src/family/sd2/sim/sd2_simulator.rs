//! The simulated SD2 drive as a byte-level peer: cuts incoming bytes into blocks, answers
//! every request addressed to it with the exact reply bytes a drive sends, and applies the
//! injected faults to those replies. It must not take shortcuts around the codec (every
//! request is decoded and every reply encoded) and must not read a clock of its own: time
//! is the `now` it is given, so the same bytes at the same times give the same replies.

use super::sd2_objects;
use super::service_channel::{
    ServiceAction, ServiceSession, INVALID_SERVICE_DRIVE_ERROR, UNSUPPORTED_ACCESS,
};
use super::sim_objects::{SimObject, CONTROL_WORD};
use crate::bus::{Peer, PeerReplies, PeerReply};
use crate::family::sd2::codec::{
    Body, Cyclic, ErrorCode, FrameExtractor, Framing, ServiceChannel, Telegram, WriteLength,
};
use crate::sim::{SimConfig, SimCore, SimFront};
use std::time::Duration;

/// A simulated single-axis SD2 drive. See the module docs of `sim` for the model.
#[derive(Debug)]
pub struct Sd2Simulator {
    /// The model, the faults and the logs: the decoded requests addressed to this drive
    /// with the time each arrived, and every control word accepted (object 68 by block or
    /// service channel, and cyclic telegrams).
    core: SimCore<(Duration, Telegram)>,
    extractor: FrameExtractor,
    service: ServiceSession,
    corrupt_blocks: u64,
}

impl Sd2Simulator {
    /// A drive just booted: switch on disabled, at rest, setpoint 0.
    pub fn new(config: SimConfig) -> Self {
        Sd2Simulator {
            core: SimCore::new(config),
            extractor: FrameExtractor::new(Framing::Requests),
            service: ServiceSession::default(),
            corrupt_blocks: 0,
        }
    }

    pub fn config(&self) -> &SimConfig {
        self.core.model.config()
    }

    /// The decoded requests addressed to this drive, with the time each arrived: all of
    /// them up to [`LOG_KEEPS`](crate::sim::LOG_KEEPS), then at least the latest ones.
    pub fn received(&self) -> &[(Duration, Telegram)] {
        self.core.requests()
    }

    /// Forgets the logs of [`received`](Self::received) and of the control words.
    pub fn clear_log(&mut self) {
        self.core.clear_log();
    }

    /// Candidate blocks that failed to decode (bad checksum, length or command). A real
    /// drive cannot trust the header of such a block, so it stays silent and the master
    /// times out; the count lets a test see that this happened.
    pub fn corrupt_blocks(&self) -> u64 {
        self.corrupt_blocks
    }

    /// The speed setpoint in rpm, as last written (object 395 or the cyclic reference).
    pub fn setpoint_rpm(&self) -> f64 {
        self.core.model.setpoint_rpm()
    }

    fn answer(&mut self, body: &Body) -> Option<Body> {
        Some(match *body {
            Body::ReadRequest { index, subindex } => {
                match sd2_objects::read(&mut self.core.model, index, subindex) {
                    Ok(data) => Body::ReadReply {
                        error: ErrorCode::OK,
                        data,
                    },
                    Err(error) => Body::ReadReply {
                        error,
                        data: Default::default(),
                    },
                }
            }
            Body::WriteRequest {
                index,
                subindex,
                data,
            } => Body::WriteReply {
                error: self
                    .write_object(index, subindex, data.as_slice())
                    .err()
                    .unwrap_or(ErrorCode::OK),
            },
            Body::CyclicRequest(request) => Body::CyclicReply(self.cyclic(&request)),
            // A reply on the bus is some other drive's business.
            Body::ReadReply { .. } | Body::WriteReply { .. } | Body::CyclicReply(_) => return None,
        })
    }

    fn write_object(&mut self, index: u16, subindex: u32, bytes: &[u8]) -> Result<(), ErrorCode> {
        let blocked = self.core.faults.is_fault_reset_blocked();
        let control_word = match (index, bytes) {
            (CONTROL_WORD, &[lo, hi]) => Some(u16::from_le_bytes([lo, hi])),
            _ => None,
        };
        if let Some(cw) = control_word.filter(|cw| self.core.disobeys_word(*cw)) {
            self.core.log_control_word(cw);
            return Ok(());
        }
        sd2_objects::write(&mut self.core.model, index, subindex, bytes, blocked)?;
        if let Some(cw) = control_word {
            self.core.log_control_word(cw);
        }
        Ok(())
    }

    /// Process data first (control word, then speed reference), then the service channel,
    /// so the reply's status shows the effect of both.
    fn cyclic(&mut self, request: &Cyclic) -> Cyclic {
        let control_word = request.word();
        self.core.log_control_word(control_word);
        let blocked = self.core.faults.is_fault_reset_blocked();
        if !self.core.disobeys_word(control_word) {
            self.core.model.write_control_word(control_word, blocked);
        }
        sd2_objects::set_speed_reference(&mut self.core.model, request.speed());
        let service = request.service.map(|s| self.serve(&s));
        let mut reply = sd2_objects::cyclic_reply(&mut self.core.model, request.header);
        reply.service = service;
        reply
    }

    fn serve(&mut self, request: &ServiceChannel) -> ServiceChannel {
        let outcome = match self.service.begin(request) {
            ServiceAction::Resend(reply) => return reply,
            ServiceAction::Read { index, subindex } => {
                sd2_objects::read(&mut self.core.model, index, subindex).and_then(|data| {
                    let s = data.as_slice();
                    let mut out = [0u8; 4];
                    out.get_mut(..s.len())
                        .ok_or(UNSUPPORTED_ACCESS)?
                        .copy_from_slice(s);
                    Ok(out)
                })
            }
            ServiceAction::Write {
                index,
                subindex,
                data,
                valid,
            } => {
                // The object's own size, when the master sent at least that many bytes.
                let n =
                    SimObject::find(index)
                        .map_or(valid, |o| if o.size() <= valid { o.size() } else { valid });
                self.write_object(index, subindex, &data[..n]).map(|()| data)
            }
            ServiceAction::Acknowledge => Ok(request.data),
            ServiceAction::Invalid => {
                self.core.model.trip(INVALID_SERVICE_DRIVE_ERROR);
                Err(UNSUPPORTED_ACCESS)
            }
        };
        self.service.finish(request, outcome)
    }

    /// Encodes `reply` into `bytes` (an empty buffer) and applies the injected faults:
    /// `None` when it is dropped.
    fn send(&mut self, reply: Telegram, now: Duration, mut bytes: Vec<u8>) -> Option<PeerReply> {
        let fate = self.core.faults.next_reply(now);
        if fate.dropped {
            return None;
        }
        let mut reply = reply;
        if fate.wrong_address {
            reply.source = reply.source.wrapping_add(1);
        }
        // Replies are never write commands, so the length-field choice does not apply.
        reply.encode_into(&mut bytes, WriteLength::Captured);
        Some(fate.checked_reply(bytes, |check| !check, now + self.config().response_latency))
    }
}

impl SimFront for Sd2Simulator {
    crate::sim_front_core!((Duration, Telegram));
    fn describe_drive(&self) -> String {
        let c = self.config();
        format!(
            "simulated SD2 at DNC address {} (ramp {} rpm/s)",
            c.address, c.ramp_rpm_per_s
        )
    }
}

impl Peer for Sd2Simulator {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        let mut replies = PeerReplies::default();
        self.receive_into(bytes, now, &mut replies);
        replies.into_list()
    }

    fn exchange_into(
        &mut self,
        bytes: &[u8],
        now: Duration,
        out: &mut PeerReplies,
    ) -> Result<(), crate::bus::TransportError> {
        self.receive_into(bytes, now, out);
        Ok(())
    }

    crate::sim_line_core!();
}

impl Sd2Simulator {
    /// [`Peer::receive`] appended to `replies`.
    fn receive_into(&mut self, bytes: &[u8], now: Duration, replies: &mut PeerReplies) {
        self.core.take_request_at(now);
        self.extractor.push(bytes);
        while let Some(block) = self.extractor.next_block() {
            let Ok(request) = block.telegram else {
                self.corrupt_blocks += 1;
                continue;
            };
            if request.dest != self.config().address || request.is_reply() {
                continue;
            }
            self.core.log_request((now, request));
            let Some(body) = self.answer(&request.body) else {
                continue;
            };
            let reply = Telegram {
                dest: request.source,
                source: self.config().address,
                body,
            };
            let bytes = replies.buffer();
            if let Some(reply) = self.send(reply, now, bytes) {
                replies.push(reply);
            }
        }
    }
}

#[cfg(test)]
#[path = "sd2_simulator_tests.rs"]
mod tests;
