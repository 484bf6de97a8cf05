//! Which device-control command moves a drive one step from a state toward a target state,
//! along the CiA 402 transition graph, using only the commands and states the drive's
//! profile has. Pure; no I/O.

use crate::dictionary::Profile;
use crate::drive::device_control::{DeviceCommand, DeviceState};

/// What to do next on the way from `from` to `to`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NextStep {
    /// Already there.
    Arrived,
    /// Send this command.
    Command(DeviceCommand),
    /// The drive moves on by itself (booting, fault reaction); wait.
    Wait,
    /// No command leads there from here.
    Unreachable,
}

/// The next step from `from` toward `to`. A drive in quick stop or fault is first brought
/// back through "switch on disabled" rather than straight on, so it never starts moving
/// again without passing the states where it is safe.
pub fn next_step(from: DeviceState, to: DeviceState) -> NextStep {
    use DeviceCommand::*;
    use DeviceState::*;
    if from == to {
        return NextStep::Arrived;
    }
    match (from, to) {
        (NotReadyToSwitchOn | FaultReactionActive, _) => NextStep::Wait,
        (_, NotReadyToSwitchOn | FaultReactionActive | Fault) => NextStep::Unreachable,
        (Fault, _) => NextStep::Command(FaultReset),
        (QuickStopActive, _) => NextStep::Command(DisableVoltage),
        (_, QuickStopActive) if from == OperationEnabled => NextStep::Command(QuickStop),
        (SwitchOnDisabled, QuickStopActive) | (ReadyToSwitchOn | SwitchedOn, QuickStopActive) => {
            // Quick stop active is only entered from operation enabled; walk there first.
            next_step(from, OperationEnabled)
        }
        (_, SwitchOnDisabled) => NextStep::Command(DisableVoltage),
        (SwitchOnDisabled, _) => NextStep::Command(Shutdown),
        (ReadyToSwitchOn, SwitchedOn | OperationEnabled) => NextStep::Command(SwitchOn),
        (SwitchedOn, ReadyToSwitchOn) | (OperationEnabled, ReadyToSwitchOn) => NextStep::Command(Shutdown),
        (SwitchedOn, OperationEnabled) => NextStep::Command(EnableOperation),
        (OperationEnabled, SwitchedOn) => NextStep::Command(DisableOperation),
        _ => NextStep::Unreachable,
    }
}

/// Where `command` takes a drive in `from` on the CiA 402 graph (the drive itself decides in
/// the end; this is what the walk plans with).
pub fn transition(from: DeviceState, command: DeviceCommand) -> DeviceState {
    use DeviceCommand::*;
    use DeviceState::*;
    match (from, command) {
        (Fault, FaultReset) => SwitchOnDisabled,
        (_, DisableVoltage) => SwitchOnDisabled,
        (OperationEnabled, QuickStop) => QuickStopActive,
        (SwitchOnDisabled | SwitchedOn | OperationEnabled, Shutdown) => ReadyToSwitchOn,
        (ReadyToSwitchOn, SwitchOn) | (OperationEnabled, DisableOperation) => SwitchedOn,
        (SwitchedOn, EnableOperation) => OperationEnabled,
        _ => from,
    }
}

/// The next step from `from` toward `to` with what `profile` has. A complete profile walks
/// exactly as [`next_step`]. A drive with fewer commands or states takes the step
/// [`next_step`] gives when the profile has its command and the state it leads to, and
/// otherwise the first command of the shortest way through the states it has; a state the
/// profile lacks is never a target or a stop on the way.
pub fn next_step_in(profile: &Profile, from: DeviceState, to: DeviceState) -> NextStep {
    if profile.is_complete() {
        return next_step(from, to);
    }
    let step = next_step(from, to);
    match step {
        NextStep::Arrived | NextStep::Wait | NextStep::Unreachable => return step,
        NextStep::Command(_) if !profile.has_state(to) => return NextStep::Unreachable,
        NextStep::Command(c) if profile.has_command(c) && profile.has_state(transition(from, c)) => {
            return step
        }
        NextStep::Command(_) => {}
    }
    let commands: Vec<DeviceCommand> = DeviceCommand::ALL
        .into_iter()
        .filter(|c| profile.has_command(*c))
        .collect();
    let mut seen = vec![from];
    // Each state reached with the first command of the shortest path to it (none yet for
    // `from` itself).
    let mut frontier: Vec<(DeviceState, Option<DeviceCommand>)> = vec![(from, None)];
    while !frontier.is_empty() {
        let mut further = Vec::new();
        for (state, first) in frontier {
            for &c in &commands {
                let next = transition(state, c);
                let first = first.unwrap_or(c);
                if profile.has_state(next) && !seen.contains(&next) {
                    if next == to {
                        return NextStep::Command(first);
                    }
                    seen.push(next);
                    further.push((next, Some(first)));
                }
            }
        }
        frontier = further;
    }
    NextStep::Unreachable
}

#[cfg(test)]
mod tests {
    use super::*;
    use DeviceState::*;

    /// Follows the path with an ideal drive (every command takes effect at once, as
    /// [`transition`] plans).
    fn walk(mut from: DeviceState, to: DeviceState) -> Vec<DeviceCommand> {
        let mut commands = Vec::new();
        for _ in 0..10 {
            match next_step(from, to) {
                NextStep::Arrived => return commands,
                NextStep::Command(c) => {
                    commands.push(c);
                    from = transition(from, c);
                }
                other => panic!("{from:?} → {to:?}: {other:?}"),
            }
        }
        panic!("no arrival from {from:?} to {to:?}: {commands:?}");
    }

    #[test]
    fn every_commandable_state_reaches_operation_enabled_and_back() {
        use DeviceCommand::*;
        assert_eq!(
            walk(SwitchOnDisabled, OperationEnabled),
            vec![Shutdown, SwitchOn, EnableOperation]
        );
        assert_eq!(
            walk(Fault, OperationEnabled),
            vec![FaultReset, Shutdown, SwitchOn, EnableOperation]
        );
        assert_eq!(
            walk(QuickStopActive, OperationEnabled),
            vec![DisableVoltage, Shutdown, SwitchOn, EnableOperation]
        );
        assert_eq!(walk(OperationEnabled, SwitchOnDisabled), vec![DisableVoltage]);
        assert_eq!(walk(OperationEnabled, ReadyToSwitchOn), vec![Shutdown]);
        assert_eq!(walk(OperationEnabled, SwitchedOn), vec![DisableOperation]);
        assert_eq!(
            walk(SwitchOnDisabled, QuickStopActive),
            vec![Shutdown, SwitchOn, EnableOperation, QuickStop]
        );
        for from in [
            SwitchOnDisabled,
            ReadyToSwitchOn,
            SwitchedOn,
            OperationEnabled,
            QuickStopActive,
            Fault,
        ] {
            for to in [SwitchOnDisabled, ReadyToSwitchOn, SwitchedOn, OperationEnabled] {
                walk(from, to);
            }
        }
    }

    #[test]
    fn states_only_the_drive_enters_are_unreachable() {
        for to in [Fault, FaultReactionActive, NotReadyToSwitchOn] {
            assert_eq!(next_step(OperationEnabled, to), NextStep::Unreachable);
        }
        assert_eq!(next_step(FaultReactionActive, SwitchOnDisabled), NextStep::Wait);
        assert_eq!(next_step(NotReadyToSwitchOn, SwitchOnDisabled), NextStep::Wait);
    }
}
