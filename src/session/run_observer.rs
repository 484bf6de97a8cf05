//! Hooks through which a running recipe or script reports as it goes (console lines, live progress,
//! streamed CSV). Observers must not fail the run: their own I/O problems are theirs.

use super::{CheckResult, ObjectRef, RunInfo, RunReport, StepInfo, StepRecord, UnitIdentity};
use std::time::Duration;

pub trait RunObserver {
    fn run_started(&mut self, _run: &RunInfo, _drive: &str) {}
    /// The unit's identity became known or changed after the start (an operator answered
    /// for it): the whole identity as it now stands.
    fn unit_identified(&mut self, _unit: &UnitIdentity) {}
    /// A step begins.
    fn step_started(&mut self, _step: &StepInfo) {}
    /// Right after `step_started`: the step's id with the iteration of every repeat around
    /// it (`4[2].1`), for reports that must tell iterations apart.
    fn step_placed(&mut self, _id: &str) {}
    /// The step `number` (an `attempts` block) begins its attempt `attempt` of `of`; it
    /// lasts until that step finishes.
    fn attempt_started(&mut self, _number: &str, _attempt: u32, _of: u32) {}
    /// The run is ending in a way no `attempts` block tries again (an error, a drive fault,
    /// a stop request, a question nobody answered): what fails from here on is final,
    /// whatever attempts are under way.
    fn attempts_given_up(&mut self) {}
    /// Progress of a long step: elapsed, total (when known) and live values.
    fn step_progress(&mut self, _number: &str, _elapsed: Duration, _total: Option<Duration>, _values: &str) {}
    /// The step `number` asks the operator `question` (with what to type) and waits for
    /// the answer at the terminal.
    fn asked(&mut self, _number: &str, _question: &str) {}
    fn step_finished(&mut self, _record: &StepRecord) {}
    fn check(&mut self, _result: &CheckResult) {}
    /// One row of a `sample` step: the time since the run's start, and one value per object.
    fn sample(&mut self, _at: Duration, _objects: &[ObjectRef], _values: &[f64]) {}
    /// Whether this observer shows live progress (a screen): text for it is built only then.
    fn wants_progress(&self) -> bool {
        false
    }
    /// A value read by `read`/`print`, or a message.
    fn message(&mut self, _text: &str) {}
    fn run_finished(&mut self, _report: &RunReport) {}
    /// The run was refused before anything was sent (an invalid file or command line,
    /// exit code 2) or could not reach its drive (3): it never started; `why` says so.
    fn run_refused(&mut self, _run: &RunInfo, _exit_code: i32, _why: &str) {}
    /// The run is about to wait (a dwell, a poll or sample interval): output held back to
    /// save system calls should go out now, so a log never lags behind a quiet drive.
    fn idle(&mut self) {}
}

/// The events an observer that only passes them on hands over alike, written once: each
/// goes to `self.relay(|o| …)`, the type's own way of reaching the observers behind it.
/// Written inside its `impl RunObserver`; what it treats otherwise (the sample rows, the
/// wait, whether it shows progress, a refused run) it writes beside it.
#[macro_export]
macro_rules! relayed_events {
    () => {
        $crate::relayed_events! {
            fn run_started(run: &$crate::session::RunInfo, drive: &str);
            fn unit_identified(unit: &$crate::session::UnitIdentity);
            fn step_started(step: &$crate::session::StepInfo);
            fn step_placed(id: &str);
            fn attempt_started(number: &str, attempt: u32, of: u32);
            fn attempts_given_up();
            fn step_progress(
                number: &str,
                elapsed: std::time::Duration,
                total: Option<std::time::Duration>,
                values: &str,
            );
            fn asked(number: &str, question: &str);
            fn step_finished(record: &$crate::session::StepRecord);
            fn check(result: &$crate::session::CheckResult);
            fn message(text: &str);
            fn run_finished(report: &$crate::session::RunReport);
        }
    };
    // Each event, handed to `self.relay` with its arguments.
    ($(fn $event:ident($($arg:ident: $type:ty),* $(,)?);)*) => {
        $(
            fn $event(&mut self, $($arg: $type),*) {
                self.relay(|o| o.$event($($arg),*));
            }
        )*
    };
}

/// Passes every event to each observer in turn.
#[derive(Default)]
pub struct Observers<'a> {
    list: Vec<&'a mut dyn RunObserver>,
}

impl<'a> Observers<'a> {
    pub fn push(&mut self, o: &'a mut dyn RunObserver) {
        self.list.push(o);
    }

    fn relay(&mut self, mut each: impl FnMut(&mut dyn RunObserver)) {
        self.list.iter_mut().for_each(|o| each(&mut **o));
    }
}

impl RunObserver for Observers<'_> {
    crate::relayed_events!();
    fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
        self.relay(|o| o.sample(at, objects, values));
    }
    fn wants_progress(&self) -> bool {
        self.list.iter().any(|o| o.wants_progress())
    }
    fn run_refused(&mut self, run: &RunInfo, exit_code: i32, why: &str) {
        self.relay(|o| o.run_refused(run, exit_code, why));
    }
    fn idle(&mut self) {
        self.relay(|o| o.idle());
    }
}
