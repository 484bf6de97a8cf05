use super::*;
use crate::session::{CheckResult, DriveEnd, EndState};
use crate::stop_request::StopSignal;
use std::time::SystemTime;

/// A confirmed stop that read the drive back in `state` at `speed` rpm.
fn stopped(state: DeviceState, speed: f64, coasting: bool) -> EndState {
    EndState {
        final_state: Some(state),
        final_speed: Some(speed),
        speed_unit: Some("rpm".into()),
        coasting,
        stop_confirmed: true,
        ..EndState::default()
    }
}

/// A run whose every check passed and whose stop read the drive back in `state` at
/// `speed` rpm.
fn ended(state: DeviceState, speed: f64, coasting: bool) -> RunReport {
    let mut r = RunReport::started(
        "r".into(),
        "r.yaml".into(),
        "sd2".into(),
        Vec::new(),
        SystemTime::now(),
    );
    r.checks.push(CheckResult::named("speed", true));
    r.end = stopped(state, speed, coasting);
    r
}

/// [`ended`], with a check that failed.
fn failing(state: DeviceState, speed: f64, coasting: bool) -> RunReport {
    let mut r = ended(state, speed, coasting);
    r.checks.push(CheckResult::named("current", false));
    r
}

/// `r` after the verdict rule.
fn settled(mut r: RunReport) -> RunReport {
    settle(&mut r);
    r
}

#[test]
fn a_drive_stopped_at_standstill_passes() {
    let r = settled(ended(DeviceState::ReadyToSwitchOn, 0.0, false));
    assert_eq!((r.verdict.clone(), r.exit_code()), (Verdict::Passed, 0));
    assert!(r.end.stop_confirmed);
}

#[test]
fn a_drive_that_trips_during_the_stop_and_coasts_is_an_error_whatever_the_checks_said() {
    let r = settled(ended(DeviceState::Fault, 2952.0, true));
    assert_eq!(r.exit_code(), 3);
    assert_eq!(r.verdict.word(), "ERROR");
    let why = r.verdict.reason().unwrap_or_default();
    assert!(
        why.contains("coasting") && why.contains("fault at 2952 rpm"),
        "{why}"
    );
    assert!(
        !r.end.stop_confirmed,
        "every report must say CHECK THE DRIVE BY HAND"
    );
}

#[test]
fn a_drive_left_in_fault_at_standstill_is_an_error() {
    let r = settled(ended(DeviceState::Fault, 0.0, false));
    assert_eq!(r.exit_code(), 3);
    assert!(r.verdict.reason().unwrap_or_default().contains("left in fault"));
}

#[test]
fn a_spindle_still_coasting_after_a_coast_down_is_an_error() {
    let r = settled(ended(DeviceState::ReadyToSwitchOn, 988.0, true));
    assert_eq!(r.exit_code(), 3);
}

#[test]
fn a_speed_not_read_back_is_no_confirmed_standstill() {
    let mut r = ended(DeviceState::ReadyToSwitchOn, 0.0, false);
    r.end.final_speed = None;
    r.end.speed_unread = true;
    settle(&mut r);
    assert_eq!(r.exit_code(), 3);
}

#[test]
fn a_failed_check_with_a_coasting_spindle_is_an_error_and_an_interrupted_run_too() {
    let failed = settled(failing(DeviceState::ReadyToSwitchOn, 900.0, true));
    assert_eq!(failed.exit_code(), 3);
    let interrupted = settled(RunReport {
        verdict: Verdict::Interrupted(StopSignal::INT),
        ..ended(DeviceState::SwitchOnDisabled, 22000.0, true)
    });
    assert_eq!(interrupted.exit_code(), 3);
    assert!(interrupted
        .verdict
        .reason()
        .unwrap_or_default()
        .starts_with("interrupted by Ctrl-C"));
}

#[test]
fn a_failed_check_without_a_verdict_yet_fails_and_a_panic_stays_a_panic() {
    let r = settled(failing(DeviceState::ReadyToSwitchOn, 0.0, false));
    assert_eq!(r.exit_code(), 1);
    let p = settled(RunReport {
        verdict: Verdict::Panicked("bug".into()),
        ..ended(DeviceState::Fault, 500.0, true)
    });
    assert_eq!(p.exit_code(), 101);
}

#[test]
fn a_passing_leave_enabled_run_passes_in_the_state_its_steps_left() {
    let r = settled(RunReport {
        kept_enabled: true,
        ..ended(DeviceState::OperationEnabled, 6000.0, false)
    });
    assert_eq!(r.exit_code(), 0);
    let not_kept = settled(ended(DeviceState::OperationEnabled, 6000.0, false));
    assert_eq!(not_kept.exit_code(), 3);
}

#[test]
fn with_several_drives_one_coasting_drive_is_an_error_said_of_that_drive() {
    let mut r = ended(DeviceState::ReadyToSwitchOn, 0.0, false);
    let end = |name: &str, speed: f64, coasting: bool| DriveEnd {
        name: name.into(),
        end: stopped(DeviceState::ReadyToSwitchOn, speed, coasting),
    };
    r.drive_ends = vec![end("left", 0.0, false), end("right", 700.0, true)];
    settle(&mut r);
    assert_eq!(r.exit_code(), 3);
    assert!(r.drive_ends[0].end.stop_confirmed && !r.drive_ends[1].end.stop_confirmed);
    assert!(r
        .verdict
        .reason()
        .unwrap_or_default()
        .contains("right: drive left in ready to switch on at 700 rpm"));
}
