//! The simulated 931: request lines in, reply lines out, over the drive model; see the
//! module docs for the choices it makes. It must not read a clock of its own: time is the
//! `now` it is given.

use super::sim_objects::SimObject;
use crate::bus::{Peer, PeerReply};
use crate::drive::device_control::DeviceState;
use crate::family::lenze_931::codec::{BootState, ErrorCode, LineExtractor, ObjectCommand, Reply, Request};
use crate::sim::{keep_recent, DriveModel, FaultInjection, SimConfig, SimulatedDrive};
use std::time::Duration;

/// CANopen objects the SDO simulation answers: control word, status word, actual speed.
const SDO_CONTROL_WORD: (u16, u8) = (0x6040, 0);
const SDO_STATUS_WORD: (u16, u8) = (0x6041, 0);
const SDO_SPEED_ACTUAL: (u16, u8) = (0x606C, 0);

#[derive(Debug)]
pub struct LenzeSimulator {
    model: DriveModel,
    extractor: LineExtractor,
    faults: FaultInjection,
    logging: bool,
    control_words: Vec<u16>,
    requests: Vec<String>,
    echo: bool,
    crlf: bool,
    /// The operating mode `SAVE!` stored and `SEP!` loads (the simulator's flash).
    flash_mode: u16,
    /// The rate `BAUDbbbb` set last (a pty or TCP line has no rate to change).
    line_rate: u32,
}

impl LenzeSimulator {
    /// A drive just switched on: switch on disabled, at rest, setpoint 0.
    pub fn new(config: SimConfig) -> Self {
        LenzeSimulator {
            model: DriveModel::new(config),
            extractor: LineExtractor::new(),
            faults: FaultInjection::default(),
            logging: true,
            control_words: Vec::new(),
            requests: Vec::new(),
            echo: false,
            crlf: false,
            flash_mode: 0,
            line_rate: 9600,
        }
    }

    /// Echo every request line before the reply (as a converter that echoes would).
    pub fn set_echo(&mut self, on: bool) {
        self.echo = on;
    }

    /// End replies with CR LF instead of CR.
    pub fn set_crlf(&mut self, on: bool) {
        self.crlf = on;
    }

    /// The request lines received, in order (while logging is on; the latest 10 000).
    pub fn requests(&self) -> &[String] {
        &self.requests
    }

    pub fn setpoint_rpm(&self) -> f64 {
        self.model.setpoint_rpm()
    }

    /// The operating mode (the drive model's parameter set).
    pub fn operating_mode(&self) -> u16 {
        self.model.parameter_set()
    }

    /// The baud rate the last `BAUDbbbb` set (9600 until then); the simulated line itself
    /// keeps working at any rate.
    pub fn line_rate(&self) -> u32 {
        self.line_rate
    }

    fn advance_to(&mut self, now: Duration) {
        while let Some((at, code)) = self.faults.take_trip_due(now) {
            self.model.advance_to(at);
            self.model.trip(code);
        }
        self.model.advance_to(now);
    }

    fn answer(&mut self, request: &Request) -> Reply {
        match *request {
            Request::Read { command, object } => self.read(command, object),
            Request::Write { object, value } => self.write(object, value),
            Request::Baud(rate) => {
                self.line_rate = rate;
                Reply::Ok
            }
            Request::Boot => Reply::Boot(BootState::Application),
            Request::Bus => Reply::Bus {
                status: "0000".into(),
                node: "01".into(),
                baud: "0500".into(),
                mode: "0000".into(),
            },
            // Both restart the drive with the default parameter set: a switch-on message
            // is what the manual says either answers with.
            Request::Init | Request::Reset => {
                self.model = DriveModel::new(self.model.config().clone());
                Reply::SwitchOn(match request {
                    Request::Init => "931 SIMULATED: default parameter set loaded".into(),
                    _ => "931 SIMULATED: reset".into(),
                })
            }
            Request::Save => {
                self.flash_mode = self.model.parameter_set();
                Reply::Done
            }
            Request::Sep => {
                // The model keeps its mode while enabled, as for a write of the mode.
                let _ = self.model.set_parameter_set(self.flash_mode);
                Reply::Done
            }
            Request::Type => Reply::Type("0931".into()),
            Request::Version => Reply::Version {
                status: "0000".into(),
                version: "0100".into(),
            },
            Request::SdoRead { index, subindex } => {
                let data = match (index, subindex) {
                    SDO_CONTROL_WORD => self.model.control_word().to_le_bytes().to_vec(),
                    SDO_STATUS_WORD => self.model.status_word().to_le_bytes().to_vec(),
                    SDO_SPEED_ACTUAL => (self.model.measured_speed_rpm().round() as i32)
                        .to_le_bytes()
                        .to_vec(),
                    _ => return Reply::UnknownCommand,
                };
                Reply::Sdo {
                    index,
                    subindex,
                    data,
                }
            }
            Request::SdoWrite {
                index,
                subindex,
                ref data,
            } => match ((index, subindex), data.as_slice()) {
                (SDO_CONTROL_WORD, &[lo, hi]) => {
                    let cw = u16::from_le_bytes([lo, hi]);
                    self.control_word(cw);
                    Reply::Sdo {
                        index,
                        subindex,
                        data: data.clone(),
                    }
                }
                _ => Reply::UnknownCommand,
            },
        }
    }

