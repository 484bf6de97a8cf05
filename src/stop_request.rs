//! Requests to stop a run (stop signals, or a request scheduled at a clock time), counted,
//! with a condition variable so that every wait in the engine wakes at once when one
//! arrives. The first request asks for the safe stop; a request that arrives while the safe
//! stop runs asks for the power stage to be switched off at once. This module only counts
//! and wakes; what a request means for a drive is the session's business.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};
use std::time::Duration;

/// A stop signal, by its POSIX number (the same on every Unix for these four).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StopSignal {
    pub number: i32,
    pub name: &'static str,
}

impl StopSignal {
    pub const HUP: StopSignal = StopSignal::posix(1, "SIGHUP");
    pub const INT: StopSignal = StopSignal::posix(2, "SIGINT");
    pub const QUIT: StopSignal = StopSignal::posix(3, "SIGQUIT");
    pub const TERM: StopSignal = StopSignal::posix(15, "SIGTERM");
    pub const ALL: [StopSignal; 4] = [Self::INT, Self::TERM, Self::HUP, Self::QUIT];
    /// The operator station's Stop button: the same request as Ctrl-C, said as what it is.
    pub const STOP_BUTTON: StopSignal = StopSignal::posix(2, "the Stop button");
    /// The operator station's web server failed: nobody can answer or press Stop any more,
    /// so the run it started is stopped as by SIGTERM.
    pub const STATION_FAILED: StopSignal = StopSignal::posix(15, "the station's server failing");
    /// Windows' console events besides Ctrl-C (which is SIGINT there too), numbered as its
    /// C runtime numbers the signals it raises for them (SIGBREAK 21; a closed console
    /// window is the hang-up of Windows).
    pub const CTRL_BREAK: StopSignal = StopSignal::posix(21, "Ctrl-Break");
    pub const CONSOLE_CLOSED: StopSignal = StopSignal::posix(1, "console closed");

    const fn posix(number: i32, name: &'static str) -> StopSignal {
        StopSignal { number, name }
    }

    /// The signal with this number, if it is one of the four stop signals.
    pub fn from_number(number: i32) -> Option<StopSignal> {
        Self::ALL.into_iter().find(|s| s.number == number)
    }

    /// `INT`, `SIGINT`, `int`: for test cases and options.
    pub fn from_name(name: &str) -> Option<StopSignal> {
        let upper = name.trim().to_ascii_uppercase();
        let short = upper.strip_prefix("SIG").unwrap_or(&upper);
        Self::ALL.into_iter().find(|s| &s.name[3..] == short)
    }

    /// The exit code after the safe stop: 128 + the signal number, as shells report it.
    pub fn exit_code(self) -> i32 {
        128 + self.number
    }

    /// What usually sends it, for the message the user reads.
    pub fn describe(self) -> &'static str {
        if self == Self::STOP_BUTTON {
            return "the Stop button on the operator station";
        }
        if self == Self::STATION_FAILED {
            return "the operator station's web server, which failed (a bug)";
        }
        match self.name {
            "SIGHUP" => "SIGHUP (terminal closed or ssh session dropped)",
            "SIGINT" => "Ctrl-C (SIGINT)",
            "SIGQUIT" => "SIGQUIT (Ctrl-\\)",
            "Ctrl-Break" => "Ctrl-Break",
            "console closed" => "the console window closing (or Windows logging off or shutting down)",
            _ => "SIGTERM (kill, timeout, systemd or a cancelled CI job)",
        }
    }
}

/// See [`StopRequests::wait_step`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WaitStep {
    Stopped,
    Reached,
    Until(Duration),
}

#[derive(Debug, Default)]
struct State {
    /// Every request so far, in order of arrival.
    received: Vec<StopSignal>,
    /// Requests already being served: the safe stop answers the first; only a later one
    /// interrupts it.
    acknowledged: usize,
    /// Once the last resort (disable voltage) has started, no request may interrupt it.
    final_stage: bool,
    /// The safe stop runs: a first request asks for what is being done anyway, so only a
    /// second one is pending — for the link too, whose exchange it must not cut off.
    safe_stop: bool,
    /// Requests that arrive by themselves when the clock reaches their time, sorted.
    scheduled: Vec<(Duration, StopSignal)>,
}

