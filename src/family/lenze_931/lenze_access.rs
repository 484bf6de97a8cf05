//! Object access for the Lenze 931 family: communication objects with `OR`/`OW` (and the
//! drive's own limits with `ON`/`OX`), identification commands as read-only text, CANopen
//! objects through the SDO simulation. A write the drive limited (codes 4 and 5) is read
//! back and returned as `Limited(stored value)`; a refusal for a value too low or too high
//! (codes 2 and 3) names the drive's limit where it can be read.

use super::codec::{ErrorCode, ObjectCommand, Reply, Request};
use super::object_address::{Ident, LenzeObject};
use super::wire_value;
use super::LenzeLink;
use crate::dictionary::{Address, DataType, RawValue};
use crate::drive::{AccessError, DriveLimits, MaintenanceOutcome, ObjectAccess, WriteOutcome, WriteResult};
use crate::link::CoreLink;

pub struct LenzeAccess {
    link: LenzeLink,
}

impl LenzeAccess {
    pub fn new(link: LenzeLink) -> Self {
        LenzeAccess { link }
    }

    pub fn link(&self) -> &LenzeLink {
        &self.link
    }

    fn object(&self, address: &Address) -> Result<LenzeObject, AccessError> {
        LenzeObject::of(address).ok_or_else(|| {
            AccessError::Encode(format!(
                "{address} is no 931 object (a communication object has subindex 0)"
            ))
        })
    }

    fn unexpected(&self, request: &Request, detail: String) -> AccessError {
        AccessError::UnexpectedReply {
            port: self.link.port().to_string(),
            address: "RS232".into(),
            request: format!("`{}` ({})", request.text(), request.describe()),
            detail,
        }
    }

    fn refused(
        &self,
        operation: &'static str,
        object: LenzeObject,
        code: ErrorCode,
        limit: Option<String>,
    ) -> AccessError {
        AccessError::Refused {
            port: self.link.port().to_string(),
            address: "RS232".into(),
            operation,
            object: object.notation(),
            code: code.0,
            text: match limit {
                Some(l) => format!("{code}; {l}"),
                None => code.to_string(),
            },
        }
    }

    fn unknown_command(&self, operation: &'static str, object: LenzeObject) -> AccessError {
        AccessError::Refused {
            port: self.link.port().to_string(),
            address: "RS232".into(),
            operation,
            object: object.notation(),
            code: 0,
            text: "the drive answered ERROR! (it does not know the command; older firmware may lack it)"
                .into(),
        }
    }

    /// One object command on a communication object: the value's 32 bits, or the code.
    fn object_command(
        &mut self,
        command: ObjectCommand,
        number: u16,
    ) -> Result<Result<u32, ErrorCode>, AccessError> {
        let request = Request::read(command, number);
        match self.link.exchange(&request)? {
            Reply::Value { value, .. } => Ok(Ok(value)),
            Reply::Error { code, .. } => Ok(Err(code)),
            Reply::UnknownCommand => Err(self.unknown_command("read", LenzeObject::Communication(number))),
            other => Err(self.unexpected(&request, format!("`{}`", other.text()))),
        }
    }

    /// `the drive's maximum is 6000 (0x00001770)`, best effort, for a refusal's text.
    fn limit_text(&mut self, number: u16, code: ErrorCode, data_type: DataType) -> Option<String> {
        let (command, side) = match code {
            ErrorCode::TOO_LOW | ErrorCode::TOO_LOW_LIMITED => (ObjectCommand::Min, "minimum"),
            ErrorCode::TOO_HIGH | ErrorCode::TOO_HIGH_LIMITED => (ObjectCommand::Max, "maximum"),
            _ => return None,
        };
        let bits = self.object_command(command, number).ok()?.ok()?;
        let shown = match wire_value::decode(bits, data_type) {
            Ok(v) => v.to_string(),
            Err(_) => (bits as i32).to_string(),
        };
        Some(format!(
            "the drive's {side} is {shown} (0x{bits:08X}, read with {}:{number:04X})",
            command.prefix()
        ))
    }

    fn read_ident(&mut self, ident: Ident, data_type: DataType) -> Result<RawValue, AccessError> {
        let request = match ident {
            Ident::Type => Request::Type,
            Ident::Version => Request::Version,
            Ident::Boot => Request::Boot,
            Ident::Bus => Request::Bus,
        };
        let text = match self.link.exchange(&request)? {
            Reply::Type(t) => t,
            Reply::Version { status, version } => format!("{version} (status {status})"),
            Reply::Boot(b) => Reply::Boot(b).text(),
            reply @ Reply::Bus { .. } => reply.text(),
            Reply::UnknownCommand => return Err(self.unknown_command("read", LenzeObject::Ident(ident))),
            other => return Err(self.unexpected(&request, format!("`{}`", other.text()))),
        };
        match data_type {
            DataType::String { .. } => Ok(RawValue::Text(text)),
            _ => Err(self.unexpected(
                &request,
                format!("`{text}` is text; give the object a string type (string(32))"),
            )),
        }
    }
}

