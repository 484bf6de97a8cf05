//! Real or virtual time, shared by the engine, the link and the simulator.
//!
//! Everything that waits asks a [`Clock`]; nothing calls `std::thread::sleep` directly, so
//! the same code runs a two-hour run-in in real time against a drive, or in well under a
//! second against the simulator with [`VirtualClock`], with identical results.
//! This module must not know about drives or protocols.

use crate::stop_request::{StopRequests, WaitStep};
use std::fmt::Debug;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};

/// A source of time that can also wait.
pub trait Clock: Send + Sync + Debug {
    /// Time elapsed since the clock started.
    fn now(&self) -> Duration;
    /// Waits until [`Clock::now`] has reached `deadline` (a virtual clock jumps there).
    fn sleep_until(&self, deadline: Duration);
    /// True for a clock that jumps instead of waiting.
    fn is_virtual(&self) -> bool;
    /// Wall-clock time at which the clock started, for reports and traces.
    fn started_at(&self) -> SystemTime;

    /// Waits until `deadline` or until a stop request is pending, whichever comes first;
    /// true when it was the stop request. Every wait of the engine goes through here, so a
    /// stop request wakes it at once instead of when the step would have woken anyway.
    fn wait_until(&self, deadline: Duration, stop: &StopRequests) -> bool {
        loop {
            let now = self.now();
            match stop.wait_step(now, deadline) {
                WaitStep::Stopped => return true,
                WaitStep::Reached => return false,
                WaitStep::Until(until) => self.wait_step_until(now, until, stop),
            }
        }
    }
    /// One step of [`Clock::wait_until`]: towards `until` (the deadline or the time of a
    /// scheduled stop request), from `now`; it may return early, and is asked again.
    fn wait_step_until(&self, now: Duration, until: Duration, stop: &StopRequests);

    /// Waits for `duration`.
    fn sleep(&self, duration: Duration) {
        self.sleep_until(self.now() + duration);
    }
    /// Wall-clock time now (for a virtual clock: its start plus virtual time).
    fn wall_time(&self) -> SystemTime {
        self.started_at() + self.now()
    }
}

/// A clock shared between threads and layers.
pub type SharedClock = Arc<dyn Clock>;

/// Wall-clock time, waiting for real.
#[derive(Debug)]
pub struct RealClock {
    start: Instant,
    started_at: SystemTime,
}

impl RealClock {
    pub fn new() -> Self {
        RealClock {
            start: Instant::now(),
            started_at: SystemTime::now(),
        }
    }

    pub fn shared() -> SharedClock {
        Arc::new(Self::new())
    }
}

impl Default for RealClock {
    fn default() -> Self {
        Self::new()
    }
}

/// Below this, `thread::sleep` overshoots by a large fraction of the wait (scheduler
/// granularity), so the last stretch is spun. Wire-time emulation at 57600 bit/s waits in
/// steps of a few hundred microseconds and needs that precision.
const SPIN_BELOW: Duration = Duration::from_micros(200);

impl Clock for RealClock {
    fn now(&self) -> Duration {
        self.start.elapsed()
    }

    fn sleep_until(&self, deadline: Duration) {
        loop {
            let now = self.now();
            if now >= deadline {
                return;
            }
            let left = deadline - now;
            if left > SPIN_BELOW {
                std::thread::sleep(left - SPIN_BELOW);
            } else {
                std::hint::spin_loop();
            }
        }
    }

    fn wait_step_until(&self, now: Duration, until: Duration, stop: &StopRequests) {
        if until - now > SPIN_BELOW {
            stop.wait_real(until - now - SPIN_BELOW)
        } else {
            std::hint::spin_loop()
        }
    }

    fn is_virtual(&self) -> bool {
        false
    }

    fn started_at(&self) -> SystemTime {
        self.started_at
    }
}

/// Simulated time: waiting moves the clock forward at once.
///
/// Only correct when everything the waiter waits for is itself driven by this clock (the
/// in-process simulator); a real port needs [`RealClock`].
#[derive(Debug)]
pub struct VirtualClock {
    nanos: AtomicU64,
    started_at: SystemTime,
}

impl VirtualClock {
    /// A virtual clock whose wall time starts at the real present moment.
    pub fn new() -> Self {
        Self::starting_at(SystemTime::now())
    }

    /// A virtual clock with a fixed wall-clock start, for reproducible reports.
    pub fn starting_at(started_at: SystemTime) -> Self {
        VirtualClock {
            nanos: AtomicU64::new(0),
            started_at,
        }
    }

    pub fn shared() -> SharedClock {
        Arc::new(Self::new())
    }

