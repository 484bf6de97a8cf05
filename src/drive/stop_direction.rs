//! Which way a command moves a drive on its state machine, for the safe stop, which may
//! only ever move a drive toward power off. A drive reads the write, not the name we give
//! it: CiA 402's `disable_operation` and `switch_on` are both control word 7, so a command
//! is judged by every command its profile writes the same way. Pure; no I/O.

use super::device_control::{DeviceCommand, DeviceState};
use super::state_path::transition;
use crate::dictionary::Profile;

/// The default safe stop's commands after the brake, in order: each is sent only where it
/// does not move the drive up ([`moves_up`]).
pub const DEFAULT_STOP: [DeviceCommand; 2] = [DeviceCommand::DisableOperation, DeviceCommand::Shutdown];

/// How far a state is from power off: the power stage off (0: switch on disabled, fault,
/// booting), ready to switch on (1), switched on (2), the power stage driving the motor
/// while it stops (3: quick stop, fault reaction), operation enabled (4). A stop only
/// lowers it.
pub fn power_rank(state: DeviceState) -> u8 {
    match state {
        DeviceState::NotReadyToSwitchOn | DeviceState::SwitchOnDisabled | DeviceState::Fault => 0,
        DeviceState::ReadyToSwitchOn => 1,
        DeviceState::SwitchedOn => 2,
        DeviceState::QuickStopActive | DeviceState::FaultReactionActive => 3,
        DeviceState::OperationEnabled => 4,
    }
}

/// The commands `profile` writes exactly as it writes `command` (`command` first): what a
/// drive may take that write for.
pub fn same_writes(profile: &Profile, command: DeviceCommand) -> Vec<DeviceCommand> {
    let Some(write) = profile.command(command) else {
        return Vec::new();
    };
    let mut all = vec![command];
    all.extend(DeviceCommand::ALL.into_iter().filter(|c| {
        *c != command
            && profile
                .command(*c)
                .is_some_and(|w| w.object == write.object && w.value == write.value)
    }));
    all
}

/// Where the write of `command` takes a drive in `from`, read as the drive reads it: the
/// transition of whichever command of the same write the state machine has from `from`
/// (the highest one, where several could apply, so that a check on it errs to safety),
/// among the states the profile has (a drive cannot show one it lacks).
pub fn taken_to(profile: &Profile, from: DeviceState, command: DeviceCommand) -> DeviceState {
    same_writes(profile, command)
        .into_iter()
        .map(|c| transition(from, c))
        .filter(|s| profile.has_state(*s))
        .max_by_key(|s| power_rank(*s))
        .unwrap_or(from)
}

/// Whether sending `command` to a drive in `from` could move it up its state machine:
/// the safe stop never sends it then.
pub fn moves_up(profile: &Profile, from: DeviceState, command: DeviceCommand) -> bool {
    power_rank(taken_to(profile, from, command)) > power_rank(from)
}

#[cfg(test)]
#[path = "stop_direction_tests.rs"]
mod tests;
