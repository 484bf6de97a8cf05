//! Object access for the SD2 family: Read/Write Wide Object over an [`Sd2Link`], with the
//! data field encoded and decoded by [`super::wire_value`].

use super::wire_value;
use super::Sd2Link;
use crate::dictionary::{Address, DataType, RawValue};
use crate::drive::{AccessError, ObjectAccess, WriteOutcome, WriteResult};
use crate::link::CoreLink;

pub struct Sd2Access {
    link: Sd2Link,
    dest: u8,
}

impl Sd2Access {
    pub fn new(link: Sd2Link, dest: u8) -> Self {
        Sd2Access { link, dest }
    }

    /// The drive's DNC address.
    pub fn dest(&self) -> u8 {
        self.dest
    }

    pub fn link(&self) -> &Sd2Link {
        &self.link
    }

    pub fn link_mut(&mut self) -> &mut Sd2Link {
        &mut self.link
    }

    fn bad_data(&self, address: &Address, detail: String) -> AccessError {
        AccessError::UnexpectedReply {
            port: self.link.port().to_string(),
            address: self.dest.to_string(),
            request: format!("read object {address}"),
            detail,
        }
    }
}

impl ObjectAccess for Sd2Access {
    fn read(&mut self, address: &Address, data_type: DataType) -> Result<RawValue, AccessError> {
        let Address::Indexed { index, subindex } = *address;
        let data = self.link.read_object(self.dest, index, subindex)?;
        wire_value::decode(data.as_slice(), data_type).map_err(|e| self.bad_data(address, e.to_string()))
    }

    fn write(&mut self, address: &Address, value: &RawValue, data_type: DataType) -> WriteResult {
        let Address::Indexed { index, subindex } = *address;
        let bytes = wire_value::encode(value, data_type).map_err(|e| AccessError::Encode(e.to_string()))?;
        self.link.write_object(self.dest, index, subindex, &bytes)?;
        Ok(WriteOutcome::Stored)
    }

    fn port(&self) -> String {
        format!("drive {} on {}", self.dest, self.link.port())
    }

    crate::link_access_core!();
}
