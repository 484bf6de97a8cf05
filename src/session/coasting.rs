//! The wait for a spindle that nothing can brake any more: its power stage is off (after
//! the stop, a coast-down, a trip) or the drive ignored the setpoint. The safe stop polls
//! the speed until standstill or the stop timeout and says which, so the end line reads a
//! speed the spindle really came down to; then the state is read once more after the
//! speed, so the end is told from the last reads. It must not send anything to the drive.

use super::safe_stop::STOP_POLL;
use super::session::{round, secs, show_duration, Session};
use crate::dictionary::Role;
use crate::drive::DeviceState;

impl Session<'_> {
    /// Polls the actual speed of the current drive, left in `state`, until it is within the
    /// standstill threshold or the stop timeout has passed; a note says how it ended. A
    /// powered drive is the escalation's business, a speed that cannot be read the end
    /// line's; neither is waited for here.
    pub(super) fn wait_for_coasting(&mut self, state: DeviceState) {
        // After a second stop request the power stage went off at once and the process
        // ends: the end line and the verdict say the spindle still coasts.
        if state.is_powered() || self.stop.count_at(self.clock.now()) >= 2 {
            return;
        }
        let Some(object) = self.role_ref(Role::SpeedActual) else {
            return;
        };
        let below = self.standstill_in(&object);
        let timeout = self.settings.standstill_timeout;
        let unit = object.unit.clone().map(|u| format!(" {u}")).unwrap_or_default();
        let called = self.cur().called();
        let started = self.clock.now();
        let give_up = started.saturating_add(timeout);
        let mut first = true;
        loop {
            let Ok(v) = self.drive().read_number(&object.name) else {
                return;
            };
            let waited = self.clock.now().saturating_sub(started);
            if v.abs() <= below {
                if !first {
                    self.note(format!(
                        "{called} coasted to standstill: {}{unit} after {}",
                        round(v),
                        secs(waited)
                    ));
                }
                return;
            }
            if first {
                self.note(format!(
                    "{called} is in {state} and its spindle turns at {}{unit}: nothing can brake it, so the stop waits for it to coast below {}{unit} (at most {})",
                    round(v),
                    round(below),
                    show_duration(timeout)
                ));
                first = false;
            }
            if waited >= timeout {
                self.note(format!(
                    "{called} still coasts at {}{unit} after the stop timeout ({}); keep clear until it stands still",
                    round(v),
                    show_duration(timeout)
                ));
                return;
            }
            let live = format!("{} {}{unit} (coasting)", object.name, round(v));
            self.observer
                .step_progress("safe stop", waited, Some(timeout), &live);
            if self
                .wait(self.clock.now().saturating_add(STOP_POLL).min(give_up))
                .is_err()
            {
                self.note(format!(
                    "the wait for {called} to coast to standstill was cut short by a further stop request"
                ));
                return;
            }
        }
    }

    /// The state read once more after the speed, so that the state told at the end is the
    /// last thing read (a drive that trips in between is told as in fault, not as stopped).
    pub(super) fn confirm_final_state(&mut self) {
        let Some(before) = self.report.end.final_state else {
            return;
        };
        match self.drive().state() {
            Ok(now) if now != before => {
                self.note(format!("the drive went from {before} to {now} as the stop ended"));
                self.report.end.final_state = Some(now);
                if matches!(now, DeviceState::OperationEnabled | DeviceState::QuickStopActive) {
                    self.report.end.stop_confirmed = false;
                }
            }
            Ok(_) => {}
            Err(e) => {
                // The state read before is no longer known to hold.
                self.report.end.stop_confirmed = false;
                self.report.end.final_state = None;
                self.note(format!(
                    "could not read the drive's state once more after its speed: {e}; CHECK THE DRIVE BY HAND"
                ));
            }
        }
    }
}
