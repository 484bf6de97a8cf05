//! The one verdict rule of a run, applied once before any report reads the verdict:
//! PASSED (exit 0) only when every check passed and the safe stop confirmed every drive
//! below the standstill threshold and in a state the stop aims for (or, for a
//! `leave_enabled` run that passed, in the state its steps left). A drive left coasting, in
//! fault, powered, with its state or speed unknown, or one that did not obey is an ERROR
//! (exit 3) whatever the checks said. The console, JUnit, HTML, the certificate and the
//! results store read the settled verdict; none of them may judge the end again.

use crate::drive::DeviceState;
use crate::session::{EndState, RunReport, Verdict};

/// Settles `report`'s verdict from the way its steps ended, its checks and each drive's
/// end: a drive whose end falls short is marked not confirmed (every report then says
/// CHECK THE DRIVE BY HAND), and a run that would otherwise pass, fail a check or end on a
/// stop signal becomes an error that says why. A panic stays a panic (exit 101).
pub fn settle(report: &mut RunReport) {
    if report.verdict == Verdict::Passed && report.checks_failed() > 0 {
        report.verdict = Verdict::Failed;
    }
    let kept = report.kept_enabled;
    let mut problems = Vec::new();
    if report.drive_ends.is_empty() {
        if let Some(why) = short_of(&report.end, kept) {
            problems.push(format!("{why}: {}", report.drive_left()));
            report.end.stop_confirmed = false;
        }
    } else {
        let mut lines = report.drive_left_lines().into_iter();
        for e in report.drive_ends.iter_mut() {
            let line = lines.next().unwrap_or_default();
            if let Some(why) = short_of(&e.end, kept) {
                e.end.stop_confirmed = false;
                problems.push(format!("{why}: {line}"));
            }
        }
        report.end.stop_confirmed = report.drive_ends.iter().all(|e| e.end.stop_confirmed);
    }
    if report.disobeyed {
        problems.push("the drive did not obey the stop commands; the stop was escalated".to_string());
    }
    if problems.is_empty() {
        return;
    }
    let why = problems.join("; ");
    report.verdict = match &report.verdict {
        Verdict::Passed | Verdict::Failed => Verdict::Error(why),
        Verdict::Interrupted(signal) => {
            Verdict::Error(format!("interrupted by {}; {why}", signal.describe()))
        }
        // A fault, a lost link or another error already says why the run ended (exit 3);
        // a panic is a bug (exit 101). The end line and CHECK THE DRIVE BY HAND say the rest.
        Verdict::Error(_) | Verdict::Panicked(_) => return,
    };
}

/// Why one drive's end falls short of a confirmed safe stop; `None` when it does not.
fn short_of(end: &EndState, kept: bool) -> Option<&'static str> {
    if !end.stop_confirmed {
        return Some("the safe stop could not be confirmed; CHECK THE DRIVE BY HAND");
    }
    if end.coasting {
        return Some("the spindle was left coasting above standstill");
    }
    if end.speed_unread {
        return Some("the speed could not be read back, so standstill is not confirmed");
    }
    match end.final_state {
        Some(DeviceState::Fault | DeviceState::FaultReactionActive) => Some("the drive was left in fault"),
        // Left enabled on purpose: the state its steps left, whatever it turns at.
        Some(_) if kept => None,
        Some(DeviceState::SwitchOnDisabled | DeviceState::ReadyToSwitchOn | DeviceState::SwitchedOn) => None,
        Some(_) => Some("the drive was not left in a state the stop aims for"),
        None if end.no_device_control => None,
        None => Some("the drive's state could not be read back"),
    }
}

#[cfg(test)]
#[path = "verdict_rule_tests.rs"]
mod tests;
