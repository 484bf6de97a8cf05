//! How a drive was left after the safe stop: its state, its speed read back, and what the
//! stop could and could not confirm. One per run, and one per drive of a run with several;
//! the reports and the verdict rule read it. Plain data; nothing here commands a drive.

use crate::drive::device_control::DeviceState;

#[derive(Debug, Clone, Default, PartialEq)]
pub struct EndState {
    /// The state the drive was left in, when it could be read.
    pub final_state: Option<DeviceState>,
    /// The actual speed read back after the safe stop, in `speed_unit`.
    pub final_speed: Option<f64>,
    pub speed_unit: Option<String>,
    /// The power stage is off but the spindle still turns (it coasts without control).
    pub coasting: bool,
    /// The safe stop was verified by reading the state back (or a successful recipe left
    /// the drive enabled on purpose). False means CHECK THE DRIVE BY HAND.
    pub stop_confirmed: bool,
    /// The dictionary has no device-control profile: drivescript could neither command
    /// the drive nor read its state, so the end says that instead of a state.
    pub no_device_control: bool,
    /// The profile names an actual speed, but it could not be read back after the stop:
    /// standstill is not known.
    pub speed_unread: bool,
}

impl EndState {
    /// The truth about the drive after the safe stop, in one line: its state, its speed,
    /// and whether it is still coasting.
    pub fn drive_left(&self) -> String {
        if self.no_device_control && self.final_state.is_none() && self.stop_confirmed {
            return "drive state not known: the dictionary has no device-control profile, so drivescript neither commanded nor stopped the drive".to_string();
        }
        let state = match self.final_state {
            Some(s) => s.to_string(),
            None => "an unknown state (it could not be read back)".to_string(),
        };
        let speed = match (self.final_speed, &self.speed_unit) {
            (Some(v), Some(u)) => format!(" at {} {u}", super::condition::number(v.round())),
            (Some(v), None) => format!(" at speed {}", super::condition::number(v.round())),
            (None, _) if self.final_state.is_some() => ", speed not read".to_string(),
            (None, _) => String::new(),
        };
        let coasting = if self.coasting {
            " — STILL COASTING: the power stage is off and nothing brakes the spindle; keep clear until it stands still"
        } else {
            ""
        };
        format!("drive left in {state}{speed}{coasting}")
    }
}