    /// Moves the clock forward by `duration` without anybody waiting.
    pub fn advance(&self, duration: Duration) {
        self.nanos.fetch_add(saturating_nanos(duration), Ordering::SeqCst);
    }
}

impl Default for VirtualClock {
    fn default() -> Self {
        Self::new()
    }
}

fn saturating_nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

impl Clock for VirtualClock {
    fn now(&self) -> Duration {
        Duration::from_nanos(self.nanos.load(Ordering::SeqCst))
    }

    fn sleep_until(&self, deadline: Duration) {
        let target = saturating_nanos(deadline);
        // A deadline already passed needs no locked write (a read is a plain load).
        if self.nanos.load(Ordering::SeqCst) < target {
            self.nanos.fetch_max(target, Ordering::SeqCst);
        }
    }

    fn wait_step_until(&self, _now: Duration, until: Duration, _stop: &StopRequests) {
        // A request scheduled before the deadline ends the jump there, at its time
        // (`wait_step` has delivered those due by now, so time always moves on).
        self.sleep_until(until);
    }

    fn is_virtual(&self) -> bool {
        true
    }

    fn started_at(&self) -> SystemTime {
        self.started_at
    }
}

/// For tests: a virtual clock on which time passes between any two readings, as a real
/// one's does (each reading `tick` after the one before), so that code which reads the
/// clock twice and assumes nothing passed in between is caught.
#[cfg(test)]
#[derive(Debug, Default)]
pub struct TickingClock {
    pub clock: VirtualClock,
    pub tick: Duration,
}

#[cfg(test)]
impl TickingClock {
    pub fn new(tick: Duration) -> Self {
        TickingClock {
            clock: VirtualClock::new(),
            tick,
        }
    }
}

#[cfg(test)]
impl Clock for TickingClock {
    fn now(&self) -> Duration {
        self.clock.advance(self.tick);
        self.clock.now()
    }
    fn sleep_until(&self, deadline: Duration) {
        self.clock.sleep_until(deadline)
    }
    fn wait_step_until(&self, _now: Duration, until: Duration, _stop: &StopRequests) {
        self.clock.sleep_until(until)
    }
    fn is_virtual(&self) -> bool {
        true
    }
    fn started_at(&self) -> SystemTime {
        self.clock.started_at()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn virtual_sleep_jumps_and_never_goes_back() {
        let c = VirtualClock::new();
        c.sleep(Duration::from_secs(7200));
        assert_eq!(c.now(), Duration::from_secs(7200));
        c.sleep_until(Duration::from_secs(10));
        assert_eq!(c.now(), Duration::from_secs(7200));
        c.advance(Duration::from_millis(5));
        assert_eq!(c.now(), Duration::from_millis(7_200_005));
        assert!(c.is_virtual());
    }

    #[test]
    fn real_sleep_reaches_its_deadline() {
        let c = RealClock::new();
        let deadline = c.now() + Duration::from_millis(2);
        c.sleep_until(deadline);
        assert!(c.now() >= deadline);
        assert!(!c.is_virtual());
    }

    #[test]
    fn a_virtual_wait_ends_at_a_scheduled_stop_request_not_at_its_deadline() {
        use crate::stop_request::StopSignal;
        let c = VirtualClock::new();
        let stop = StopRequests::new();
        let s = Duration::from_secs;
        stop.schedule(s(15), StopSignal::TERM);
        assert!(!c.wait_until(s(10), &stop));
        assert_eq!(c.now(), s(10));
        assert!(c.wait_until(s(40), &stop));
        assert_eq!(c.now(), s(15));
        stop.acknowledge();
        assert!(!c.wait_until(s(20), &stop));
        assert_eq!(c.now(), s(20));
    }

    #[test]
    fn a_real_wait_wakes_within_milliseconds_of_a_request_from_another_thread() {
        use crate::stop_request::StopSignal;
        let c = RealClock::new();
        let stop = std::sync::Arc::new(StopRequests::new());
        let sender = stop.clone();
        let t = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(30));
            sender.request(StopSignal::INT);
        });
        let before = c.now();
        assert!(c.wait_until(before + Duration::from_secs(60), &stop));
        // Generous bound: this fails only if the wait ran to its deadline.
        assert!(c.now() - before < Duration::from_secs(30));
        t.join().expect("sender");
    }

    #[test]
    fn wall_time_follows_virtual_time() {
        let start = SystemTime::UNIX_EPOCH + Duration::from_secs(1_000_000);
        let c = VirtualClock::starting_at(start);
        c.advance(Duration::from_secs(3));
        assert_eq!(c.wall_time(), start + Duration::from_secs(3));
    }
}
