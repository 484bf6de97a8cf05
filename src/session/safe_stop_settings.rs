//! How the safety of a run behaves where a recipe or the command line may choose: how often
//! the drive is watched for faults, how long the safe stop waits for standstill, what counts
//! as standstill, how long it tries to reopen a lost port. Plain data with the documented
//! defaults.

use crate::dictionary::{Quantity, Unit};
use std::time::Duration;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafeStopSettings {
    /// How long the default safe stop waits, with the setpoint at 0, for the spindle to
    /// come to a standstill before it disables the drive. A spindle disabled at speed
    /// coasts for minutes, so this waits for the drive's own braking ramp.
    pub standstill_timeout: Duration,
    /// Speeds within ± this count as standstill.
    pub standstill: Quantity,
    /// Whether the safe stop brakes a turning drive (setpoint 0, wait for standstill)
    /// before anything disables it, a recipe's own `finally` included. Only a recipe's
    /// explicit `safe_stop: { brake_to_standstill: false }` turns it off (a drive that
    /// brakes by itself on disable, or a finally that stops it its own way).
    pub brake_to_standstill: bool,
    /// How long to keep trying to reopen a lost port to deliver the safe stop.
    pub reconnect_timeout: Duration,
    /// The status word is read for fault watching at most this often: between steps and
    /// during waits. Reading it after every step would halve the reads a run can make; at
    /// 250 ms it costs 2 % of a 57600 bit/s line (nothing while a `sample` reads the status
    /// word: its reply stands for the watch's), and the drive reacts to its own faults at
    /// once anyway (this only ends the recipe's steps).
    pub fault_poll: Duration,
    /// `run -x`: the first failed check ends the run through the safe stop, whatever the
    /// recipe's `on_failure` says.
    pub stop_on_failure: bool,
}

impl Default for SafeStopSettings {
    fn default() -> Self {
        SafeStopSettings {
            standstill_timeout: Duration::from_secs(60),
            standstill: Quantity::new(10.0, Some(Unit::Rpm)),
            brake_to_standstill: true,
            reconnect_timeout: Duration::from_secs(10),
            fault_poll: Duration::from_millis(250),
            stop_on_failure: false,
        }
    }
}
