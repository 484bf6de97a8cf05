//! Object access through the DNC 8-byte cyclic telegram: control word and speed reference
//! go out in every telegram; status word, actual speed, drive error (and, with a stated
//! scaling, actual current) come back in every reply, so one round trip answers several
//! reads. Other objects travel in the acyclic service channel of the same telegram; what
//! the service channel cannot carry (more than 4 bytes, a subindex) goes by object access.
//!
//! The last control word and speed reference are repeated, never invented: before the first
//! telegram both are read from the drive (objects 68 and 395). The telegram is sent at
//! least every `period` while the session waits (see [`ObjectAccess::keep_alive`]).
//!
//! Not in the sources, and therefore this module's own choices (the simulator makes the
//! same ones, see `sim/service_channel.rs`): a service reply is complete when it echoes
//! the request's index, toggle and function; state bit 7 set means the access failed with
//! the SD2 error code in sdata0. Marked in README as unconfirmed on hardware.

use super::codec::{Cyclic, ErrorCode, ServiceChannel, ServiceFunction, SPEED_FULL_SCALE};
use super::cyclic_settings::CyclicSettings;
use super::wire_value;
use super::Sd2Access;
use crate::clock::SharedClock;
use crate::dictionary::{Address, DataType, RawValue};
use crate::drive::{AccessError, ObjectAccess, WriteOutcome, WriteResult};
use crate::link::CoreLink;
use std::time::Duration;

/// One service of the channel: its function, the object, how many bytes of the data field
/// count, and the data written (zeros for a read).
#[derive(Debug, Clone, Copy)]
struct Service {
    function: ServiceFunction,
    index: u16,
    size: u8,
    data: [u8; 4],
}

impl Service {
    fn read(index: u16, size: u8) -> Service {
        Service {
            function: ServiceFunction::Read,
            index,
            size,
            data: [0; 4],
        }
    }
}

/// Objects the process data carries. 67, 68, 395 and 398 are in the sources; 400 and 401
/// are the built-in dictionary's (unconfirmed) current and drive-error objects.
const STATUS_WORD: u16 = 67;
const CONTROL_WORD: u16 = 68;
pub(super) const SPEED_SETPOINT: u16 = 395;
const SPEED_ACTUAL: u16 = 398;
const CURRENT_ACTUAL: u16 = 400;
const DRIVE_ERROR: u16 = 401;
/// Objects 395 and 398 count 0.001 rpm; 400 counts 0.001 A in the built-in dictionary.
const COUNTS_PER_RPM: f64 = 1000.0;
const COUNTS_PER_AMPERE: f64 = 1000.0;
/// A service reply that has not come after this many telegrams is given up.
const SERVICE_TELEGRAMS: u32 = 50;
/// Reply state bit 7: the service failed.
const SERVICE_FAILED: u8 = 0x80;

pub struct Sd2CyclicAccess {
    /// The object channel on the same link: start values, and objects the service
    /// channel cannot carry.
    object: Sd2Access,
    settings: CyclicSettings,
    /// What goes out in every telegram; `None` until read from the drive.
    output: Option<(u16, i16)>,
    /// The next telegram's heartbeat toggle.
    heartbeat: bool,
    /// The toggle of the last service request (the first request uses the other value,
    /// as the printed examples do: read with toggle 0, then write with toggle 1).
    service_toggle: bool,
    /// Whether a service went through since the channel opened (until then the drive
    /// may remember another master's toggle).
    service_used: bool,
    last_sent: Option<Duration>,
    /// Set by a reopen: the next output read from the drive is sent with speed 0.
    resume_stopped: bool,
}

/// A value the cyclic reply carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ProcessValue {
    Status,
    Speed,
    DriveError,
    Current,
}

impl Sd2CyclicAccess {
    pub fn new(object: Sd2Access, settings: CyclicSettings) -> Self {
        Sd2CyclicAccess {
            object,
            settings,
            output: None,
            heartbeat: false,
            service_toggle: true,
            service_used: false,
            last_sent: None,
            resume_stopped: false,
        }
    }

    fn dest(&self) -> u8 {
        self.object.dest()
    }

