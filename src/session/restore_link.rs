//! Reaching a drive again after its link was lost, for the safe stop: the port reopened
//! with back-off until the drive answers (and is the same drive) or the reconnect time is
//! used up. It must not send any stop command (that is `safe_stop.rs`).

use super::session::show_duration;
use super::session::{secs, Session};
use crate::drive::DriveError;
use std::time::Duration;

/// First pause between attempts to reopen a lost port; doubled up to [`REOPEN_PAUSE_MAX`].
const REOPEN_PAUSE: Duration = Duration::from_millis(100);
const REOPEN_PAUSE_MAX: Duration = Duration::from_secs(2);

impl Session<'_> {
    /// After a reopen: what shows that the drive answers again — its state read, or
    /// without a device-control profile its identity (or, without that, the port being
    /// open). The state is not told here: the end line tells it once, from what the stop
    /// reads back at its end (a replay answers this read from wherever its capture stood).
    fn answer_after_reopen(&mut self) -> Result<String, DriveError> {
        if self.has_device_control() {
            return self
                .drive()
                .state()
                .map(|_| "the drive answers again (its state is read back at the end of the stop)".into());
        }
        match self
            .drive_ref()
            .dictionary()
            .lookup("ident")
            .ok()
            .map(|d| d.name.clone())
        {
            Some(name) => self.drive().read(&name).map(|_| {
                "the drive answers (its state cannot be read without a device-control profile)".into()
            }),
            None => Ok("the port is open again (no device-control profile to read the drive's state)".into()),
        }
    }

    /// After a reopen: whether the drive answering has the identity read at the start (a
    /// re-enumerated adapter can come back under a name another one had).
    fn same_drive(&mut self) -> bool {
        match self.cur().identity.clone() {
            Some(before) => self.identity().is_none_or(|now| now == before),
            None => true,
        }
    }

    /// Reopens the port with back-off until it answers or the reconnect time is used up;
    /// reports every attempt. True when the drive answers again.
    pub fn restore_link(&mut self) -> bool {
        if self.cur().link_given_up {
            return false;
        }
        let started = self.clock.now();
        let give_up = started.saturating_add(self.settings.reconnect_timeout);
        let mut pause = REOPEN_PAUSE;
        let port = self.drive_ref().port();
        for attempt in 1u32.. {
            let result = self.drive().reopen().and_then(|()| self.answer_after_reopen());
            let at = secs(self.clock.now().saturating_sub(started));
            match result {
                Ok(_) if !self.same_drive() => {
                    self.note(format!(
                        "{port} answers again, but with another drive's identity; the stop is not sent to it. CHECK THE DRIVE BY HAND"
                    ));
                    self.cur().link_given_up = true;
                    return false;
                }
                Ok(answer) => {
                    self.note(format!(
                        "link to {port} restored at attempt {attempt} after {at}; {answer}"
                    ));
                    return true;
                }
                Err(e) => self.observer.message(&format!(
                    "safe stop: reopening {port}, attempt {attempt} after {at}: {e}"
                )),
            }
            let next = self.clock.now().saturating_add(pause);
            if next > give_up {
                self.note(format!(
                    "gave up reopening {port} after {attempt} attempt(s) in {}",
                    show_duration(self.settings.reconnect_timeout)
                ));
                self.cur().link_given_up = true;
                return false;
            }
            // A further stop request does not end the attempts: reaching the drive is
            // the only way to stop it.
            self.clock.sleep_until(next);
            pause = (pause * 2).min(REOPEN_PAUSE_MAX);
        }
        false
    }
}
