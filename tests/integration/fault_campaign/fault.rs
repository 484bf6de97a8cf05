//! The fault a scenario injects and when: before the safe stop (during the steps) or
//! inside it. Drive faults go into the simulated drive's `FaultInjection` (the simulator
//! core's knobs), stop signals into the run's stop requests, a store that goes away is a
//! lock another connection takes on the SQLite file. Choosing and applying only.

use super::recipe_gen::Rng;
use super::target::Target;
use drivescript::drive::device_control::DeviceCommand;
use drivescript::sim::SimulatedDrive;
use drivescript::stop_request::{StopRequests, StopSignal};
use std::time::Duration;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// Nothing goes wrong but what the recipe itself does.
    None,
    /// The drive trips with this drive error.
    Trip(u16),
    /// The line goes away (a pulled USB adapter, a lost CAN adapter) for this long.
    LineLost(Duration),
    /// The drive answers nothing for this long while the line is up.
    Silent(Duration),
    /// The next replies come this late.
    LateReplies(u32, Duration),
    /// The next replies come with line noise (a CAN frame's data scrambled).
    Garbage(u32),
    /// The next replies have a wrong check byte.
    Corrupt(u32),
    /// A CANopen node sends an EMCY with this code and runs on.
    Emcy(u16),
    /// A CiA 402 node's heartbeat and SDO answers stop for good.
    HeartbeatLoss,
    /// A stop signal.
    Signal(StopSignal),
    /// A stop signal, and another this much later.
    SecondSignal(StopSignal, StopSignal, Duration),
    /// The results store is locked by another connection from this step on (0: from the
    /// start): it takes nothing more and the run goes to the spool.
    StoreGone(usize),
    /// The simulated drive panics while handling a request.
    Panic,
    /// The enabled drive acknowledges these stop commands but does not obey them.
    Disobeys(&'static [DeviceCommand]),
}

/// A fault and where it falls.
#[derive(Debug, Clone, Copy)]
pub struct Fault {
    pub kind: Kind,
    /// Clock time of the fault (signals, trips, the start of a lost line).
    pub at: Duration,
    /// It falls inside the safe stop (as the dry run placed it).
    pub during_stop: bool,
}

const SIGNALS: [StopSignal; 4] = StopSignal::ALL;
const EMCY_CODES: [u16; 4] = [0x2310, 0x4310, 0x3210, 0x8110];
const IGNORED: [&[DeviceCommand]; 2] = [
    &[DeviceCommand::DisableOperation, DeviceCommand::Shutdown],
    &[
        DeviceCommand::DisableOperation,
        DeviceCommand::Shutdown,
        DeviceCommand::QuickStop,
        DeviceCommand::DisableVoltage,
    ],
];

fn millis(rng: &mut Rng, from: u64, to: u64) -> Duration {
    Duration::from_millis(from + rng.below(to - from))
}

/// A fault for `target`, placed with `stop_start` and `stop_end`: when the dry run's safe
/// stop began and when that run ended.
pub fn choose(target: &Target, rng: &mut Rng, stop_start: Duration, stop_end: Duration) -> Fault {
    let kind = loop {
        let kind = match rng.below(30) {
            0 | 1 => Kind::None,
            2..=5 => Kind::Trip(1 + rng.below(0x7FFE) as u16),
            6 | 7 => Kind::LineLost(millis(rng, 500, 8_000)),
            8..=10 => Kind::Silent(match rng.chance(30) {
                true => Duration::from_secs(3600),
                false => millis(rng, 200, 6_000),
            }),
            11 | 12 => Kind::LateReplies(1 + rng.below(4) as u32, millis(rng, 20, 3_000)),
            13 | 14 => Kind::Garbage(1 + rng.below(4) as u32),
            15 => Kind::Corrupt(1 + rng.below(4) as u32),
            16 | 17 if target.can => Kind::Emcy(rng.pick(&EMCY_CODES)),
            18 | 19 if target.heartbeat => Kind::HeartbeatLoss,
            20..=22 => Kind::Signal(rng.pick(&SIGNALS)),
            23..=25 => Kind::SecondSignal(rng.pick(&SIGNALS), rng.pick(&SIGNALS), millis(rng, 5, 2_000)),
            26 => Kind::StoreGone(rng.below(4) as usize),
            27 => Kind::Panic,
            28 | 29 if target.controlled => Kind::Disobeys(rng.pick(&IGNORED)),
            _ => continue,
        };
        break kind;
    };
    // Half inside the safe stop as the dry run had it, the rest anywhere in the steps.
    let during_stop = rng.chance(50) || stop_start < Duration::from_millis(300);
    let at = if during_stop {
        let stop = stop_end.saturating_sub(stop_start).as_millis() as u64;
        stop_start + millis(rng, 0, stop.max(1))
    } else {
        millis(rng, 200, stop_start.as_millis() as u64)
    };
    Fault {
        kind,
        at,
        during_stop,
    }
}

impl Fault {
    /// Puts the fault into the simulated drive (for the drive's own faults).
    pub fn inject(&self, sim: &mut dyn SimulatedDrive) {
        let at = self.at;
        let f = sim.faults();
        match self.kind {
            Kind::Trip(code) => {
                f.trip_at(at, code);
            }
            Kind::LineLost(d) => {
                f.line_down(at, at + d);
            }
            Kind::Silent(d) => {
                f.silent(at, at + d);
            }
            Kind::LateReplies(n, by) => {
                f.replies_from(at).delay_replies(n, by);
            }
            Kind::Garbage(n) => {
                f.replies_from(at).garbage(n);
            }
            Kind::Corrupt(n) => {
                f.replies_from(at).corrupt_checksum(n);
            }
            Kind::Emcy(code) => {
                f.emergency_at(at, code);
            }
            Kind::HeartbeatLoss => {
                f.silent(at, at + Duration::from_secs(24 * 3600));
            }
            Kind::Panic => {
                f.panic_at(at);
            }
            Kind::Disobeys(commands) => {
                f.ignore_commands(commands);
            }
            Kind::None | Kind::Signal(_) | Kind::SecondSignal(..) | Kind::StoreGone(_) => {}
        }
    }

    /// Schedules the stop signals of the fault.
    pub fn schedule(&self, stop: &StopRequests) {
        match self.kind {
            Kind::Signal(s) => stop.schedule(self.at, s),
            Kind::SecondSignal(first, second, after) => {
                stop.schedule(self.at, first);
                stop.schedule(self.at + after, second);
            }
            _ => {}
        }
    }

    /// The first signal's time, if the fault is a signal.
    pub fn signal_at(&self) -> Option<Duration> {
        matches!(self.kind, Kind::Signal(_) | Kind::SecondSignal(..)).then_some(self.at)
    }

    /// One line for a report of a failure.
    pub fn describe(&self) -> String {
        let when = if self.during_stop {
            "during the safe stop"
        } else {
            "during the steps"
        };
        format!("{:?} at {:?} ({when})", self.kind, self.at)
    }
}
