//! A hook that sees every telegram a link sends and receives (traces, `-v`), and the
//! link's own events (timeouts, retries). Observers must not block or fail the link.

use crate::family::sd2::codec::{DecodeError, Telegram};
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
    fn telegram(
        &mut self,
        at: Duration,
        direction: Direction,
        bytes: &[u8],
        decoded: &Result<Telegram, DecodeError>,
    );
    /// Something happened on the link that is not a telegram: a timeout, a retry, skipped noise.
    fn event(&mut self, at: Duration, text: &str);
}
