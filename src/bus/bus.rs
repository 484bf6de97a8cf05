//! A bus as a family's link uses it: a byte stream (serial line, TCP serial server, the
//! in-process simulator) or a CAN frame bus, either shared by every drive on it.

use super::{SharedFrameBus, SharedTransport};

#[derive(Clone, Debug)]
pub enum Bus {
    Bytes(SharedTransport),
    Frames(SharedFrameBus),
}

/// Which kind of bus a family needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BusKind {
    Bytes,
    Frames,
}

impl Bus {
    pub fn kind(&self) -> BusKind {
        match self {
            Bus::Bytes(_) => BusKind::Bytes,
            Bus::Frames(_) => BusKind::Frames,
        }
    }

    /// What the bus is, for messages.
    pub fn name(&self) -> &str {
        match self {
            Bus::Bytes(t) => t.name(),
            Bus::Frames(f) => f.name(),
        }
    }
}
