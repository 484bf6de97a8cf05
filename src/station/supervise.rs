//! The station process's own endings: each stop signal (Ctrl-C, SIGTERM, …) is passed on
//! to the run under way as the same stop request (so a second one switches the power
//! stage off) and no new run starts; a web server that died (a bug) stops the run too,
//! since nobody could answer or press Stop any more. The process ends only after the run's
//! safe stop. Waits and forwards; the stop itself is the session's.

use super::station::Station;
use crate::stop_request::{StopRequests, StopSignal};
use std::time::Duration;

/// How the station ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    Signal(StopSignal),
    ServerFailed,
}

/// Waits until a stop signal arrives (or the server stops serving), passes it on to the
/// run under way, and returns once that run's safe stop is over.
pub fn supervise(station: &Station, signals: &StopRequests, serving: &dyn Fn() -> bool) -> Ended {
    let mut forwarded = 0;
    let mut ended = None;
    loop {
        signals.wait_real(Duration::from_millis(200));
        let arrived = signals.count_at(Duration::ZERO);
        if let Some(first) = signals.first() {
            while forwarded < arrived {
                station.shut_down(first);
                forwarded += 1;
            }
            signals.acknowledge();
            ended.get_or_insert(Ended::Signal(first));
        }
        if ended.is_none() && !serving() {
            station.shut_down(StopSignal::STATION_FAILED);
            ended = Some(Ended::ServerFailed);
        }
        if let Some(how) = ended.filter(|_| !station.running()) {
            station.join();
            // The pages have the result; their streams end so the server can stop.
            station.log().close();
            return how;
        }
    }
}