    fn process_value(&self, address: &Address) -> Option<ProcessValue> {
        let Address::Indexed { index, subindex: 0 } = *address else {
            return None;
        };
        match index {
            STATUS_WORD => Some(ProcessValue::Status),
            SPEED_ACTUAL => Some(ProcessValue::Speed),
            DRIVE_ERROR => Some(ProcessValue::DriveError),
            CURRENT_ACTUAL if self.settings.current_scale_a.is_some() => Some(ProcessValue::Current),
            _ => None,
        }
    }

    /// The service channel carries up to 4 bytes of an object without subindex.
    fn service_fits(address: &Address, data_type: DataType) -> Option<(u16, u8)> {
        let Address::Indexed { index, subindex: 0 } = *address else {
            return None;
        };
        let size = u8::try_from(data_type.size())
            .ok()
            .filter(|s| *s <= 4 && data_type.is_integer())?;
        Some((index, size))
    }

    /// Control word and speed reference as the drive has them now, read once.
    fn output(&mut self) -> Result<(u16, i16), AccessError> {
        if let Some(o) = self.output {
            return Ok(o);
        }
        let word = self
            .object
            .read(&Address::indexed(CONTROL_WORD, 0), DataType::U16)?;
        let setpoint = self
            .object
            .read(&Address::indexed(SPEED_SETPOINT, 0), DataType::I32)?;
        let word = word.as_int().and_then(|w| u16::try_from(w).ok()).unwrap_or(0);
        let mut rpm = setpoint.as_int().unwrap_or(0) as f64 / COUNTS_PER_RPM;
        if std::mem::take(&mut self.resume_stopped) {
            rpm = 0.0;
        }
        // A setpoint the drive holds beyond the scaling is sent as the nearest the telegram
        // can carry; it is the drive's own value, not one the user asked for.
        let reference = self.reference(rpm).unwrap_or(if rpm < 0.0 {
            -SPEED_FULL_SCALE
        } else {
            SPEED_FULL_SCALE
        });
        self.output = Some((word, reference));
        Ok((word, reference))
    }

    /// The speed reference for `rpm`: a fraction of the velocity scaling, 0x3FFF = +100 %,
    /// truncated toward zero as in the printed examples (50 % = 0x1FFF, 25 % = 0x0FFF).
    fn reference(&self, rpm: f64) -> Result<i16, AccessError> {
        let fraction = rpm / self.settings.velocity_scaling_rpm;
        if !fraction.is_finite() || fraction.abs() > 1.0 {
            return Err(AccessError::Encode(format!(
                "{rpm} rpm is beyond ±100 % of the velocity scaling ({} rpm), the most the cyclic telegram carries; nothing was sent",
                self.settings.velocity_scaling_rpm
            )));
        }
        Ok((fraction * f64::from(SPEED_FULL_SCALE)).trunc() as i16)
    }

    /// One cyclic round trip with the current output and, optionally, a service request.
    fn exchange(&mut self, service: Option<ServiceChannel>) -> Result<Cyclic, AccessError> {
        let (word, reference) = self.output()?;
        let mut request = Cyclic::request(word, reference, self.settings.heartbeat && self.heartbeat);
        request.service = service;
        if self.settings.heartbeat {
            self.heartbeat = !self.heartbeat;
        }
        let dest = self.dest();
        self.last_sent = Some(self.object.link().clock().now());
        self.object.link_mut().cyclic(dest, request)
    }

    fn value_of(&self, reply: &Cyclic, value: ProcessValue) -> RawValue {
        let counts = match value {
            ProcessValue::Status => i64::from(reply.word()),
            ProcessValue::DriveError => i64::from(reply.drive_error()),
            ProcessValue::Speed => {
                let rpm = f64::from(reply.speed()) / f64::from(SPEED_FULL_SCALE)
                    * self.settings.velocity_scaling_rpm;
                (rpm * COUNTS_PER_RPM).round() as i64
            }
            ProcessValue::Current => {
                let amps = f64::from(reply.current()) * self.settings.current_scale_a.unwrap_or(0.0);
                (amps * COUNTS_PER_AMPERE).round() as i64
            }
        };
        RawValue::Int(counts)
    }