impl State {
    fn pending(&self) -> bool {
        let needed = if self.safe_stop { 2 } else { 1 };
        !self.final_stage && self.received.len() > self.acknowledged && self.received.len() >= needed
    }
}

/// The run's stop requests, shared by the signal watcher, the engine and the link.
#[derive(Debug)]
pub struct StopRequests {
    state: Mutex<State>,
    changed: Condvar,
    /// True until the first request arrives or is scheduled: every wait and every read asks
    /// whether a stop is pending, millions of times in a long run, and this answers the
    /// usual "no" without taking the lock.
    quiet: AtomicBool,
}

impl Default for StopRequests {
    fn default() -> Self {
        StopRequests {
            state: Mutex::default(),
            changed: Condvar::new(),
            quiet: AtomicBool::new(true),
        }
    }
}

impl StopRequests {
    pub fn new() -> Self {
        Self::default()
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic while holding this lock cannot leave the counters half-updated, and the
        // safe stop after a panic needs them.
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// A stop request arrives now (a signal, a button).
    pub fn request(&self, signal: StopSignal) {
        let mut s = self.lock();
        s.received.push(signal);
        self.quiet.store(false, Ordering::SeqCst);
        drop(s);
        self.changed.notify_all();
    }

    /// A stop request that arrives by itself when the clock reaches `at` (in virtual time
    /// too, where no thread could deliver it at the right moment).
    pub fn schedule(&self, at: Duration, signal: StopSignal) {
        let mut s = self.lock();
        let i = s.scheduled.partition_point(|(t, _)| *t <= at);
        s.scheduled.insert(i, (at, signal));
        self.quiet.store(false, Ordering::SeqCst);
        drop(s);
        self.changed.notify_all();
    }

    /// Delivers the scheduled requests due at `now`.
    fn deliver_due(s: &mut State, now: Duration) {
        while let Some(&(at, signal)) = s.scheduled.first() {
            if at > now {
                break;
            }
            s.scheduled.remove(0);
            s.received.push(signal);
        }
    }

    /// How many requests arrived by clock time `now`.
    pub fn count_at(&self, now: Duration) -> usize {
        if self.quiet.load(Ordering::SeqCst) {
            return 0;
        }
        let mut s = self.lock();
        Self::deliver_due(&mut s, now);
        s.received.len()
    }

    /// The first request, which decides the exit code.
    pub fn first(&self) -> Option<StopSignal> {
        self.lock().received.first().copied()
    }

    /// True when a request arrived (by `now`) that nobody has answered yet.
    pub fn pending_at(&self, now: Duration) -> bool {
        if self.quiet.load(Ordering::SeqCst) {
            return false;
        }
        let mut s = self.lock();
        Self::deliver_due(&mut s, now);
        s.pending()
    }

    /// The requests so far are being answered (the safe stop has started): waits go on
    /// until another one arrives.
    pub fn acknowledge(&self) {
        let mut s = self.lock();
        s.acknowledged = s.received.len();
    }

    /// The safe stop has started: the requests so far are being answered, and from now on
    /// only a second request in all interrupts a wait or an exchange.
    pub fn enter_safe_stop(&self) {
        let mut s = self.lock();
        s.acknowledged = s.received.len();
        s.safe_stop = true;
    }

    /// The safe stop is over: what arrived during it was answered by it, and a later run
    /// (of several files) is interrupted by the next request again.
    pub fn leave_safe_stop(&self) {
        let mut s = self.lock();
        s.acknowledged = s.received.len();
        s.safe_stop = false;
    }

    /// The last resort has started: from now on nothing interrupts a wait.
    pub fn enter_final_stage(&self) {
        self.lock().final_stage = true;
    }

    /// What a wait until `deadline` does next at clock time `now`: end because a request is
    /// pending, end because the deadline is reached, or wait until the returned time (the
    /// deadline, or an earlier scheduled request).
    pub fn wait_step(&self, now: Duration, deadline: Duration) -> WaitStep {
        if self.pending_at(now) {
            return WaitStep::Stopped;
        }
        if now >= deadline {
            return WaitStep::Reached;
        }
        WaitStep::Until(
            self.next_scheduled()
                .map_or(deadline, |at| at.clamp(now, deadline)),
        )
    }

    /// The next scheduled request after `now`, if any.
    pub fn next_scheduled(&self) -> Option<Duration> {
        if self.quiet.load(Ordering::SeqCst) {
            return None;
        }
        self.lock().scheduled.first().map(|(at, _)| *at)
    }

    /// Waits on the condition variable for at most `timeout` of real time, or until a
    /// request arrives or is scheduled. Returns at once if one is already pending.
    pub fn wait_real(&self, timeout: Duration) {
        let s = self.lock();
        if s.pending() {
            return;
        }
        let seen = (s.received.len(), s.scheduled.len());
        let _unused = self
            .changed
            .wait_timeout_while(s, timeout, |s| (s.received.len(), s.scheduled.len()) == seen)
            .unwrap_or_else(PoisonError::into_inner);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::time::Instant;

    #[test]
    fn the_first_request_is_pending_until_acknowledged_and_a_second_is_pending_again() {
        let stop = StopRequests::new();
        let t = Duration::ZERO;
        assert!(!stop.pending_at(t));
        stop.request(StopSignal::TERM);
        assert!(stop.pending_at(t));
        stop.acknowledge();
        assert!(!stop.pending_at(t));
        stop.request(StopSignal::INT);
        assert!(stop.pending_at(t));
        assert_eq!(stop.first(), Some(StopSignal::TERM));
        assert_eq!(stop.count_at(t), 2);
        stop.enter_final_stage();
        stop.request(StopSignal::INT);
        assert!(!stop.pending_at(t));
    }

    #[test]
    fn during_the_safe_stop_only_a_second_request_in_all_is_pending() {
        let stop = StopRequests::new();
        let t = Duration::ZERO;
        stop.enter_safe_stop();
        stop.request(StopSignal::INT);
        assert!(
            !stop.pending_at(t),
            "the first request asks for the stop that runs"
        );
        stop.request(StopSignal::INT);
        assert!(stop.pending_at(t));
        stop.leave_safe_stop();
        assert!(!stop.pending_at(t));
        stop.request(StopSignal::INT);
        assert!(stop.pending_at(t), "after the safe stop a request counts again");
    }

    #[test]
    fn scheduled_requests_arrive_when_the_clock_reaches_them() {
        let stop = StopRequests::new();
        let s = Duration::from_secs;
        stop.schedule(s(31), StopSignal::INT);
        stop.schedule(s(30), StopSignal::HUP);
        assert_eq!(stop.next_scheduled(), Some(s(30)));
        assert!(!stop.pending_at(s(29)));
        assert_eq!(stop.count_at(s(30)), 1);
        assert_eq!(stop.first(), Some(StopSignal::HUP));
        assert_eq!(stop.count_at(s(40)), 2);
        assert_eq!(stop.next_scheduled(), None);
    }

    #[test]
    fn a_request_from_another_thread_wakes_a_real_wait_at_once() {
        let stop = Arc::new(StopRequests::new());
        let other = stop.clone();
        let started = Instant::now();
        let sender = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(20));
            other.request(StopSignal::QUIT);
        });
        stop.wait_real(Duration::from_secs(30));
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "the wait did not wake"
        );
        assert!(stop.pending_at(Duration::ZERO));
        sender.join().expect("sender");
    }

    #[test]
    fn signal_names_numbers_and_exit_codes() {
        for (name, code) in [("INT", 130), ("SIGTERM", 143), ("hup", 129), ("QUIT", 131)] {
            let s = StopSignal::from_name(name).expect(name);
            assert_eq!(s.exit_code(), code);
            assert_eq!(StopSignal::from_number(s.number), Some(s));
        }
        assert_eq!(StopSignal::from_name("KILL"), None);
    }
}