impl ObjectAccess for LenzeAccess {
    fn read(&mut self, address: &Address, data_type: DataType) -> Result<RawValue, AccessError> {
        match self.object(address)? {
            LenzeObject::Communication(number) => match self.object_command(ObjectCommand::Read, number)? {
                Ok(bits) => wire_value::decode(bits, data_type)
                    .map_err(|e| self.unexpected(&Request::read(ObjectCommand::Read, number), e.to_string())),
                Err(code) => Err(self.refused("read", LenzeObject::Communication(number), code, None)),
            },
            LenzeObject::Ident(ident) => self.read_ident(ident, data_type),
            object @ LenzeObject::CanOpen { index, subindex } => {
                let request = Request::SdoRead { index, subindex };
                match self.link.exchange(&request)? {
                    Reply::Sdo { data, .. } => wire_value::decode_bytes(&data, data_type)
                        .map_err(|e| self.unexpected(&request, e.to_string())),
                    Reply::UnknownCommand => Err(self.unknown_command("read", object)),
                    other => Err(self.unexpected(&request, format!("`{}`", other.text()))),
                }
            }
        }
    }

    fn write(&mut self, address: &Address, value: &RawValue, data_type: DataType) -> WriteResult {
        match self.object(address)? {
            object @ LenzeObject::Communication(number) => {
                let bits =
                    wire_value::encode(value, data_type).map_err(|e| AccessError::Encode(e.to_string()))?;
                let request = Request::Write {
                    object: number,
                    value: bits,
                };
                match self.link.exchange(&request)? {
                    Reply::Ok => Ok(WriteOutcome::Stored),
                    Reply::Error { code, .. } if code.is_limited() => {
                        // The reply does not carry the value the drive stored: read it back.
                        let stored = self.read(address, data_type)?;
                        Ok(WriteOutcome::Limited(stored))
                    }
                    Reply::Error { code, .. } => {
                        let limit = self.limit_text(number, code, data_type);
                        Err(self.refused("write", object, code, limit))
                    }
                    Reply::UnknownCommand => Err(self.unknown_command("write", object)),
                    other => Err(self.unexpected(&request, format!("`{}`", other.text()))),
                }
            }
            object @ LenzeObject::CanOpen { index, subindex } => {
                let data = wire_value::encode_bytes(value, data_type)
                    .map_err(|e| AccessError::Encode(e.to_string()))?;
                let request = Request::SdoWrite {
                    index,
                    subindex,
                    data,
                };
                match self.link.exchange(&request)? {
                    Reply::Sdo { .. } => Ok(WriteOutcome::Stored),
                    Reply::UnknownCommand => Err(self.unknown_command("write", object)),
                    other => Err(self.unexpected(&request, format!("`{}`", other.text()))),
                }
            }
            object @ LenzeObject::Ident(_) => Err(AccessError::Encode(format!(
                "{} is an identification command and cannot be written",
                object.notation()
            ))),
        }
    }

    fn limits(&mut self, address: &Address, data_type: DataType) -> Option<Result<DriveLimits, AccessError>> {
        let LenzeObject::Communication(number) = LenzeObject::of(address)? else {
            return None;
        };
        let side = |access: &mut Self, command: ObjectCommand| -> Result<Option<RawValue>, AccessError> {
            match access.object_command(command, number)? {
                Ok(bits) => wire_value::decode(bits, data_type)
                    .map(Some)
                    .map_err(|e| access.unexpected(&Request::read(command, number), e.to_string())),
                Err(ErrorCode::NO_LOWER_LIMIT | ErrorCode::NO_UPPER_LIMIT) => Ok(None),
                Err(code) => Err(access.refused(
                    "read the limits of",
                    LenzeObject::Communication(number),
                    code,
                    None,
                )),
            }
        };
        Some((|| {
            let min = side(self, ObjectCommand::Min)?;
            let max = side(self, ObjectCommand::Max)?;
            Ok(DriveLimits { min, max })
        })())
    }

    fn store_parameters(&mut self) -> Option<Result<(), AccessError>> {
        let request = Request::Save;
        Some(match self.link.exchange(&request) {
            Ok(Reply::Done) => Ok(()),
            Ok(other) => Err(self.unexpected(&request, format!("`{}`", other.text()))),
            Err(e) => Err(e),
        })
    }

    fn maintain(
        &mut self,
        action: &str,
        argument: Option<u32>,
    ) -> Option<Result<MaintenanceOutcome, AccessError>> {
        let request = match super::maintenance::request(action, argument) {
            Ok(r) => r,
            Err(e) => return Some(Err(AccessError::Encode(e.to_string()))),
        };
        let reply = match self.link.exchange(&request) {
            Ok(r) => r,
            Err(e) => return Some(Err(e)),
        };
        Some(match (&request, reply) {
            (Request::Reset | Request::Init, Reply::SwitchOn(text)) => Ok(MaintenanceOutcome {
                reply: text,
                line_rate: None,
            }),
            (Request::Sep, Reply::Done) => Ok(MaintenanceOutcome {
                reply: "DONE".into(),
                line_rate: None,
            }),
            (Request::Baud(rate), Reply::Ok) => Ok(MaintenanceOutcome {
                reply: "OK!".into(),
                line_rate: Some(*rate),
            }),
            (_, Reply::UnknownCommand) => Err(AccessError::Refused {
                port: self.link.port().to_string(),
                address: "RS232".into(),
                operation: "carry out",
                object: request.text(),
                code: 0,
                text: "the drive answered ERROR! (it does not know the command; older firmware may lack it)"
                    .into(),
            }),
            (_, other) => Err(self.unexpected(&request, format!("`{}`", other.text()))),
        })
    }

    fn port(&self) -> String {
        format!("the 931 on {}", self.link.port())
    }

    crate::link_access_core!();
}
