//! A hook that sees every telegram a link sends and receives (traces, `-v`), and the
//! link's own events (timeouts, retries). It gets bytes only: what they mean is the
//! family's [`super::TelegramExplainer`]'s to say. Observers must not block or fail the link.

use crate::bus::CanFrame;
use std::time::Duration;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    Sent,
    Received,
}

impl Direction {
    /// `TX` / `RX`, as in serial monitors.
    pub fn tag(self) -> &'static str {
        match self {
            Direction::Sent => "TX",
            Direction::Received => "RX",
        }
    }
}

pub trait TelegramObserver: Send {
    /// A telegram crossed the wire at clock time `at`.
    fn telegram(&mut self, at: Duration, direction: Direction, bytes: &[u8]);
    /// Something happened on the link that is not a telegram: a timeout, a retry, skipped noise.
    fn event(&mut self, at: Duration, text: &str);
    /// A CAN frame crossed the bus at clock time `at`. Observers that write frames in a CAN
    /// tool's format override it; the default hands [`CanFrame::to_bytes`] to `telegram`.
    fn frame(&mut self, at: Duration, direction: Direction, frame: &CanFrame) {
        self.telegram(at, direction, &frame.to_bytes());
    }
}
