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
use crate::sim::{keep_recent, DriveModel, FaultInjection, SimConfig, SimulatedDrive};
use std::time::Duration;

/// #6.42, whose accepted values are logged.
const CONTROL_WORD: Parameter = Parameter { menu: 6, param: 42 };
/// The earliest a drive answers after a message.
const TURNAROUND: Duration = Duration::from_millis(1);

#[derive(Debug)]
pub struct CtSimulator {
    node: NodeAddress,
    model: DriveModel,
    parameters: CtParameters,
    faults: FaultInjection,
    pending: Vec<u8>,
    /// The parameter of the last completed read or write to this drive: rewrites and short
    /// commands are valid while it is set.
    established: Option<Parameter>,
    logging: bool,
    received: Vec<(Duration, Request)>,
    control_words: Vec<u16>,
}

impl CtSimulator {
    /// A drive just powered up: healthy, disabled, at rest, reference 0.
    pub fn new(node: NodeAddress, config: SimConfig) -> Self {
        let parameters = CtParameters::new(config.max_speed_rpm);
        CtSimulator {
            node,
            model: DriveModel::new(config),
            parameters,
            faults: FaultInjection::default(),
            pending: Vec::new(),
            established: None,
            logging: true,
            received: Vec::new(),
            control_words: Vec::new(),
        }
    }

    pub fn node(&self) -> NodeAddress {
        self.node
    }

    /// The decoded messages that reached this drive (its own address, its group or all).
    pub fn received(&self) -> &[(Duration, Request)] {
        &self.received
    }

    pub fn setpoint_rpm(&self) -> f64 {
        self.model.setpoint_rpm()
    }

    pub fn describe(&self) -> String {
        format!(
            "simulated Unidrive SP at serial address {} (ramp {} rpm/s)",
            self.node,
            self.model.config().ramp_rpm_per_s
        )
    }

    fn advance_to(&mut self, now: Duration) {
        while let Some((at, code)) = self.faults.take_trip_due(now) {
            self.model.advance_to(at);
            self.model.trip(code);
            self.parameters.note_trip(code);
        }
        self.model.advance_to(now);
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
        match self.parameters.read(&mut self.model, parameter) {
            Some(value) => Reply::Value { parameter, value },
            None => Reply::NoSuchParameter,
        }
    }

    fn write(&mut self, parameter: Parameter, value: DataValue) -> Reply {
        self.established = Some(parameter);
        match self.parameters.write(&mut self.model, parameter, value) {
            Ok(Effect::None) => {}
            Ok(Effect::Control(cw)) => self.control(cw),
            Ok(Effect::Reset) => {
                let blocked = self.faults.is_fault_reset_blocked();
                if matches!(self.model.state(), DeviceState::Fault) {
                    self.model.write_control_word(0, blocked);
                    self.model.write_control_word(0x80, blocked);
                }
            }
            Err(Refusal::NoSuchParameter | Refusal::ReadOnly | Refusal::OutOfRange) => return Reply::Refused,
        }
        if parameter == CONTROL_WORD {
            self.log_control_word(self.parameters.control_word());
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
        if matches!(
            self.model.state(),
            DeviceState::OperationEnabled | DeviceState::QuickStopActive
        ) && self.faults.ignores(command)
        {
            return;
        }
        let blocked = self.faults.is_fault_reset_blocked();
        for _ in 0..3 {
            let word = match (self.model.state(), target) {
                (from, to) if from == to => return,
                (_, DeviceState::SwitchOnDisabled) => 0,
                (DeviceState::SwitchOnDisabled, _) => 6,
                (DeviceState::ReadyToSwitchOn, _) | (DeviceState::OperationEnabled, _) => 7,
                (DeviceState::SwitchedOn, _) => 15,
                // Tripped or braking: the control word waits for the reset.
                _ => return,
            };
            self.model.write_control_word(word, blocked);
        }
    }

    fn log_control_word(&mut self, cw: u16) {
        if self.logging {
            keep_recent(&mut self.control_words, cw);
        }
    }

    /// Encodes `reply` and applies the injected faults: `None` when it is dropped.
    fn send(&mut self, reply: Reply, now: Duration) -> Option<PeerReply> {
        let fate = self.faults.next_reply();
        if fate.dropped {
            return None;
        }
        let mut bytes = reply.encode().ok()?;
        if fate.corrupt_checksum {
            if let Some(last) = bytes.last_mut() {
                *last ^= 0x01;
            }
        }
        Some(PeerReply {
            at: now + TURNAROUND.max(self.model.config().response_latency) + fate.extra_delay,
            bytes,
        })
    }
}

impl Peer for CtSimulator {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        if self.faults.take_panic_due(now) {
            panic!("injected test fault: the simulated drive panics while handling a request");
        }
        self.advance_to(now);
        self.parameters.note_trip(self.model.drive_error());
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
                    if mine && self.logging {
                        keep_recent(&mut self.received, (now, request));
                    }
                    if let Some(reply) = self.answer(request) {
                        replies.extend(self.send(reply, now));
                    }
                }
            }
        }
        replies
    }

    fn reachable(&self, now: Duration) -> bool {
        self.faults.line_up(now)
    }
}

impl SimulatedDrive for CtSimulator {
    fn faults(&mut self) -> &mut FaultInjection {
        &mut self.faults
    }
    fn control_words_written(&self) -> Vec<u16> {
        self.control_words.clone()
    }
    fn state(&self) -> DeviceState {
        self.model.state()
    }
    fn speed_rpm(&self, now: Duration) -> f64 {
        self.model.speed_at(&self.faults, now)
    }
    fn set_logging(&mut self, on: bool) {
        self.logging = on;
    }
    fn describe(&self) -> String {
        CtSimulator::describe(self)
    }
    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}

#[cfg(test)]
#[path = "ct_simulator_tests.rs"]
mod tests;
