//! The small trait each protocol family implements so the drive layer can read and write
//! objects without knowing bytes on the wire. Implementations own their link.

use super::DriveError;
use crate::clock::SharedClock;
use crate::dictionary::Address;

/// Raw object access: little-endian bytes in, little-endian bytes out.
pub trait ObjectAccess: Send {
    fn read(&mut self, address: &Address) -> Result<Vec<u8>, DriveError>;
    fn write(&mut self, address: &Address, bytes: &[u8]) -> Result<(), DriveError>;
    /// What we are talking to, for messages.
    fn port(&self) -> String;
    /// The clock the link waits on (real, or virtual with the simulator).
    fn clock(&self) -> SharedClock;
    /// Opens the port again after the line was lost (see `Transport::reopen`).
    fn reopen(&mut self) -> Result<(), DriveError>;
}
