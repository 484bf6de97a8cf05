//! Object access for the Control Techniques family: parameters read and written as exact
//! decimal text over a [`CtLink`]. Objects live at menu.parameter, which the dictionary
//! maps onto index = menu, subindex = parameter.

use super::codec::{DataValue, NodeAddress, Parameter, Reply, Request};
use super::ct_link::{nak_text, CtLink};
use crate::dictionary::{Address, DataType, RawValue};
use crate::drive::{AccessError, ObjectAccess, WriteOutcome, WriteResult};
use crate::link::CoreLink;

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

    /// One menu, read from #M.00 on with `ACK` (read next). A reply names its parameter, so
    /// an `ACK` whose answer was lost and that the link sent again (the drive then moved on
    /// twice) shows as a gap, which is read again with the full address.
    fn scan_menu(&mut self, menu: u8, found: &mut Vec<(Address, RawValue)>) -> Result<(), AccessError> {
        let Some(first) = Parameter::new(menu, 0) else {
            return Ok(());
        };
        let mut reply = self.link.transact(&Request::Read {
            address: self.node,
            parameter: first,
        })?;
        let mut expected = first;
        loop {
            match reply {
                Some(Reply::Value { parameter, value }) if parameter == expected => {
                    found.push((
                        Address::indexed(u16::from(parameter.menu), u32::from(parameter.param)),
                        RawValue::Decimal {
                            digits: value.digits,
                            places: value.places,
                        },
                    ));
                }
                // Skipped: read the one expected with its full address before going on.
                Some(Reply::Value { .. }) => {
                    reply = self.link.transact(&Request::Read {
                        address: self.node,
                        parameter: expected,
                    })?;
                    continue;
                }
                // No such parameter (EOT); the drive still moves on with the next ACK.
                _ => {}
            }
            if expected.param == 99 {
                return Ok(());
            }
            expected = expected.next();
            reply = self.link.transact(&Request::ReadNext)?;
        }
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
    fn changes_line(&self, address: &Address) -> bool {
        self.link.config().baud_parameter.is_some()
            && self.parameter(address).ok() == self.link.config().baud_parameter
    }

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

    fn write(&mut self, address: &Address, value: &RawValue, _data_type: DataType) -> WriteResult {
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

    fn list_objects(
        &mut self,
        keep_going: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&str),
    ) -> Option<Result<Vec<(Address, RawValue)>, AccessError>> {
        if self.node.is_broadcast() {
            return Some(Err(AccessError::Encode(
                "a scan reads, so it needs one drive's address (G.U with U 1..9)".into(),
            )));
        }
        // The sources give no list of menus, so every menu number a message can carry is
        // asked (0..99, each #M.00..#M.99); a menu the drive lacks answers EOT throughout.
        let mut found = Vec::new();
        for menu in 0..=99u8 {
            if !keep_going() {
                break;
            }
            progress(&format!("menu {menu}: {} parameter(s) so far", found.len()));
            if let Err(e) = self.scan_menu(menu, &mut found) {
                return Some(Err(e));
            }
        }
        Some(Ok(found))
    }

    fn group(&self) -> Option<String> {
        self.node.is_broadcast().then(|| self.node.describe())
    }

    fn port(&self) -> String {
        format!("{} on {}", self.node.describe(), self.link.port())
    }

    crate::link_access_core!();
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
