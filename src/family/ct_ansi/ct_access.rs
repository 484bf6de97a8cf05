//! Object access for the Control Techniques family: parameters read and written as exact
//! decimal text over a [`CtLink`]. Objects live at menu.parameter, which the dictionary
//! maps onto index = menu, subindex = parameter.

use super::codec::{DataValue, NodeAddress, Parameter, Reply, Request};
use super::ct_link::{nak_text, CtLink};
use crate::clock::SharedClock;
use crate::dictionary::{Address, DataType, RawValue};
use crate::drive::{AccessError, ObjectAccess, WriteOutcome};

pub struct CtAccess {
    link: CtLink,
    node: NodeAddress,
}

impl CtAccess {
    pub fn new(link: CtLink, node: NodeAddress) -> Self {
        CtAccess { link, node }
    }

    pub fn link(&self) -> &CtLink {
        &self.link
    }

    fn parameter(&self, address: &Address) -> Result<Parameter, AccessError> {
        let Address::Indexed { index, subindex } = *address;
        u8::try_from(index)
            .ok()
            .zip(u8::try_from(subindex).ok())
            .and_then(|(m, p)| Parameter::new(m, p))
            .ok_or_else(|| {
                AccessError::Encode(format!(
                    "menu {index}, parameter {subindex} is no Control Techniques parameter (menu and parameter are 0..99)"
                ))
            })
    }

    fn refused(&self, operation: &'static str, parameter: Parameter, text: String) -> AccessError {
        AccessError::Refused {
            port: self.link.port().to_string(),
            address: self.node.to_string(),
            operation,
            object: parameter.to_string(),
            code: 0,
            text,
        }
    }

    fn unexpected(&self, request: String, detail: String) -> AccessError {
        AccessError::UnexpectedReply {
            port: self.link.port().to_string(),
            address: self.node.to_string(),
            request,
            detail,
        }
    }
}

impl ObjectAccess for CtAccess {
    fn read(&mut self, address: &Address, _data_type: DataType) -> Result<RawValue, AccessError> {
        let parameter = self.parameter(address)?;
        if self.node.is_broadcast() {
            return Err(AccessError::Encode(format!(
                "{} takes writes only: every drive addressed would answer a read at once; give one drive's address (G.U with U 1..9) to read",
                self.node.describe()
            )));
        }
        let reply = self.link.transact(&Request::Read {
            address: self.node,
            parameter,
        })?;
        match reply {
            Some(Reply::Value { value, .. }) => Ok(RawValue::Decimal {
                digits: value.digits,
                places: value.places,
            }),
            Some(Reply::NoSuchParameter) => Err(self.refused(
                "read",
                parameter,
                format!("the drive has no parameter {parameter} (it answered EOT)"),
            )),
            other => Err(self.unexpected(format!("read {parameter}"), shown(other))),
        }
    }

    fn write(
        &mut self,
        address: &Address,
        value: &RawValue,
        _data_type: DataType,
    ) -> Result<WriteOutcome, AccessError> {
        let parameter = self.parameter(address)?;
        let value = match *value {
            RawValue::Int(i) => DataValue::new(i, 0),
            RawValue::Decimal { digits, places } => DataValue::new(digits, places),
            ref other => {
                return Err(AccessError::Encode(format!(
                    "{parameter} takes a decimal number, not {other}"
                )))
            }
        };
        let reply = self.link.transact(&Request::Write {
            address: Some(self.node),
            parameter,
            value,
        })?;
        match reply {
            // A group or global write: nobody answers, so nothing more can be known.
            None | Some(Reply::Accepted) => Ok(WriteOutcome::Stored),
            Some(Reply::Refused) => Err(self.refused("write", parameter, nak_text().to_string())),
            Some(other) => Err(self.unexpected(format!("write {parameter} = {value}"), shown(Some(other)))),
        }
    }

    fn port(&self) -> String {
        format!("{} on {}", self.node.describe(), self.link.port())
    }

    fn clock(&self) -> SharedClock {
        self.link.clock().clone()
    }

    fn reopen(&mut self) -> Result<(), AccessError> {
        self.link.reopen()
    }
}

/// A reply of the wrong kind, for the message.
fn shown(reply: Option<Reply>) -> String {
    match reply {
        None => "no reply".into(),
        Some(Reply::Value { parameter, value }) => format!("the value {value} of {parameter}"),
        Some(Reply::Accepted) => "ACK".into(),
        Some(Reply::Refused) => "NAK".into(),
        Some(Reply::NoSuchParameter) => "EOT".into(),
    }
}
