//! The run's observer as a script runs: every event passed on to the run's own observers,
//! and the rows of the sample a script asked for kept for it (statistics always, values up
//! to a script's array limit). Observes only; performs nothing.

use super::exchange::Window;
use super::sandbox::MAX_ARRAY_SIZE;
use crate::session::{ObjectRef, RunObserver, Stats};
use std::cell::RefCell;
use std::rc::Rc;
use std::time::Duration;

/// Passes every event on, and keeps the rows of the sample a script asked for.
pub(super) struct Tap<'a> {
    pub inner: &'a mut dyn RunObserver,
    pub capture: Rc<RefCell<Capture>>,
}

impl Tap<'_> {
    fn relay(&mut self, mut each: impl FnMut(&mut dyn RunObserver)) {
        each(&mut *self.inner);
    }
}

impl RunObserver for Tap<'_> {
    crate::relayed_events!();
    fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
        self.capture.borrow_mut().push(values);
        self.inner.sample(at, objects, values);
    }
    fn wants_progress(&self) -> bool {
        self.inner.wants_progress()
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
