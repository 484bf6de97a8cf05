use super::*;
use crate::drive::device_control::{DeviceCommand::*, DeviceState::*};
use proptest::prelude::*;
use std::sync::OnceLock;

/// Every built-in dictionary's profile, by name: every family's.
fn profiles() -> &'static [(&'static str, Profile)] {
    static ALL: OnceLock<Vec<(&'static str, Profile)>> = OnceLock::new();
    ALL.get_or_init(|| {
        let registry = crate::family::Registry::builtin();
        let all: Vec<_> = registry
            .dictionary_names()
            .into_iter()
            .filter_map(|name| {
                let dictionary = registry
                    .load_dictionary(name)
                    .unwrap_or_else(|e| panic!("built-in dictionary {name}: {e}"));
                dictionary.profile().cloned().map(|p| (name, p))
            })
            .collect();
        // SD2, CT ANSI, Lenze 9400, CANopen 402 and both Modbus inverters (Lenze 931 has
        // no device-control profile: nothing to stop).
        assert!(
            all.len() >= 6,
            "built-in profiles: {:?}",
            all.iter().map(|(n, _)| n).collect::<Vec<_>>()
        );
        all
    })
}

/// What the safe stop sends, in the order it may send it: the default stop's commands
/// (each only where it does not move the drive up: `command_down`), then the escalation's
/// quick stop (only from operation enabled) and disable voltage (always).
fn stop_sends(profile: &Profile, state: DeviceState, command: DeviceCommand) -> bool {
    profile.has_command(command)
        && match command {
            QuickStop => state == OperationEnabled,
            DisableVoltage => true,
            c => DEFAULT_STOP.contains(&c) && !moves_up(profile, state, c),
        }
}

const SENT_BY_A_STOP: [DeviceCommand; 4] = [DisableOperation, Shutdown, QuickStop, DisableVoltage];

#[test]
fn from_ready_to_switch_on_disable_operation_reads_as_switch_on_and_is_not_sent() {
    let cia402 = Profile::with_defaults(Vec::new());
    assert_eq!(taken_to(&cia402, ReadyToSwitchOn, DisableOperation), SwitchedOn);
    assert!(moves_up(&cia402, ReadyToSwitchOn, DisableOperation));
    assert!(!moves_up(&cia402, OperationEnabled, DisableOperation));
    assert!(!moves_up(&cia402, SwitchedOn, Shutdown));
    // Shutdown from switch on disabled is a move up too (to ready to switch on).
    assert!(moves_up(&cia402, SwitchOnDisabled, Shutdown));
}

#[test]
fn escalation_commands_go_down_from_every_state_of_every_profile() {
    for (name, profile) in profiles() {
        for state in DeviceState::ALL.into_iter().filter(|s| profile.has_state(*s)) {
            for c in [QuickStop, DisableVoltage] {
                if stop_sends(profile, state, c) {
                    assert!(
                        !moves_up(profile, state, c),
                        "{name}: {c:?} from {state} goes to {}",
                        taken_to(profile, state, c)
                    );
                }
            }
        }
    }
}

proptest! {
    /// For any profile, any start state and any order of the stop's commands, no command
    /// the stop sends takes the drive up its state machine.
    #[test]
    fn the_stop_never_moves_a_drive_up(
        which in 0usize..64,
        start in 0usize..DeviceState::ALL.len(),
        order in proptest::collection::vec(0usize..SENT_BY_A_STOP.len(), 0..10),
    ) {
        let all = profiles();
        let (name, profile) = &all[which % all.len()];
        let states: Vec<DeviceState> =
            DeviceState::ALL.into_iter().filter(|s| profile.has_state(*s)).collect();
        let mut state = states[start % states.len()];
        for i in order {
            let command = SENT_BY_A_STOP[i];
            if !stop_sends(profile, state, command) {
                continue;
            }
            let next = taken_to(profile, state, command);
            prop_assert!(
                power_rank(next) <= power_rank(state),
                "{}: {:?} sent from {} moves the drive up to {}", name, command, state, next
            );
            state = next;
        }
    }
}
