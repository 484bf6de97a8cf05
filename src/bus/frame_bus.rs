//! A CAN bus as drives on it see it: send a frame, wait for frames. Backends (SLCAN over a
//! serial adapter, SocketCAN, the in-process simulator) implement [`FrameBus`];
//! [`SharedFrameBus`] lets several nodes' links share one bus, each locking it for one
//! exchange. Knows nothing about what the frames mean.

use super::{CanFrame, TransportError};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
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

/// A frame bus shared by the links of several nodes.
#[derive(Clone)]
pub struct SharedFrameBus {
    inner: Arc<Mutex<Box<dyn FrameBus>>>,
    name: Arc<str>,
}

impl SharedFrameBus {
    pub fn new(bus: Box<dyn FrameBus>) -> Self {
        let name: Arc<str> = bus.name().into();
        SharedFrameBus {
            inner: Arc::new(Mutex::new(bus)),
            name,
        }
    }

    /// The bus for one exchange (see `SharedTransport::lock` for why poison is ignored).
    pub fn lock(&self) -> MutexGuard<'_, Box<dyn FrameBus>> {
        self.inner.lock().unwrap_or_else(PoisonError::into_inner)
    }

    pub fn name(&self) -> &str {
        &self.name
    }
}

impl std::fmt::Debug for SharedFrameBus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SharedFrameBus({})", self.name)
    }
}
