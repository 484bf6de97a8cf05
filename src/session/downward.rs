//! The safe stop's device-control commands (its default ones and those of a recipe's own
//! `finally` or `on_fault`), each sent only where it moves the drive toward power off: from `ready to switch on`, CiA 402's `disable_operation` is control
//! word 7, which the drive reads as `switch on`. It must not choose which commands a stop
//! sends (that is `safe_stop.rs`).

use super::session::Session;
use super::stop::Stop;
use crate::drive::stop_direction::{moves_up, taken_to};
use crate::drive::DeviceCommand;

impl Session<'_> {
    /// Sends `command` to the current drive unless, from the state it reads now, the
    /// drive would take it as a move up its state machine; then says why it was not sent.
    /// A state that cannot be read is no reason to hold back a stop command.
    pub(super) fn command_down(&mut self, command: DeviceCommand) -> Result<String, Stop> {
        if let Ok(state) = self.drive().state() {
            let profile = self.drive_ref().profile()?;
            if moves_up(profile, state, command) {
                return Ok(format!(
                    "not sent: the drive is in {state}, where {} would move it up to {}",
                    profile.command_text(command),
                    taken_to(profile, state, command)
                ));
            }
        }
        self.send_command(command)
    }
}
