//! What tests and the command line may ask of any family's simulated drive, whatever bytes
//! it speaks: its injected faults, the control words it accepted, its state and speed. The
//! family's own simulator type is reachable through `as_any_mut` for family-specific tests.

use super::FaultInjection;
use crate::drive::DeviceState;
use std::any::Any;
use std::time::Duration;

pub trait SimulatedDrive: Send {
    /// Faults to inject into the next replies or at a given time.
    fn faults(&mut self) -> &mut FaultInjection;
    /// Every control word accepted, in order (while logging is on).
    fn control_words_written(&self) -> Vec<u16>;
    /// The state changes control words made, as (clock time, from, to), oldest first.
    fn commanded_changes(&self) -> Vec<(Duration, DeviceState, DeviceState)>;
    /// The device state as of the last request.
    fn state(&self) -> DeviceState;
    /// Model speed (without noise) at clock time `now`.
    fn speed_rpm(&self, now: Duration) -> f64;
    /// Logging of requests and control words on (default) or off: a long run-in that nobody
    /// inspects need not keep every telegram.
    fn set_logging(&mut self, on: bool);
    /// One line for the command line's first output.
    fn describe(&self) -> String;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}
