//! Object access for the SD2 family: Read/Write Wide Object over an [`Sd2Link`].

use super::Sd2Link;
use crate::clock::SharedClock;
use crate::dictionary::Address;
use crate::drive::{DriveError, ObjectAccess};

pub struct Sd2Access {
    link: Sd2Link,
    dest: u8,
}

impl Sd2Access {
    pub fn new(link: Sd2Link, dest: u8) -> Self {
        Sd2Access { link, dest }
    }

    pub fn link(&self) -> &Sd2Link {
        &self.link
    }

    pub fn link_mut(&mut self) -> &mut Sd2Link {
        &mut self.link
    }
}

impl ObjectAccess for Sd2Access {
    fn read(&mut self, address: &Address) -> Result<Vec<u8>, DriveError> {
        let Address::Indexed { index, subindex } = *address;
        Ok(self
            .link
            .read_object(self.dest, index, subindex)?
            .as_slice()
            .to_vec())
    }

    fn write(&mut self, address: &Address, bytes: &[u8]) -> Result<(), DriveError> {
        let Address::Indexed { index, subindex } = *address;
        Ok(self.link.write_object(self.dest, index, subindex, bytes)?)
    }

    fn port(&self) -> String {
        format!("drive {} on {}", self.dest, self.link.port())
    }

    fn clock(&self) -> SharedClock {
        self.link.clock().clone()
    }

    fn reopen(&mut self) -> Result<(), DriveError> {
        Ok(self.link.reopen()?)
    }
}