    /// Runs one service (read or write) to completion and returns the reply's data field,
    /// with the process data of the telegram that completed it.
    fn service(&mut self, service: Service) -> Result<(Cyclic, [u8; 4]), AccessError> {
        let fresh_start = !self.service_used;
        match self.service_once(service) {
            // A drive that still remembers another master's toggle takes the first request
            // for a repeat and answers the old service: start again with the other toggle.
            Err(AccessError::BadReply { .. }) if fresh_start => self.service_once(service),
            other => other,
        }
    }

    fn service_once(&mut self, service: Service) -> Result<(Cyclic, [u8; 4]), AccessError> {
        let Service {
            function,
            index,
            size,
            data,
        } = service;
        self.service_toggle = !self.service_toggle;
        let request = ServiceChannel::request(self.service_toggle, function, size, index, data);
        for _ in 0..SERVICE_TELEGRAMS {
            let reply = self.exchange(Some(request))?;
            let Some(answer) = reply.service else { continue };
            if (answer.ctrl & 0x07) != (request.ctrl & 0x07) || answer.index != index {
                continue;
            }
            self.service_used = true;
            if answer.ctrl & SERVICE_FAILED != 0 {
                let code = ErrorCode(answer.data[0]);
                return Err(AccessError::Refused {
                    port: self.object.link().port().to_string(),
                    address: self.dest().to_string(),
                    operation: if function == ServiceFunction::Write {
                        "write"
                    } else {
                        "read"
                    },
                    object: format!("{index} (service channel)"),
                    code: u32::from(code.0),
                    text: code.to_string(),
                });
            }
            return Ok((reply, answer.data));
        }
        Err(self.unexpected(
            format!("service {} of object {index}", function.id()),
            format!("no completed service reply in {SERVICE_TELEGRAMS} telegrams"),
        ))
    }

    /// A reply of this drive that did not bring what `request` asked for.
    fn unexpected(&self, request: String, detail: String) -> AccessError {
        AccessError::UnexpectedReply {
            port: self.object.link().port().to_string(),
            address: self.dest().to_string(),
            request,
            detail,
        }
    }

    /// The value of `object` in the data field of a completed service read.
    fn service_value(
        &self,
        data: &[u8; 4],
        size: u8,
        data_type: DataType,
        object: impl std::fmt::Display,
    ) -> Result<RawValue, AccessError> {
        wire_value::decode(&data[..usize::from(size)], data_type)
            .map_err(|detail| self.unexpected(format!("service read of object {object}"), detail.to_string()))
    }

    fn service_read(
        &mut self,
        address: &Address,
        data_type: DataType,
    ) -> Option<Result<RawValue, AccessError>> {
        let (index, size) = Self::service_fits(address, data_type)?;
        Some(
            self.service(Service::read(index, size))
                .and_then(|(_, data)| self.service_value(&data, size, data_type, index)),
        )
    }
}

impl ObjectAccess for Sd2CyclicAccess {
    fn read(&mut self, address: &Address, data_type: DataType) -> Result<RawValue, AccessError> {
        if let Some(value) = self.process_value(address) {
            let reply = self.exchange(None)?;
            return Ok(self.value_of(&reply, value));
        }
        match self.service_read(address, data_type) {
            Some(result) => result,
            None => self.object.read(address, data_type),
        }
    }

    fn write(&mut self, address: &Address, value: &RawValue, data_type: DataType) -> WriteResult {
        let (word, reference) = self.output()?;
        match *address {
            Address::Indexed {
                index: CONTROL_WORD,
                subindex: 0,
            } => {
                let new = value
                    .as_int()
                    .and_then(|v| u16::try_from(v).ok())
                    .ok_or_else(|| AccessError::Encode(format!("control word {value} is not 0..=65535")))?;
                self.output = Some((new, reference));
                self.exchange(None)?;
                return Ok(WriteOutcome::Stored);
            }
            Address::Indexed {
                index: SPEED_SETPOINT,
                subindex: 0,
            } => {
                let counts = value
                    .as_int()
                    .ok_or_else(|| AccessError::Encode(format!("speed setpoint {value} is not a count")))?;
                let new = self.reference(counts as f64 / COUNTS_PER_RPM)?;
                self.output = Some((word, new));
                self.exchange(None)?;
                return Ok(WriteOutcome::Stored);
            }
            _ => {}
        }
        let Some((index, size)) = Self::service_fits(address, data_type) else {
            return self.object.write(address, value, data_type);
        };
        let bytes = wire_value::encode(value, data_type).map_err(|e| AccessError::Encode(e.to_string()))?;
        let mut data = [0u8; 4];
        data[..bytes.len()].copy_from_slice(&bytes);
        self.service(Service {
            function: ServiceFunction::Write,
            index,
            size,
            data,
        })?;
        Ok(WriteOutcome::Stored)
    }

