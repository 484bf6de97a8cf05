//! Moves bytes between the PC and a drive: serial port, TCP serial server, or the
//! in-process simulator. Knows nothing about telegrams; framing and checking belong to the
//! link above. The trait is object-safe so the command line chooses a backend at run time.

mod memory;
mod serial;
mod tcp;
mod transport_error;

pub use memory::{MemoryTransport, Peer, PeerReply, WireTime};
pub use serial::{
    list_ports, DataBits, Parity, PortInfo, SerialSettings, SerialTransport, StopBits, UsbInfo,
};
pub use tcp::TcpTransport;
pub use transport_error::TransportError;

use std::time::Duration;

/// A byte pipe to one drive (or one bus).
pub trait Transport: Send {
    /// What this transport talks to, for messages: `/dev/ttyUSB0 at 57600 8N1`,
    /// `tcp 192.0.2.7:4001`, `built-in simulated drive`.
    fn name(&self) -> &str;

    /// Sends all of `bytes`.
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), TransportError>;

    /// Waits at most `timeout` for input and returns how many bytes were put into `buf`
    /// (at least one). Nothing within `timeout` is [`TransportError::Timeout`], never `Ok(0)`.
    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError>;

    /// Throws away input that has arrived but not been read (stale replies, line noise);
    /// returns how many bytes were dropped.
    fn discard_input(&mut self) -> Result<usize, TransportError>;

    /// Closes and opens the same port again (same path and settings, same address), after
    /// the line was lost: a USB adapter re-enumerated, a serial server restarted. The safe
    /// stop uses it to reach a drive that may still be running.
    fn reopen(&mut self) -> Result<(), TransportError>;
}
