//! Object access for the Modbus families: a holding register is read with 03 and written
//! with 06 (one register) or 16 (two), an input register is read with 04 and cannot be
//! written. An exception reply is the drive's refusal, named with the specification's
//! text; a write to slave 0 (broadcast) is sent without confirmation.

use super::codec::{Function, Request, Response};
use super::register_address::{Register, Table};
use super::register_value;
use super::ModbusLink;
use crate::dictionary::{Address, DataType, RawValue};
use crate::drive::{AccessError, ObjectAccess, WriteOutcome, WriteResult};
use crate::link::CoreLink;

pub struct ModbusAccess {
    link: ModbusLink,
}

impl ModbusAccess {
    pub fn new(link: ModbusLink) -> Self {
        ModbusAccess { link }
    }

    pub fn link(&self) -> &ModbusLink {
        &self.link
    }

    fn register(address: &Address) -> Result<Register, AccessError> {
        Register::of(address).ok_or_else(|| AccessError::Encode(format!("{address} is no Modbus register")))
    }

    fn count(data_type: DataType) -> Result<u16, AccessError> {
        register_value::count(data_type)
            .ok_or_else(|| AccessError::Encode(format!("a Modbus object cannot have the type {data_type}")))
    }

    fn refused(&self, operation: &'static str, register: Register, function: u8, code: u8) -> AccessError {
        let code = super::codec::ExceptionCode(code);
        let after = match code {
            // Busy at every attempt: the link asked again after a pause each time.
            super::codec::ExceptionCode::SERVER_DEVICE_BUSY
            | super::codec::ExceptionCode::ACKNOWLEDGE => {
                "; it was still so at the last attempt: let it finish its long command, then try again (more time between attempts: --timeout, --retries)"
            }
            _ => "",
        };
        AccessError::Refused {
            port: self.link.port(),
            address: self.link.shown_unit(),
            operation,
            object: register.notation(),
            code: code.0.into(),
            text: format!("function {function:02X} answered with {code}{after}"),
        }
    }

    fn unexpected(&self, register: Register, detail: String) -> AccessError {
        AccessError::UnexpectedReply {
            port: self.link.port(),
            address: self.link.shown_unit(),
            request: register.notation(),
            detail,
        }
    }
}

impl ObjectAccess for ModbusAccess {
    fn read(&mut self, address: &Address, data_type: DataType) -> Result<RawValue, AccessError> {
        let register = Self::register(address)?;
        let function = match register.table {
            Table::Holding => Function::ReadHolding,
            Table::Input => Function::ReadInput,
        };
        let request = Request::Read {
            function,
            start: register.address,
            count: Self::count(data_type)?,
        };
        match self.link.exchange(&request)? {
            Some(Response::Registers { values, .. }) => {
                register_value::decode(&values, data_type, register.low_word_first)
                    .map_err(|e| self.unexpected(register, e.to_string()))
            }
            Some(Response::Exception { function, code }) => {
                Err(self.refused("read", register, function, code.0))
            }
            other => Err(self.unexpected(register, format!("{other:?}"))),
        }
    }

    fn write(&mut self, address: &Address, value: &RawValue, data_type: DataType) -> WriteResult {
        let register = Self::register(address)?;
        if register.table == Table::Input {
            return Err(AccessError::Encode(format!(
                "{} is an input register, which Modbus cannot write",
                register.notation()
            )));
        }
        let words = register_value::encode(value, data_type, register.low_word_first)
            .map_err(|e| AccessError::Encode(e.to_string()))?;
        let request = match words.as_slice() {
            [value] => Request::WriteSingle {
                address: register.address,
                value: *value,
            },
            _ => Request::WriteMultiple {
                start: register.address,
                values: words,
            },
        };
        match self.link.exchange(&request)? {
            None | Some(Response::WriteSingle { .. } | Response::WriteMultiple { .. }) => {
                Ok(WriteOutcome::Stored)
            }
            // Accepted, to be carried out (Application Protocol V1.1b3, 7: code 05).
            Some(Response::Exception {
                code: super::codec::ExceptionCode::ACKNOWLEDGE,
                ..
            }) => Ok(WriteOutcome::Stored),
            Some(Response::Exception { function, code }) => {
                Err(self.refused("write", register, function, code.0))
            }
            Some(other) => Err(self.unexpected(register, format!("{other:?}"))),
        }
    }

    fn group(&self) -> Option<String> {
        (self.link.unit() == super::codec::rtu::BROADCAST)
            .then(|| "every slave on the line (broadcast)".into())
    }

    fn port(&self) -> String {
        format!("{} on {}", self.link.shown_unit(), self.link.port())
    }

    crate::link_access_core!();
}
