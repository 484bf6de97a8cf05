//! A bus that several drives share (RS485 multi-drop, or nodes on one CAN bus): each link
//! locks it for one whole exchange (request, reply, retries), so the exchanges of two
//! drives never interleave on the wire. One type for byte transports and frame buses.
//! Knows nothing about telegrams or frames.

use super::{FrameBus, Transport, TransportError};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

/// A bus (`B` is `dyn Transport` or `dyn FrameBus`) shared by the links of several drives.
pub struct Shared<B: ?Sized> {
    /// One shared allocation, so that a link's handle for one exchange costs one count.
    inner: Arc<Line<B>>,
}

/// The bus and its name, behind one count.
struct Line<B: ?Sized> {
    name: Box<str>,
    bus: Mutex<Box<B>>,
}

/// A byte transport shared by the drives on one line.
pub type SharedTransport = Shared<dyn Transport>;
/// A frame bus shared by the links of several nodes.
pub type SharedFrameBus = Shared<dyn FrameBus>;

/// What a shared bus tells about itself: its name for messages, and its kind for `Debug`.
pub trait Named {
    const KIND: &'static str;
    fn bus_name(&self) -> &str;
}

impl Named for dyn Transport {
    const KIND: &'static str = "SharedTransport";
    fn bus_name(&self) -> &str {
        self.name()
    }
}

impl Named for dyn FrameBus {
    const KIND: &'static str = "SharedFrameBus";
    fn bus_name(&self) -> &str {
        self.name()
    }
}

impl<B: ?Sized + Named> Shared<B> {
    pub fn new(bus: Box<B>) -> Self {
        let name = bus.bus_name().into();
        Shared {
            inner: Arc::new(Line {
                name,
                bus: Mutex::new(bus),
            }),
        }
    }

    /// The bus for one exchange. A panic in another user's exchange leaves the bus usable:
    /// the next exchange discards stale input anyway, and the safe stop needs it.
    pub fn lock(&self) -> MutexGuard<'_, Box<B>> {
        self.inner.bus.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// What the bus talks to, for messages (as when it was opened).
    pub fn name(&self) -> &str {
        &self.inner.name
    }

    /// How many users share it (the links of the drives on this bus).
    pub fn users(&self) -> usize {
        Arc::strong_count(&self.inner)
    }
}

impl SharedTransport {
    /// Reopens the port after it was lost (see [`Transport::reopen`]).
    pub fn reopen(&self) -> Result<(), TransportError> {
        self.lock().reopen()
    }
}

impl<B: ?Sized> Clone for Shared<B> {
    fn clone(&self) -> Self {
        Shared {
            inner: self.inner.clone(),
        }
    }
}

impl<B: ?Sized + Named> std::fmt::Debug for Shared<B> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}({})", B::KIND, self.inner.name)
    }
}
