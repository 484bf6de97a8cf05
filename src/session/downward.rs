//! The safe stop's own device-control commands, each sent only where it moves the drive
//! toward power off: from `ready to switch on`, CiA 402's `disable_operation` is control
//! word 7, which the drive reads as `switch on`. It must not choose which commands a stop
//! sends (that is `safe_stop.rs`).

use super::session::Session;
use super::stop::Stop;
use crate::drive::stop_direction::{moves_up, taken_to};
use crate::drive::{DeviceCommand, DeviceState};

impl Session<'_> {
    /// Sends `command` to the current drive unless, from the state it reads now, the
    /// drive would take it as a move up its state machine; then says why it was not sent.
    /// A state that cannot be read is no reason to hold back a stop, but no reason to risk
    /// a move up either: a command that would move some state up is replaced by disable
    /// voltage, which takes every state down (the power stage off at once).
    pub(super) fn command_down(&mut self, command: DeviceCommand) -> Result<String, Stop> {
        match self.drive().state() {
            Ok(state) => {
                let profile = self.drive_ref().profile()?;
                if moves_up(profile, state, command) {
                    return Ok(format!(
                        "not sent: the drive is in {state}, where {} would move it up to {}",
                        profile.command_text(command),
                        taken_to(profile, state, command)
                    ));
                }
            }
            Err(e) => {
                let profile = self.drive_ref().profile()?;
                let risky = DeviceState::ALL
                    .into_iter()
                    .filter(|s| profile.has_state(*s))
                    .any(|s| moves_up(profile, s, command));
                let off = DeviceCommand::DisableVoltage;
                if risky && command != off && profile.has_command(off) {
                    let instead = self.send_command(off)?;
                    return Ok(format!(
                        "the state could not be read ({e}), and {command} could move the drive up from some state: sent disable voltage instead ({instead})"
                    ));
                }
            }
        }
        self.send_command(command)
    }
}
