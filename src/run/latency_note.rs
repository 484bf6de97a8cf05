//! The word a run says once, before its first step, when a USB-serial adapter's latency
//! timer alone makes the recipe's sample interval unreachable: every reply waits in the
//! adapter up to the timer, so no exchange (and no sample) comes quicker. Reads the
//! timer only; never changes it.

use crate::bus::{latency_timer_ms, latency_timer_path, sysfs_root};
use std::time::Duration;

/// The warning for `port` (a serial port, as `--port` names it) and the plan's shortest
/// sample interval; `None` when the timer is not exposed or leaves the interval reachable.
pub fn latency_note(port: &str, shortest_sample: Option<Duration>) -> Option<String> {
    let root = sysfs_root();
    let ms = latency_timer_ms(&root, port)?;
    let every = shortest_sample?;
    let timer = Duration::from_millis(u64::from(ms));
    if timer < every {
        return None;
    }
    let path = latency_timer_path(&root, port)?;
    Some(format!(
        "warning: {port} is a USB-serial adapter with a latency timer of {ms} ms: every reply waits up to that long in the adapter, so samples every {} ms cannot be kept; lower it with `echo 1 | sudo tee {}` (needs root; lost when the adapter is replugged)",
        every.as_millis(),
        path.display()
    ))
}
