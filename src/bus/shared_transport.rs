//! A byte transport that several drives on one line share (RS485 multi-drop): each link
//! locks it for one whole exchange (request, reply, retries), so the exchanges of two
//! drives never interleave on the wire. Knows nothing about telegrams.

use super::{Transport, TransportError};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

#[derive(Clone)]
pub struct SharedTransport {
    inner: Arc<Mutex<Box<dyn Transport>>>,
    name: Arc<str>,
}

impl SharedTransport {
    pub fn new(transport: Box<dyn Transport>) -> Self {
        let name: Arc<str> = transport.name().into();
        SharedTransport {
            inner: Arc::new(Mutex::new(transport)),
            name,
        }
    }

    /// The transport for one exchange. A panic in another user's exchange leaves the port
    /// usable: the next exchange discards stale input anyway, and the safe stop needs it.
    pub fn lock(&self) -> MutexGuard<'_, Box<dyn Transport>> {
        self.inner.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// What the transport talks to, for messages (as when it was opened).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Reopens the port after it was lost (see [`Transport::reopen`]).
    pub fn reopen(&self) -> Result<(), TransportError> {
        self.lock().reopen()
    }

    /// How many users share it (the links of the drives on this line).
    pub fn users(&self) -> usize {
        Arc::strong_count(&self.inner)
    }
}

impl std::fmt::Debug for SharedTransport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SharedTransport({})", self.name)
    }
}
