//! The simulated inverter as a byte-level peer: cuts incoming bytes into RTU frames (or
//! MBAP frames for Modbus TCP), answers those addressed to its slave id with the exact
//! bytes an inverter sends, acts on broadcasts (slave 0) without answering, ignores frames
//! with a bad CRC as a slave does, and applies the injected faults to the replies. As the
//! Application Protocol V1.1b3 asks (6.x state diagrams, 7), a function it does not support
//! (04, 0x17, any other code) is answered with exception 01 and a request whose length
//! fields disagree (FC 16's byte count) with 03, on RTU as on TCP; an RTU frame ends with
//! a silence (Serial Line V1.02, 2.5.1.1), so what a truncated frame left is dropped once
//! the line was quiet, and the next request is read whole. It must not take shortcuts
//! around the codec and must not read a clock of its own.

use super::inverter_registers::{InverterRegisters, Refusal, RUN_COMMAND};
use crate::bus::{Peer, PeerReply};
use crate::family::modbus::codec::{mbap, rtu, ExceptionCode, Function, Request, Response};
use crate::family::modbus::Framing;
use crate::sim::{SimConfig, SimCore, SimFront};
use std::time::Duration;

/// The earliest an inverter answers after a request.
const TURNAROUND: Duration = Duration::from_millis(1);
/// RTU: bytes left over from an incomplete frame are dropped after this much silence. The
/// specification's 3.5 characters are 4 ms at 9600 bit/s; a simulator on a loaded machine
/// allows more, so that scheduling never cuts a frame that came in pieces.
const RTU_SILENCE: Duration = Duration::from_millis(20);

#[derive(Debug)]
pub struct ModbusSimulator {
    unit: u8,
    framing: Framing,
    core: SimCore<(Duration, Request)>,
    registers: InverterRegisters,
    pending: Vec<u8>,
    /// When the last bytes came (RTU's silence counts from here).
    last_bytes: Duration,
}

impl ModbusSimulator {
    pub fn new(unit: u8, framing: Framing, config: SimConfig) -> Self {
        ModbusSimulator {
            unit,
            framing,
            core: SimCore::new(config),
            registers: InverterRegisters::default(),
            pending: Vec::new(),
            last_bytes: Duration::ZERO,
        }
    }

    pub fn unit(&self) -> u8 {
        self.unit
    }

    /// The requests addressed to this slave (broadcasts included), decoded.
    pub fn received(&self) -> &[(Duration, Request)] {
        self.core.requests()
    }

    pub fn setpoint_rpm(&self) -> f64 {
        self.core.model.setpoint_rpm()
    }

    fn write(&mut self, register: u16, value: u16) -> Result<(), Refusal> {
        let command = self.registers.write(&mut self.core.model, register, value)?;
        if register == RUN_COMMAND {
            self.core.log_control_word(value);
        }
        if let Some(command) = command {
            if !self.core.disobeys(command) {
                InverterRegisters::command(&mut self.core.model, &self.core.faults, command);
            }
        }
        Ok(())
    }

    fn answer(&mut self, request: &Request) -> Response {
        let refused = |function: Function, refusal: Refusal| Response::Exception {
            function: function.code(),
            code: match refusal {
                Refusal::Address => ExceptionCode::ILLEGAL_DATA_ADDRESS,
                Refusal::Value => ExceptionCode::ILLEGAL_DATA_VALUE,
            },
        };
        match request {
            Request::Read {
                function: function @ Function::ReadHolding,
                start,
                count,
            } => {
                let values: Result<Vec<u16>, Refusal> = (0..*count)
                    .map(|i| {
                        let register = start.checked_add(i).ok_or(Refusal::Address)?;
                        self.registers.read(&mut self.core.model, register)
                    })
                    .collect();
                match values {
                    Ok(values) => Response::Registers {
                        function: *function,
                        values,
                    },
                    Err(r) => refused(*function, r),
                }
            }
            // The E500 manual documents only holding registers (functions 03, 06, 16): input
            // registers are a function this slave does not support, exception 01 (6.4: the
            // function code is checked before the address).
            Request::Read { function, .. } => Response::Exception {
                function: function.code(),
                code: ExceptionCode::ILLEGAL_FUNCTION,
            },
            Request::WriteSingle { address, value } => match self.write(*address, *value) {
                Ok(()) => Response::WriteSingle {
                    address: *address,
                    value: *value,
                },
                Err(r) => refused(Function::WriteSingle, r),
            },
            Request::WriteMultiple { start, values } => {
                let mut result = Ok(());
                for (i, value) in values.iter().enumerate() {
                    result = result.and_then(|()| {
                        let register = start.checked_add(i as u16).ok_or(Refusal::Address)?;
                        self.write(register, *value)
                    });
                }
                match result {
                    Ok(()) => Response::WriteMultiple {
                        start: *start,
                        count: values.len() as u16,
                    },
                    Err(r) => refused(Function::WriteMultiple, r),
                }
            }
            Request::ReadWrite { .. } => Response::Exception {
                function: Function::ReadWrite.code(),
                code: ExceptionCode::ILLEGAL_FUNCTION,
            },
        }
    }

