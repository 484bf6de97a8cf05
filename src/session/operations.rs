//! The simple operations: device commands, the state walk, writing and reading objects,
//! showing a message, and dwelling (a wait that watches for faults).

use super::session::Session;
use super::stop::Stop;
use super::{exact_with_unit, ObjectRef, SetValue};
use crate::dictionary::RawValue;
use crate::drive::{DeviceCommand, DeviceState, WriteOutcome};
use std::fmt::Write as _;
use std::time::Duration;

impl Session<'_> {
    /// Marks the current drive as the latest enabled: the safe stop stops the last
    /// enabled first.
    fn note_enabled(&mut self) {
        self.enable_count += 1;
        let order = self.enable_count;
        self.cur().enabled_order = order;
    }

    /// Writes one device-control command to the current drive. Once the run ends (on_fault,
    /// finally, the safe stop) a stop command is sent only where it moves the drive down
    /// (`command_down`): a `finally: [disable_operation, shutdown]` after steps that left
    /// the drive in ready to switch on must not switch it on again.
    pub fn command(&mut self, command: DeviceCommand) -> Result<String, Stop> {
        if self.in_safe_stop && crate::drive::stop_direction::DEFAULT_STOP.contains(&command) {
            return self.command_down(command);
        }
        self.send_command(command)
    }

    /// Writes one device-control command to the current drive, as it is.
    pub(super) fn send_command(&mut self, command: DeviceCommand) -> Result<String, Stop> {
        // Counted before sending: a drive whose enable was sent but not answered (a stop
        // signal, a lost reply) may be running and is stopped first.
        if command == DeviceCommand::EnableOperation {
            self.note_enabled();
        }
        let sent = self.drive().command(command);
        self.say_link_notices();
        sent?;
        Ok(self.drive_ref().profile()?.command_text(command))
    }

    /// Writes one device-control command to the drive called `drive`.
    pub fn command_on(&mut self, drive: &str, command: DeviceCommand) -> Result<String, Stop> {
        self.select(drive)?;
        self.command(command)
    }

    /// Writes one device-control command to every drive of the run, in the order declared
    /// (the one drive of a single-drive run); the first failure ends the step.
    pub fn command_all(&mut self, command: DeviceCommand) -> Result<String, Stop> {
        if !self.several_drives() {
            return self.command(command);
        }
        let mut done = Vec::new();
        for i in 0..self.drives.len() {
            self.current = i;
            let text = self.command(command)?;
            done.push(format!("{}: {text}", self.drives[i].name));
        }
        Ok(done.join("; "))
    }

    /// [`Session::go_to`] on the drive called `drive`.
    pub fn go_to_on(&mut self, drive: &str, state: DeviceState, timeout: Duration) -> Result<String, Stop> {
        self.select(drive)?;
        self.go_to(state, timeout)
    }

    /// [`Session::go_to`] on every drive of the run, one after the other.
    pub fn go_to_all(&mut self, state: DeviceState, timeout: Duration) -> Result<String, Stop> {
        if !self.several_drives() {
            return self.go_to(state, timeout);
        }
        let mut done = Vec::new();
        for i in 0..self.drives.len() {
            self.current = i;
            let text = self.go_to(state, timeout)?;
            done.push(format!("{}: {text}", self.drives[i].name));
        }
        Ok(done.join("; "))
    }

    /// Walks the state machine to `state`, each transition within `timeout`.
    pub fn go_to(&mut self, state: DeviceState, timeout: Duration) -> Result<String, Stop> {
        // The same rule as `interrupted`, without borrowing the session, whose drive the
        // walk borrows.
        let (stop, clock, in_safe_stop) = (self.stop, self.clock.clone(), self.in_safe_stop);
        if state == DeviceState::OperationEnabled {
            self.note_enabled();
        }
        let walked = self.drive().go_to(state, timeout, &move || {
            let now = clock.now();
            stop.pending_at(now) && !(in_safe_stop && stop.count_at(now) < 2)
        });
        self.say_link_notices();
        let transitions = walked?;
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
            let name = self.select_object(&object.name)?;
            let outcome = match value {
                // A bare quantity is in the object's unit.
                SetValue::Number(n) => {
                    self.track_setpoint(object, n.value);
                    self.drive().write(name, n)?
                }
                SetValue::Text(t) => self.drive().write_text(name, t)?,
            };
            if let WriteOutcome::Limited(stored) = outcome {
                let line = self.limited_warning(object, value, stored);
                self.observer.message(&format!("warning: {line}"));
                limited.push(line);
            }
        }
        if limited.is_empty() {
            Ok("written".into())
        } else {
            Ok(format!("written; warning: {}", limited.join(", ")))
        }
    }

    /// What a write the drive limited stored: read back from the drive (what later
    /// checks will see), else the value the drive reported with the write.
    pub(super) fn limited_warning(
        &mut self,
        object: &ObjectRef,
        asked: &SetValue,
        stored: RawValue,
    ) -> String {
        let asked = match asked {
            SetValue::Number(n) => exact_with_unit(n, object.unit.as_deref()),
            SetValue::Text(t) => format!("{t:?}"),
        };
        let name = object
            .name
            .split_once('.')
            .map_or(object.name.as_str(), |(_, o)| o);
        let stored = match self.drive().read(name) {
            Ok(v) => format!("{v} (read back)"),
            Err(_) => match self.drive_ref().object(name).map(|d| d.value_of(stored.clone())) {
                Ok(Ok(v)) => format!("{v} (as the drive reported it; the read-back failed)"),
                _ => format!("raw {stored} (as the drive reported it; the read-back failed)"),
            },
        };
        format!(
            "{} = {asked} was limited by the drive, which stored {stored}",
            object.name
        )
    }

    /// Reads objects and shows each value.
    pub fn read(&mut self, objects: &[ObjectRef]) -> Result<String, Stop> {
        // The step's own line shows the values; a line per value as well would say it twice.
        let mut shown = String::new();
        for o in objects {
            let name = self.select_object(&o.name)?;
            let v = self.drive().read(name)?;
            if !shown.is_empty() {
                shown.push_str(", ");
            }
            let _ = write!(shown, "{} = {v}", o.name);
        }
        Ok(shown)
    }

    /// Reads one object as a number in its engineering unit, for a front end that computes
    /// with it (a script's `read`); not a step of its own.
    pub fn read_number(&mut self, object: &ObjectRef) -> Result<f64, Stop> {
        let name = self.select_object(&object.name)?;
        Ok(self.drive().read_number(name)?)
    }

    /// The drive's state now, for a front end that branches on it; not a step of its own.
    pub fn state(&mut self) -> Result<DeviceState, Stop> {
        Ok(self.drive().state()?)
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

    /// Keeps `value` for the timeline when `object` is the drive's speed setpoint (of the
    /// first drive that writes one).
    pub(super) fn track_setpoint(&mut self, object: &ObjectRef, value: f64) {
        let is_setpoint = self
            .role_ref(crate::dictionary::Role::SpeedSetpoint)
            .is_some_and(|s| object.name.ends_with(&s.name));
        if !is_setpoint {
            return;
        }
        let t = self.clock.now().saturating_sub(self.run_start).as_secs_f64();
        let (tracked, series) = self
            .setpoints
            .get_or_insert_with(|| (object.clone(), super::BucketSeries::new(0.0, 1e-3)));
        if tracked.name == object.name {
            series.push(t, value);
        }
    }
}
