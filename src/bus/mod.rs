//! Buses between the PC and its drives: byte transports (serial port, TCP serial server,
//! the in-process simulator) and CAN frame buses, each shareable by several drives on one
//! line. Knows nothing about telegrams; framing and checking belong to the family's link.
//! The traits are object-safe so the command line chooses a backend at run time.

mod bus;
mod can_frame;
mod can_frame_text_error;
mod frame_bus;
mod memory;
mod memory_frame_bus;
mod peer_line;
mod read_within;
#[cfg(test)]
mod scripted_peer;
mod serial;
mod shared;
mod slcan_adapter;
mod slcan_bus;
pub mod slcan_codec;
#[cfg(target_os = "linux")]
mod socketcan_bus;
mod tcp;
#[cfg(test)]
mod transport_checks;
mod transport_error;
mod usb_latency;

pub use bus::{Bus, BusKind};
pub use can_frame::CanFrame;
pub use can_frame_text_error::CanFrameTextError;
pub use frame_bus::FrameBus;
pub use memory_frame_bus::{FramePeer, MemoryFrameBus};
pub use peer_line::{EchoingLine, FramePeerLine, PeerLine};
#[cfg(test)]
pub use scripted_peer::ScriptedPeer;
pub use shared::{Named, Shared, SharedFrameBus, SharedTransport};
pub use slcan_adapter::SlcanAdapter;
pub use slcan_bus::SlcanBus;
#[cfg(target_os = "linux")]
pub use socketcan_bus::SocketCanBus;
#[cfg(test)]
pub use transport_checks::candump_replies;

/// A SocketCAN interface as a frame bus (Linux only; elsewhere a clear refusal).
pub fn open_socketcan(interface: &str) -> Result<Box<dyn FrameBus>, TransportError> {
    #[cfg(target_os = "linux")]
    {
        Ok(Box::new(SocketCanBus::open(interface)?))
    }
    #[cfg(not(target_os = "linux"))]
    {
        Err(TransportError::Open {
            port: interface.to_string(),
            detail: "SocketCAN exists only on Linux; use an SLCAN adapter with --can slcan:PORT".into(),
        })
    }
}

pub use memory::{MemoryTransport, Peer, PeerReplies, PeerReply, WireTime};
pub use serial::{
    list_ports, DataBits, Parity, PortInfo, SerialSettings, SerialTransport, StopBits, UsbInfo,
};
pub use tcp::TcpTransport;
pub use transport_error::TransportError;
pub use usb_latency::{latency_timer_ms, latency_timer_path, sysfs_root};

use std::time::Duration;

/// A byte pipe to one drive (or one bus).
pub trait Transport: Send {
    /// What this transport talks to, for messages: `/dev/ttyUSB0 at 57600 8N1`,
    /// `tcp 192.0.2.7:4001`, `built-in simulated drive`.
    fn name(&self) -> &str;

    /// Sends all of `bytes`.
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), TransportError>;

    /// How long the last write may still be on its way after `write_all` returned: a
    /// serial port hands the bytes to its driver and returns before the line has carried
    /// them, and no reply can start before they are out. Reply timeouts start after it.
    fn still_sending(&self) -> Duration {
        Duration::ZERO
    }

    /// Waits at most `timeout` for input and returns how many bytes were put into `buf`
    /// (at least one). Nothing within `timeout` is [`TransportError::Timeout`], never `Ok(0)`.
    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError>;

    /// Throws away input that has arrived but not been read (stale replies, line noise);
    /// returns how many bytes were dropped.
    fn discard_input(&mut self) -> Result<usize, TransportError>;

    /// Throws away what was written but not yet taken by the other side; `false` when
    /// this transport cannot. On a pseudo-terminal's near end that is what no program read
    /// from its far end: a simulator serving a line nobody reads drops its own frames
    /// there, as a real adapter's are lost, instead of waiting for ever.
    fn discard_output(&mut self) -> Result<bool, TransportError> {
        Ok(false)
    }

    /// The exchange just ended with its reply and nothing after it, so the next
    /// [`discard_input`](Self::discard_input) need not ask the device whether input is
    /// waiting (a system call per telegram). Transports with nothing to save ignore it.
    fn exchange_complete(&mut self) {}

    /// The line settings of a serial port, for a protocol that times its frames in
    /// characters (Modbus RTU's silence of 3.5 characters); `None` for other transports.
    fn serial_settings(&self) -> Option<SerialSettings> {
        None
    }

    /// Closes and opens the same port again (same path and settings, same address), after
    /// the line was lost: a USB adapter re-enumerated, a serial server restarted. The safe
    /// stop uses it to reach a drive that may still be running.
    fn reopen(&mut self) -> Result<(), TransportError>;
}