    /// The next whole frame in what has come: its unit, PDU, transaction id (TCP).
    fn next_frame(&mut self) -> Option<Option<(u8, Vec<u8>, u16)>> {
        match self.framing {
            // What came in one piece and carries a right CRC is one frame, whatever its
            // function code or length fields say: it is answered (an exception where they
            // are wrong), not taken apart as noise.
            Framing::Rtu if self.pending.len() >= 4 && rtu::decode(&self.pending).is_ok() => {
                let frame = std::mem::take(&mut self.pending);
                Some(
                    rtu::decode(&frame)
                        .ok()
                        .map(|(unit, pdu)| (unit, pdu.to_vec(), 0)),
                )
            }
            Framing::Rtu => match rtu::split(&self.pending, rtu::Sender::Master) {
                rtu::Split::Incomplete => None,
                rtu::Split::Noise(n) => {
                    self.pending.drain(..n);
                    Some(None)
                }
                rtu::Split::Frame(n) => {
                    let frame: Vec<u8> = self.pending.drain(..n).collect();
                    // A slave ignores a frame whose CRC is wrong.
                    Some(
                        rtu::decode(&frame)
                            .ok()
                            .map(|(unit, pdu)| (unit, pdu.to_vec(), 0)),
                    )
                }
            },
            Framing::Tcp => {
                let n = mbap::frame_len(&self.pending)?;
                if self.pending.len() < n {
                    return None;
                }
                let frame: Vec<u8> = self.pending.drain(..n).collect();
                Some(
                    mbap::decode(&frame)
                        .ok()
                        .map(|f| (f.unit, f.pdu.to_vec(), f.transaction)),
                )
            }
        }
    }

    fn send(&mut self, response: &Response, transaction: u16, now: Duration) -> Option<PeerReply> {
        let fate = self.core.faults.next_reply(now);
        if fate.dropped {
            return None;
        }
        let unit = if fate.wrong_address {
            self.unit.wrapping_add(1)
        } else {
            self.unit
        };
        let pdu = response.encode();
        let bytes = match self.framing {
            Framing::Rtu => rtu::encode(unit, &pdu),
            Framing::Tcp => mbap::encode(transaction, unit, &pdu),
        };
        let at = self.core.reply_at(now, TURNAROUND);
        Some(fate.checked_reply(bytes, |check| check ^ 0x01, at))
    }
}

impl Peer for ModbusSimulator {
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        self.core.take_request_at(now);
        if self.framing == Framing::Rtu && now.saturating_sub(self.last_bytes) > RTU_SILENCE {
            self.pending.clear();
        }
        self.last_bytes = now;
        self.pending.extend_from_slice(bytes);
        let mut replies = Vec::new();
        while let Some(frame) = self.next_frame() {
            let Some((unit, pdu, transaction)) = frame else {
                continue;
            };
            let broadcast = self.framing == Framing::Rtu && unit == rtu::BROADCAST;
            if unit != self.unit && !broadcast {
                continue;
            }
            let request = match Request::decode(&pdu) {
                Ok(r) => r,
                Err(_) if broadcast => continue,
                Err(_) => {
                    let function = pdu.first().copied().unwrap_or(0) & 0x7F;
                    let code = if Function::of(function).is_ok() {
                        ExceptionCode::ILLEGAL_DATA_VALUE
                    } else {
                        ExceptionCode::ILLEGAL_FUNCTION
                    };
                    replies.extend(self.send(&Response::Exception { function, code }, transaction, now));
                    continue;
                }
            };
            self.core.log_request((now, request.clone()));
            if broadcast && !request.writes() {
                continue;
            }
            let response = self.answer(&request);
            if !broadcast {
                replies.extend(self.send(&response, transaction, now));
            }
        }
        replies
    }

    fn reachable(&self, now: Duration) -> bool {
        self.core.faults.line_up(now)
    }
}

impl SimFront for ModbusSimulator {
    crate::sim_front_core!((Duration, Request));
    fn describe_drive(&self) -> String {
        let at = match self.framing {
            Framing::Rtu => format!("Modbus RTU slave {}", self.unit),
            Framing::Tcp => format!("Modbus TCP unit {}", self.unit),
        };
        format!(
            "simulated inverter (Sunfar E500 register map) at {at} (ramp {} rpm/s)",
            self.core.model.config().ramp_rpm_per_s
        )
    }
}
