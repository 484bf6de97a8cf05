//! A CAN bus as drives on it see it: send a frame, wait for frames. Backends (SLCAN over a
//! serial adapter, SocketCAN, the in-process simulator) implement [`FrameBus`];
//! [`super::SharedFrameBus`] lets several nodes' links share one bus, each locking it for
//! one exchange. Knows nothing about what the frames mean.

use super::{CanFrame, TransportError};
use std::time::Duration;

pub trait FrameBus: Send {
    /// What the bus is, for messages: `slcan /dev/ttyACM0 at 500 kbit/s`, `can0`.
    fn name(&self) -> &str;
    fn send(&mut self, frame: &CanFrame) -> Result<(), TransportError>;
    /// The next frame within `timeout`; nothing is [`TransportError::Timeout`].
    fn receive(&mut self, timeout: Duration) -> Result<CanFrame, TransportError>;
    /// Opens the bus again after the adapter was lost.
    fn reopen(&mut self) -> Result<(), TransportError>;
}
