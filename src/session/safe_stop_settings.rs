//! How the safe stop behaves where a recipe or the command line may choose: how long to
//! wait for standstill, what counts as standstill, how long to try to reopen a lost port.
//! Plain data with the documented defaults.

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
    /// How long to keep trying to reopen a lost port to deliver the safe stop.
    pub reconnect_timeout: Duration,
}

impl Default for SafeStopSettings {
    fn default() -> Self {
        SafeStopSettings {
            standstill_timeout: Duration::from_secs(60),
            standstill: Quantity::new(10.0, Some(Unit::Rpm)),
            reconnect_timeout: Duration::from_secs(10),
        }
    }
}
