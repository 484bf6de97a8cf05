//! The simple operations: device commands, the state walk, writing and reading objects,
//! showing a message, and dwelling (a wait that watches for faults).

use super::session::Session;
use super::stop::Stop;
use super::{ObjectRef, SetValue};
use crate::dictionary::{Quantity, Unit};
use crate::drive::{DeviceCommand, DeviceState, WriteOutcome};
use std::time::Duration;

impl Session<'_> {
    /// Writes one device-control command.
    pub fn command(&mut self, command: DeviceCommand) -> Result<String, Stop> {
        self.drive.command(command)?;
        Ok(self.drive.profile()?.command_text(command))
    }

    /// Walks the state machine to `state`, each transition within `timeout`.
    pub fn go_to(&mut self, state: DeviceState, timeout: Duration) -> Result<String, Stop> {
        // The same rule as `interrupted`, without borrowing the session, whose drive the
        // walk borrows.
        let (stop, clock, in_safe_stop) = (self.stop, self.clock.clone(), self.in_safe_stop);
        let transitions = self.drive.go_to(state, timeout, &move || {
            let now = clock.now();
            stop.pending_at(now) && !(in_safe_stop && stop.count_at(now) < 2)
        })?;
        if transitions.is_empty() {
            Ok(format!("already {state}"))
        } else {
            Ok(transitions
                .iter()
                .map(|t| format!("{} → {}", t.command, t.to))
                .collect::<Vec<_>>()
                .join(", "))
        }
    }

    /// Writes objects in order; a value the drive limited is a warning, not a failure.
    pub fn set(&mut self, writes: &[(ObjectRef, SetValue)]) -> Result<String, Stop> {
        let mut limited = Vec::new();
        for (object, value) in writes {
            let outcome = match value {
                SetValue::Number(n) => {
                    let unit = object.unit.as_deref().and_then(Unit::from_symbol);
                    self.drive.write(&object.name, &Quantity::new(*n, unit))?
                }
                SetValue::Text(t) => self.drive.write_text(&object.name, t)?,
            };
            if let WriteOutcome::Limited(stored) = outcome {
                limited.push(format!(
                    "{} limited by the drive (stored raw {stored})",
                    object.name
                ));
            }
        }
        if limited.is_empty() {
            Ok("written".into())
        } else {
            Ok(format!("written; warning: {}", limited.join(", ")))
        }
    }

    /// Reads objects and shows each value.
    pub fn read(&mut self, objects: &[ObjectRef]) -> Result<String, Stop> {
        let mut shown = Vec::new();
        for o in objects {
            let v = self.drive.read(&o.name)?;
            let line = format!("{} = {v}", o.name);
            self.observer.message(&line);
            shown.push(line);
        }
        Ok(shown.join(", "))
    }

    /// Shows a message.
    pub fn print(&mut self, text: &str) -> Result<String, Stop> {
        self.observer.message(text);
        Ok(String::new())
    }

    /// Waits `d`, watching the drive for faults.
    pub fn dwell(&mut self, d: Duration, number: &str) -> Result<(), Stop> {
        let start = self.clock.now();
        let end = start.saturating_add(d);
        loop {
            self.watch_fault(true)?;
            let now = self.clock.now();
            if now >= end {
                return Ok(());
            }
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.observer.step_progress(number, now - start, Some(d), "");
            self.wait(now.saturating_add(self.settings.fault_poll).min(end))?;
        }
    }
}
