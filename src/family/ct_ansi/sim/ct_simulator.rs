//! The simulated Control Techniques drive as a byte-level peer: cuts incoming bytes into
//! messages, answers those addressed to it with the exact reply bytes a drive sends, acts
//! on group and global writes without answering, and applies the injected faults to the
//! replies. It must not take shortcuts around the codec and must not read a clock of its
//! own: time is the `now` it is given.

use super::ct_parameters::{target_state, CtParameters, Effect, Refusal};
use crate::bus::{Peer, PeerReply};
use crate::drive::device_control::{DeviceCommand, DeviceState};
use crate::family::ct_ansi::codec::{
    split, DataValue, NodeAddress, Parameter, Reply, Request, Sender, Split,
};
use crate::sim::{SimConfig, SimCore, SimFront};
use std::time::Duration;

/// #6.42, whose accepted values are logged.
const CONTROL_WORD: Parameter = Parameter { menu: 6, param: 42 };
/// The earliest a drive answers after a message.
const TURNAROUND: Duration = Duration::from_millis(1);

#[derive(Debug)]
pub struct CtSimulator {
    node: NodeAddress,
    /// The model, the faults and the logs: the decoded messages that reached this drive
    /// (its own address, its group or all) and the values #6.42 accepted.
    core: SimCore<(Duration, Request)>,
    parameters: CtParameters,
    pending: Vec<u8>,
    /// The parameter of the last completed read or write to this drive: rewrites and short
    /// commands are valid while it is set.
    established: Option<Parameter>,
}

impl CtSimulator {
    /// A drive just powered up: healthy, disabled, at rest, reference 0.
    pub fn new(node: NodeAddress, config: SimConfig) -> Self {
        let parameters = CtParameters::new(config.max_speed_rpm);
        CtSimulator {
            node,
            core: SimCore::new(config),
            parameters,
            pending: Vec::new(),
            established: None,
        }
    }

    pub fn node(&self) -> NodeAddress {
        self.node
    }

    /// The decoded messages that reached this drive (its own address, its group or all).
    pub fn received(&self) -> &[(Duration, Request)] {
        self.core.requests()
    }

    pub fn setpoint_rpm(&self) -> f64 {
        self.core.model.setpoint_rpm()
    }

    fn advance_to(&mut self, now: Duration) {
        while let Some((at, code)) = self.core.faults.take_trip_due(now) {
            self.core.model.advance_to(at);
            self.core.model.trip(code);
            self.parameters.note_trip(code);
        }
        self.core.model.advance_to(now);
    }

    /// The reply to one message, `None` when the drive stays silent.
    fn answer(&mut self, request: Request) -> Option<Reply> {
        match request {
            Request::Read { address, parameter } => {
                if address != self.node {
                    // Another drive's (or a colliding group) read: the address is gone.
                    self.established = None;
                    return None;
                }
                Some(self.read(parameter))
            }
            Request::Write {
                address: Some(address),
                parameter,
                value,
            } => {
                if !self.node.accepts(address) {
                    self.established = None;
                    return None;
                }
                let reply = self.write(parameter, value);
                if address.is_broadcast() {
                    // Acted on, never answered; it establishes no address either.
                    self.established = None;
                    return None;
                }
                Some(reply)
            }
            Request::Write {
                address: None,
                parameter,
                value,
            } => {
                self.established?;
                Some(self.write(parameter, value))
            }
            Request::ReadAgain => self.established.map(|p| self.read(p)),
            Request::ReadNext => self.established.map(|p| self.read(p.next())),
            Request::ReadPrevious => self.established.map(|p| self.read(p.previous())),
        }
    }

    fn read(&mut self, parameter: Parameter) -> Reply {
        // Even a read of a parameter that does not exist establishes the address.
        self.established = Some(parameter);
        match self.parameters.read(&mut self.core.model, parameter) {
            Some(value) => Reply::Value { parameter, value },
            None => Reply::NoSuchParameter,
        }
    }

    fn write(&mut self, parameter: Parameter, value: DataValue) -> Reply {
        self.established = Some(parameter);
        match self.parameters.write(&mut self.core.model, parameter, value) {
            Ok(Effect::None) => {}
            Ok(Effect::Control(cw)) => self.control(cw),
            Ok(Effect::Reset) => {
                let blocked = self.core.faults.is_fault_reset_blocked();
                if matches!(self.core.model.state(), DeviceState::Fault) {
                    self.core.model.write_control_word(0, blocked);
                    self.core.model.write_control_word(0x80, blocked);
                }
            }
            Err(Refusal::NoSuchParameter | Refusal::ReadOnly | Refusal::OutOfRange) => return Reply::Refused,
        }
        if parameter == CONTROL_WORD {
            self.core.log_control_word(self.parameters.control_word());
        }
        Reply::Accepted
    }

    /// Carries out a control word on the CiA 402 model, one transition at a time. An
    /// injected fault can make the running drive ignore it.
    fn control(&mut self, cw: u16) {
        let target = target_state(cw);
        let command = match target {
            DeviceState::SwitchOnDisabled => DeviceCommand::DisableVoltage,
            DeviceState::SwitchedOn => DeviceCommand::DisableOperation,
            _ => DeviceCommand::EnableOperation,
        };
        if self.core.disobeys(command) {
            return;
        }
        let blocked = self.core.faults.is_fault_reset_blocked();
        self.core.model.walk_to(target, blocked);
    }

    /// Encodes `reply` and applies the injected faults: `None` when it is dropped.
    fn send(&mut self, reply: Reply, now: Duration) -> Option<PeerReply> {
        let fate = self.core.faults.next_reply(now);
        if fate.dropped {
            return None;
        }
        let bytes = reply.encode().ok()?;
        let at = self.core.reply_at(now, TURNAROUND);
        Some(fate.checked_reply(bytes, |check| check ^ 0x01, at))
    }
}

impl Peer for CtSimulator {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        self.core.panic_if_due(now);
        self.advance_to(now);
        self.parameters.note_trip(self.core.model.drive_error());
        self.pending.extend_from_slice(bytes);
        let mut replies = Vec::new();
        loop {
            match split(&self.pending, Sender::Master) {
                Split::Incomplete => break,
                Split::Noise(n) => {
                    // EOT and anything unexpected abort: the address is gone.
                    self.pending.drain(..n);
                    self.established = None;
                }
                Split::Message(n) => {
                    let message: Vec<u8> = self.pending.drain(..n).collect();
                    let Ok(request) = Request::decode(&message) else {
                        self.established = None;
                        continue;
                    };
                    let mine = match request {
                        Request::Read { address, .. }
                        | Request::Write {
                            address: Some(address),
                            ..
                        } => self.node.accepts(address),
                        _ => self.established.is_some(),
                    };
                    if mine {
                        self.core.log_request((now, request));
                    }
                    if let Some(reply) = self.answer(request) {
                        replies.extend(self.send(reply, now));
                    }
                }
            }
        }
        replies
    }

    crate::sim_line_core!();
}

impl SimFront for CtSimulator {
    crate::sim_front_core!((Duration, Request));
    fn describe_drive(&self) -> String {
        format!(
            "simulated Unidrive SP at serial address {} (ramp {} rpm/s)",
            self.node,
            self.core.model.config().ramp_rpm_per_s
        )
    }
}

#[cfg(test)]
#[path = "ct_simulator_tests.rs"]
mod tests;
