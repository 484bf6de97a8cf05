//! The wait for input that the serial and TCP transports share: try to read until bytes
//! come or the caller's time is up, as one loop, so that both treat a signal, a spurious
//! wake-up and a short timeout alike. Knows nothing of either device.

use super::transport_error::TransportError;
use std::time::{Duration, Instant};

/// Calls `attempt(buf, time left)` until it reads bytes (`Some(n)`), fails, or `timeout`
/// has passed (`None`: the caller names its port in the timeout). An empty `buf` reads 0
/// at once.
pub(super) fn read_within(
    buf: &mut [u8],
    timeout: Duration,
    mut attempt: impl FnMut(&mut [u8], Duration) -> Result<Option<usize>, TransportError>,
) -> Result<Option<usize>, TransportError> {
    if buf.is_empty() {
        return Ok(Some(0));
    }
    let deadline = Instant::now() + timeout;
    loop {
        if let Some(n) = attempt(buf, deadline.saturating_duration_since(Instant::now()))? {
            return Ok(Some(n));
        }
        if Instant::now() >= deadline {
            return Ok(None);
        }
    }
}
