//! What every family's simulator front shares around its own bytes: the drive model, the
//! injected faults, the bounded logs of what it was sent and of the control words it took,
//! and the [`SimulatedDrive`] answers built from them. A front implements [`SimFront`] and
//! gets [`SimulatedDrive`]; it must not repeat any of this. Nothing here knows bytes.

use super::{keep_recent, DriveModel, FaultInjection, SimConfig, SimulatedDrive};
use crate::drive::{DeviceCommand, DeviceState};
use std::any::Any;
use std::time::Duration;

/// The family-neutral half of a simulated drive; `E` is what the front logs per request
/// (a decoded telegram with its time, a request line).
#[derive(Debug)]
pub struct SimCore<E> {
    pub model: DriveModel,
    pub faults: FaultInjection,
    logging: bool,
    requests: Vec<E>,
    control_words: Vec<u16>,
}

impl<E> SimCore<E> {
    /// A drive just switched on: the model's first state, no faults but the emergency
    /// messages the settings schedule, logging on.
    pub fn new(config: SimConfig) -> Self {
        let mut faults = FaultInjection::default();
        for &(at, code) in &config.emergencies {
            faults.emergency_at(at, code);
        }
        for &(at, code) in &config.trips {
            faults.trip_at(at, code);
        }
        if let Some((from, until)) = config.silent {
            faults.silent(from, until);
        }
        SimCore {
            model: DriveModel::new(config),
            faults,
            logging: true,
            requests: Vec::new(),
            control_words: Vec::new(),
        }
    }

    /// Moves the model to `now`, tripping at every injected trip due on the way.
    pub fn advance_to(&mut self, now: Duration) {
        while let Some((at, code)) = self.faults.take_trip_due(now) {
            self.model.advance_to(at);
            self.model.trip(code);
        }
        self.model.advance_to(now);
    }

    /// When the reply to a request that arrived at `now` goes out: after the configured
    /// response latency, and never sooner than the protocol's `turnaround`.
    pub fn reply_at(&self, now: Duration, turnaround: Duration) -> Duration {
        now + turnaround.max(self.model.config().response_latency)
    }

    /// The injected panic, when it is due: a front calls this first for every request.
    pub fn panic_if_due(&mut self, now: Duration) {
        if self.faults.take_panic_due(now) {
            panic!("injected test fault: the simulated drive panics while handling a request");
        }
    }

    /// What a front does first with every request it takes: the injected panic when it is
    /// due, then the model moved to `now`.
    pub fn take_request_at(&mut self, now: Duration) {
        self.panic_if_due(now);
        self.advance_to(now);
    }

    /// True when an injected fault makes the enabled drive ignore `command` (it still
    /// starts up normally, so a recipe can get it running).
    pub fn disobeys(&self, command: DeviceCommand) -> bool {
        matches!(
            self.model.state(),
            DeviceState::OperationEnabled | DeviceState::QuickStopActive
        ) && self.faults.ignores(command)
    }

    /// [`disobeys`](Self::disobeys) the command `control_word` gives.
    pub fn disobeys_word(&self, control_word: u16) -> bool {
        self.disobeys(self.model.command_for(control_word))
    }

    /// Keeps `entry` in the request log (while logging is on; the latest entries only).
    pub fn log_request(&mut self, entry: E) {
        if self.logging {
            keep_recent(&mut self.requests, entry);
        }
    }

    /// Keeps `control_word` in the control-word log (while logging is on).
    pub fn log_control_word(&mut self, control_word: u16) {
        if self.logging {
            keep_recent(&mut self.control_words, control_word);
        }
    }

    /// What the drive was sent, in order (while logging is on; the latest 10 000 at least).
    pub fn requests(&self) -> &[E] {
        &self.requests
    }

    pub fn control_words(&self) -> &[u16] {
        &self.control_words
    }

    /// Forgets both logs.
    pub fn clear_log(&mut self) {
        self.requests.clear();
        self.control_words.clear();
    }

    pub fn set_logging(&mut self, on: bool) {
        self.logging = on;
    }
}

/// The line of a byte front's [`Peer`](crate::bus::Peer) as its [`SimCore`]'s faults have
/// it (up, and until when), written inside its `impl Peer`: `sim_line_core!();`.
#[macro_export]
macro_rules! sim_line_core {
    () => {
        fn reachable(&self, now: std::time::Duration) -> bool {
            self.core.faults.line_up(now)
        }

        fn up_until(&self, now: std::time::Duration) -> std::time::Duration {
            self.core.faults.line_up_until(now)
        }
    };
}

/// The CAN adapter of a frame front's [`FramePeer`](crate::bus::FramePeer) as its
/// [`SimCore`]'s faults have it, written inside its `impl FramePeer`: `sim_frame_line_core!();`.
#[macro_export]
macro_rules! sim_frame_line_core {
    () => {
        fn reachable(&self, now: std::time::Duration) -> bool {
            self.core.faults.line_up(now)
        }
    };
}

/// The [`SimFront`] accessors of a front that keeps its [`SimCore`] in a field `core`,
/// written inside its `impl SimFront`: `sim_front_core!((Duration, Request));` logs each
/// request as its time and the decoded request.
#[macro_export]
macro_rules! sim_front_core {
    ($logged:ty) => {
        type Logged = $logged;
        fn core(&self) -> &$crate::sim::SimCore<Self::Logged> {
            &self.core
        }
        fn core_mut(&mut self) -> &mut $crate::sim::SimCore<Self::Logged> {
            &mut self.core
        }
    };
}

/// A family's simulator front: its own bytes around a [`SimCore`].
pub trait SimFront: Send + 'static {
    /// What the front logs per request.
    type Logged;
    fn core(&self) -> &SimCore<Self::Logged>;
    fn core_mut(&mut self) -> &mut SimCore<Self::Logged>;
    /// One line for the command line's first output.
    fn describe_drive(&self) -> String;
}

impl<T: SimFront> SimulatedDrive for T {
    fn faults(&mut self) -> &mut FaultInjection {
        &mut self.core_mut().faults
    }
    fn control_words_written(&self) -> Vec<u16> {
        self.core().control_words().to_vec()
    }
    fn commanded_changes(&self) -> Vec<(Duration, DeviceState, DeviceState)> {
        self.core().model.commanded_changes().to_vec()
    }
    fn state(&self) -> DeviceState {
        self.core().model.state()
    }
    fn speed_rpm(&self, now: Duration) -> f64 {
        let core = self.core();
        core.model.speed_at(&core.faults, now)
    }
    fn set_logging(&mut self, on: bool) {
        self.core_mut().set_logging(on);
    }
    fn describe(&self) -> String {
        self.describe_drive()
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
