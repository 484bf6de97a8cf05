//! The run's observer as a script runs: every event passed on to the run's own observers,
//! and the rows of the sample a script asked for kept for it (statistics always, values up
//! to a script's array limit). Observes only; performs nothing.

use super::exchange::Window;
use super::sandbox::MAX_ARRAY_SIZE;
use crate::session::{
    CheckResult, ObjectRef, RunInfo, RunObserver, RunReport, Stats, StepInfo, StepRecord, UnitIdentity,
};
use std::cell::RefCell;
use std::rc::Rc;
use std::time::Duration;

/// Passes every event on, and keeps the rows of the sample a script asked for.
pub(super) struct Tap<'a> {
    pub inner: &'a mut dyn RunObserver,
    pub capture: Rc<RefCell<Capture>>,
}

impl RunObserver for Tap<'_> {
    fn run_started(&mut self, run: &RunInfo, drive: &str) {
        self.inner.run_started(run, drive);
    }
    fn unit_identified(&mut self, unit: &UnitIdentity) {
        self.inner.unit_identified(unit);
    }
    fn step_started(&mut self, step: &StepInfo) {
        self.inner.step_started(step);
    }
    fn step_placed(&mut self, id: &str) {
        self.inner.step_placed(id);
    }
    fn attempt_started(&mut self, number: &str, attempt: u32, of: u32) {
        self.inner.attempt_started(number, attempt, of);
    }
    fn attempts_given_up(&mut self) {
        self.inner.attempts_given_up();
    }
    fn step_progress(&mut self, number: &str, elapsed: Duration, total: Option<Duration>, values: &str) {
        self.inner.step_progress(number, elapsed, total, values);
    }
    fn asked(&mut self, number: &str, question: &str) {
        self.inner.asked(number, question);
    }
    fn step_finished(&mut self, record: &StepRecord) {
        self.inner.step_finished(record);
    }
    fn check(&mut self, result: &CheckResult) {
        self.inner.check(result);
    }
    fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
        self.capture.borrow_mut().push(values);
        self.inner.sample(at, objects, values);
    }
    fn wants_progress(&self) -> bool {
        self.inner.wants_progress()
    }
    fn message(&mut self, text: &str) {
        self.inner.message(text);
    }
    fn run_finished(&mut self, report: &RunReport) {
        self.inner.run_finished(report);
    }
    fn idle(&mut self) {
        self.inner.idle();
    }
}

/// The window of the sample being taken: statistics always, values up to a script's
/// array limit.
#[derive(Default)]
pub(super) struct Capture {
    windows: Vec<Window>,
    recording: bool,
}

impl Capture {
    pub fn start(&mut self, objects: &[ObjectRef]) {
        self.windows = objects
            .iter()
            .map(|o| Window {
                object: o.clone(),
                stats: Stats::default(),
                values: Some(Vec::new()),
            })
            .collect();
        self.recording = true;
    }

    pub fn push(&mut self, values: &[f64]) {
        if !self.recording {
            return;
        }
        for (w, v) in self.windows.iter_mut().zip(values) {
            w.stats.push(*v);
            if w.values.as_ref().is_some_and(|k| k.len() >= MAX_ARRAY_SIZE) {
                w.values = None;
            }
            if let Some(kept) = w.values.as_mut() {
                kept.push(*v);
            }
        }
    }

    pub fn finish(&mut self) -> Vec<Window> {
        self.recording = false;
        std::mem::take(&mut self.windows)
    }
}