    fn read_many(&mut self, objects: &[(Address, DataType)], out: &mut Vec<Result<RawValue, AccessError>>) {
        let values = self.read_together(objects);
        out.extend(values);
    }

    fn keep_alive(&mut self) -> Result<Option<Duration>, AccessError> {
        let now = self.object.link().clock().now();
        let period = self.settings.period;
        let due = self
            .last_sent
            .map_or(Duration::ZERO, |t| t.saturating_add(period));
        if now >= due {
            self.exchange(None)?;
            return Ok(Some(period));
        }
        Ok(Some(due - now))
    }

    fn port(&self) -> String {
        format!("{} (cyclic channel)", self.object.port())
    }

    fn clock(&self) -> SharedClock {
        self.object.clock()
    }

    fn reopen(&mut self) -> Result<(), AccessError> {
        self.object.reopen()?;
        // The drive may have been reset: ask it again rather than repeat our memory. A
        // reopen happens only in the safe stop, so the channel does not resume the old
        // speed: it sends 0, which a drive still enabled brakes to under control (clearing
        // the enable instead would let the spindle coast), and the stop goes on from there.
        self.output = None;
        self.resume_stopped = true;
        self.service_used = false;
        Ok(())
    }
}

impl Sd2CyclicAccess {
    /// The objects of [`ObjectAccess::read_many`], the process values and one rider from
    /// a single cyclic telegram.
    fn read_together(&mut self, objects: &[(Address, DataType)]) -> Vec<Result<RawValue, AccessError>> {
        let carried: Vec<Option<ProcessValue>> = objects.iter().map(|(a, _)| self.process_value(a)).collect();
        if carried.iter().all(Option::is_none) && objects.len() < 2 {
            return objects.iter().map(|(a, t)| self.read(a, *t)).collect();
        }
        // One object that is not process data may ride along in the same telegram.
        let rider = objects
            .iter()
            .zip(&carried)
            .position(|((a, t), c)| c.is_none() && Self::service_fits(a, *t).is_some());
        let first = match rider {
            Some(i) => {
                let (address, data_type) = objects[i];
                let (index, size) = Self::service_fits(&address, data_type).unwrap_or((0, 4));
                match self.service(Service::read(index, size)) {
                    Ok((reply, data)) => {
                        let value = self.service_value(&data, size, data_type, address);
                        Ok((reply, Some(value)))
                    }
                    // The drive refused that one object: the process values still come,
                    // and only the refused object fails.
                    Err(refused @ AccessError::Refused { .. }) => {
                        self.exchange(None).map(|reply| (reply, Some(Err(refused))))
                    }
                    Err(e) => Err(e),
                }
            }
            None => self.exchange(None).map(|reply| (reply, None)),
        };
        let (reply, ridden) = match first {
            Ok(r) => r,
            Err(e) => {
                let text = e.to_string();
                let mut out = vec![Err(e)];
                out.extend(
                    (1..objects.len()).map(|_| Err(self.unexpected("cyclic telegram".into(), text.clone()))),
                );
                return out;
            }
        };
        let mut ridden = ridden;
        objects
            .iter()
            .enumerate()
            .map(|(i, (address, data_type))| {
                if let Some(value) = carried[i] {
                    return Ok(self.value_of(&reply, value));
                }
                if Some(i) == rider {
                    if let Some(value) = ridden.take() {
                        return value;
                    }
                }
                self.read(address, *data_type)
            })
            .collect()
    }
}

#[cfg(test)]
#[path = "cyclic_access_tests.rs"]
mod tests;
