//! The simulated 931: request lines in, reply lines out, over the drive model; see the
//! module docs for the choices it makes. It must not read a clock of its own: time is the
//! `now` it is given.

use super::sim_objects::SimObject;
use crate::bus::{Peer, PeerReply};
use crate::family::lenze_931::codec::{BootState, ErrorCode, LineExtractor, ObjectCommand, Reply, Request};
use crate::sim::{DriveModel, SimConfig, SimCore, SimFront};
use std::time::Duration;

/// CANopen objects the SDO simulation answers: control word, status word, actual speed.
const SDO_CONTROL_WORD: (u16, u8) = (0x6040, 0);
const SDO_STATUS_WORD: (u16, u8) = (0x6041, 0);
const SDO_SPEED_ACTUAL: (u16, u8) = (0x606C, 0);

#[derive(Debug)]
pub struct LenzeSimulator {
    /// The model, the faults and the logs (the request lines, the control words).
    core: SimCore<String>,
    extractor: LineExtractor,
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
            core: SimCore::new(config),
            extractor: LineExtractor::new(),
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
        self.core.requests()
    }

    pub fn setpoint_rpm(&self) -> f64 {
        self.core.model.setpoint_rpm()
    }

    /// The operating mode (the drive model's parameter set).
    pub fn operating_mode(&self) -> u16 {
        self.core.model.parameter_set()
    }

    /// The baud rate the last `BAUDbbbb` set (9600 until then); the simulated line itself
    /// keeps working at any rate.
    pub fn line_rate(&self) -> u32 {
        self.line_rate
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
                self.core.model = DriveModel::new(self.core.model.config().clone());
                Reply::SwitchOn(match request {
                    Request::Init => "931 SIMULATED: default parameter set loaded".into(),
                    _ => "931 SIMULATED: reset".into(),
                })
            }
            Request::Save => {
                self.flash_mode = self.core.model.parameter_set();
                Reply::Done
            }
            Request::Sep => {
                // The model keeps its mode while enabled, as for a write of the mode.
                let _ = self.core.model.set_parameter_set(self.flash_mode);
                Reply::Done
            }
            Request::Type => Reply::Type("0931".into()),
            Request::Version => Reply::Version {
                status: "0000".into(),
                version: "0100".into(),
            },
            Request::SdoRead { index, subindex } => {
                let data = match (index, subindex) {
                    SDO_CONTROL_WORD => self.core.model.control_word().to_le_bytes().to_vec(),
                    SDO_STATUS_WORD => self.core.model.status_word().to_le_bytes().to_vec(),
                    SDO_SPEED_ACTUAL => (self.core.model.measured_speed_rpm().round() as i32)
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
            ObjectCommand::Read | ObjectCommand::Write => object.read(&mut self.core.model),
            ObjectCommand::Internal => object.internal(&mut self.core.model),
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
                if self.core.disobeys_word(cw) {
                    self.core.log_control_word(cw);
                    return Reply::Ok;
                }
            }
        }
        let blocked = self.core.faults.is_fault_reset_blocked();
        match object.write(&mut self.core.model, value, blocked) {
            Ok(limited) => {
                if object == SimObject::ControlWord {
                    self.core.log_control_word(value as u16);
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
        self.core.log_control_word(cw);
        if !self.core.disobeys_word(cw) {
            let blocked = self.core.faults.is_fault_reset_blocked();
            self.core.model.write_control_word(cw, blocked);
        }
    }

    /// The reply's bytes with the injected faults applied; `None` when it is dropped.
    fn send(&mut self, reply: &Reply, now: Duration) -> Option<PeerReply> {
        let fate = self.core.faults.next_reply(now);
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
        Some(fate.reply(bytes, now + self.core.model.config().response_latency))
    }
}

impl Peer for LenzeSimulator {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        self.core.take_request_at(now);
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
                    self.core.log_request(request.text());
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

    crate::sim_line_core!();
}

impl SimFront for LenzeSimulator {
    crate::sim_front_core!(String);
    fn describe_drive(&self) -> String {
        format!(
            "simulated Lenze 931 on RS232 (ramp {} rpm/s; object numbers are the simulator's own, see dictionary/lenze-931.yaml)",
            self.core.model.config().ramp_rpm_per_s
        )
    }
}

#[cfg(test)]
#[path = "lenze_simulator_tests.rs"]
mod tests;
