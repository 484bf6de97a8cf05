//! The word a run says once, before its first step, when a USB-serial adapter's latency
//! timer alone slows the line: every reply waits in the adapter up to the timer, so no
//! exchange comes quicker than the timer allows, whatever the wire could carry, and no
//! sample interval shorter than the timer can be kept. Reads the timer only; never
//! changes it.

use super::line_exchange::LineExchange;
use crate::bus::{latency_timer_ms, latency_timer_path, sysfs_root};
use std::time::Duration;

/// The warning for `port` (a serial port, as `--port` names it), the plan's shortest
/// sample interval and one read exchange on the line (measured only when the port has a
/// timer); `None` when the timer is not exposed or slows neither.
pub fn latency_note(
    port: &str,
    shortest_sample: Option<Duration>,
    exchange: impl FnOnce() -> Option<LineExchange>,
) -> Option<String> {
    let root = sysfs_root();
    let ms = latency_timer_ms(&root, port)?;
    let timer = Duration::from_millis(u64::from(ms));
    if timer.is_zero() {
        return None;
    }
    let samples = shortest_sample
        .filter(|every| timer >= *every)
        .map(|every| format!("samples every {} ms cannot be kept", every.as_millis()));
    // The timer at least halves the line's exchanges when it is as long as an exchange's
    // bytes take on the wire.
    let line = exchange().filter(|e| timer >= e.wire_time()).map(|e| {
        let wire = e.wire_time().as_secs_f64();
        format!(
            "reads of {} ({} bytes, {:.1} ms on the wire at {}) drop from about {:.0}/s to as few as {:.0}/s",
            e.object,
            e.bytes,
            wire * 1e3,
            e.settings,
            1.0 / wire,
            1.0 / (wire + timer.as_secs_f64())
        )
    });
    let consequences: Vec<String> = line.into_iter().chain(samples).collect();
    if consequences.is_empty() {
        return None;
    }
    let path = latency_timer_path(&root, port)?;
    Some(format!(
        "warning: {port} is a USB-serial adapter with a latency timer of {ms} ms: every reply waits up to that long in the adapter, so {}; lower it with `echo 1 | sudo tee {}` (needs root; lost when the adapter is replugged)",
        consequences.join(", and "),
        path.display()
    ))
}