    fn read(&mut self, command: ObjectCommand, number: u16) -> Reply {
        let error = |code| Reply::Error { command, code };
        let Some(object) = SimObject::find(number) else {
            return error(ErrorCode::NO_OBJECT);
        };
        let value = match command {
            ObjectCommand::Read | ObjectCommand::Write => object.read(&mut self.model),
            ObjectCommand::Internal => object.internal(&mut self.model),
            ObjectCommand::Min => match object.limits().0 {
                Some(v) => v,
                None => return error(ErrorCode::NO_LOWER_LIMIT),
            },
            ObjectCommand::Max => match object.limits().1 {
                Some(v) => v,
                None => return error(ErrorCode::NO_UPPER_LIMIT),
            },
        };
        Reply::Value {
            object: number,
            value: value as i32 as u32,
        }
    }

    fn write(&mut self, number: u16, bits: u32) -> Reply {
        let error = |code| Reply::Error {
            command: ObjectCommand::Write,
            code,
        };
        let Some(object) = SimObject::find(number) else {
            return error(ErrorCode::NO_OBJECT);
        };
        let value = i64::from(bits as i32);
        if object == SimObject::ControlWord {
            if let Ok(cw) = u16::try_from(value) {
                if self.disobeys(cw) {
                    self.log_control_word(cw);
                    return Reply::Ok;
                }
            }
        }
        let blocked = self.faults.is_fault_reset_blocked();
        match object.write(&mut self.model, value, blocked) {
            Ok(limited) => {
                if object == SimObject::ControlWord {
                    self.log_control_word(value as u16);
                }
                match limited {
                    Some(code) => error(code),
                    None => Reply::Ok,
                }
            }
            Err(code) => error(code),
        }
    }

    fn control_word(&mut self, cw: u16) {
        self.log_control_word(cw);
        if !self.disobeys(cw) {
            let blocked = self.faults.is_fault_reset_blocked();
            self.model.write_control_word(cw, blocked);
        }
    }

    fn disobeys(&self, control_word: u16) -> bool {
        matches!(
            self.model.state(),
            DeviceState::OperationEnabled | DeviceState::QuickStopActive
        ) && self.faults.ignores(self.model.command_for(control_word))
    }

    fn log_control_word(&mut self, cw: u16) {
        if self.logging {
            keep_recent(&mut self.control_words, cw);
        }
    }

    /// The reply's bytes with the injected faults applied; `None` when it is dropped.
    fn send(&mut self, reply: &Reply, now: Duration) -> Option<PeerReply> {
        let fate = self.faults.next_reply();
        if fate.dropped {
            return None;
        }
        let mut text = match (reply, fate.wrong_address) {
            (Reply::Value { object, value }, true) => Reply::Value {
                object: object.wrapping_add(1),
                value: *value,
            }
            .text(),
            _ => reply.text(),
        };
        if fate.corrupt_checksum {
            let mid = text.len() / 2;
            text.replace_range(mid..=mid.min(text.len().saturating_sub(1)), "#");
        }
        let mut bytes = text.into_bytes();
        bytes.push(b'\r');
        if self.crlf {
            bytes.push(b'\n');
        }
        Some(PeerReply {
            at: now + self.model.config().response_latency + fate.extra_delay,
            bytes,
        })
    }
}

impl Peer for LenzeSimulator {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        if self.faults.take_panic_due(now) {
            panic!("injected test fault: the simulated drive panics while handling a request");
        }
        self.advance_to(now);
        self.extractor.push(bytes);
        let mut replies = Vec::new();
        while let Some(line) = self.extractor.next_line() {
            if self.echo && !line.bytes.is_empty() {
                let mut echo = line.bytes.clone();
                echo.push(b'\r');
                replies.push(PeerReply { at: now, bytes: echo });
            }
            let reply = match line.text.as_deref().map(Request::parse) {
                Ok(Ok(request)) => {
                    if self.logging {
                        keep_recent(&mut self.requests, request.text());
                    }
                    self.answer(&request)
                }
                // Garbage, an over-long line or an unknown command: what any unknown
                // command gets.
                _ => Reply::UnknownCommand,
            };
            replies.extend(self.send(&reply, now));
        }
        replies
    }

    fn reachable(&self, now: Duration) -> bool {
        self.faults.line_up(now)
    }
}

impl SimulatedDrive for LenzeSimulator {
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
        format!(
            "simulated Lenze 931 on RS232 (ramp {} rpm/s; object numbers are the simulator's own, see dictionary/lenze-931.yaml)",
            self.model.config().ramp_rpm_per_s
        )
    }
    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}

#[cfg(test)]
#[path = "lenze_simulator_tests.rs"]
mod tests;
