//! `watch:` limits that hold for the whole run: each object read every `every`, and a
//! value beyond its limit for `hold` (against noise) ends the run at once through the safe
//! stop. Judges values the session reads; it must not stop the drive itself.

use super::condition::Condition;
use super::session::Session;
use super::stop::Stop;
use super::{CheckResult, StepOrigin};
use std::time::Duration;

/// One watched limit, as the recipe's `watch:` gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct Watch {
    /// The object and the limit it must keep (`motor_temperature below 80 °C`).
    pub condition: Condition,
    /// How long the value must stay beyond the limit before it counts (`for:`).
    pub hold: Duration,
    /// How often the object is read.
    pub every: Duration,
    pub origin: StepOrigin,
}

/// Where one watch stands: when it was read last and since when it is beyond its limit.
#[derive(Debug, Clone, Default)]
pub(super) struct WatchState {
    read_at: Option<Duration>,
    beyond_since: Option<Duration>,
}

impl Session<'_> {
    /// The limits watched from the run's first step until its steps end.
    pub fn with_watches(mut self, watches: Vec<Watch>) -> Self {
        self.watches = watches.into_iter().map(|w| (w, WatchState::default())).collect();
        self
    }

    /// A block's own watches join the run's while its steps run; returns what
    /// [`Session::end_block_watches`] takes to drop them again.
    pub fn begin_block_watches(&mut self, watches: &[Watch]) -> usize {
        let before = self.watches.len();
        self.watches
            .extend(watches.iter().map(|w| (w.clone(), WatchState::default())));
        before
    }

    /// The block's steps ended: its watches are read no more.
    pub fn end_block_watches(&mut self, before: usize) {
        self.watches.truncate(before);
    }

    /// Reads each watch that is due; a limit crossed for its whole `hold` is recorded as a
    /// failed check (the watch, the value, the time, the step) and ends the run. Never in
    /// the safe stop: nothing there may be ended early.
    pub(super) fn check_watches(&mut self) -> Result<(), Stop> {
        if self.in_safe_stop || self.watches.is_empty() {
            return Ok(());
        }
        let current = self.current;
        let result = self.check_watches_now();
        self.current = current;
        result
    }

    fn check_watches_now(&mut self) -> Result<(), Stop> {
        for i in 0..self.watches.len() {
            let now = self.clock.now();
            let (watch, state) = &self.watches[i];
            if state.read_at.is_some_and(|t| now < t.saturating_add(watch.every)) {
                continue;
            }
            let condition = watch.condition.clone();
            let (holds, seen, measured) = self.read_condition(&condition)?;
            let (watch, state) = &mut self.watches[i];
            state.read_at = Some(now);
            if holds {
                state.beyond_since = None;
                continue;
            }
            let since = *state.beyond_since.get_or_insert(now);
            if now.saturating_sub(since) < watch.hold {
                continue;
            }
            let held = match watch.hold.is_zero() {
                true => String::new(),
                false => format!(" for {}", super::show_duration(watch.hold)),
            };
            let name = format!("watch {condition}");
            let message = format!(
                "{seen} at {:.3} s of the run{held}: the watch {condition} was crossed",
                now.saturating_sub(self.run_start).as_secs_f64()
            );
            let origin = watch.origin.clone();
            // The limits and unit as `expect` keeps them, for every report and the store.
            let (object, (low, high)) = match &condition {
                Condition::Value { object, predicate } => (Some(object.clone()), predicate.reported_limits()),
                _ => (None, (None, None)),
            };
            let check = CheckResult {
                measured,
                measured_text: Some(seen),
                unit: object.as_ref().and_then(|o| o.unit.clone()),
                low,
                high,
                object: object.map(|o| o.name),
                message: message.clone(),
                origin: origin.clone(),
                ..CheckResult::named(name.clone(), false)
            };
            self.expect_result(check)?;
            let (step, _) = self.place();
            let step = match step.is_empty() {
                true => String::new(),
                false => format!(" in step {step}"),
            };
            let text = format!("watch crossed{step}: {message} ({origin}); the run ends here");
            self.observer.message(&text);
            self.report.safe_stop.push(text.clone());
            self.report.stopped_on_failure = Some(text.clone());
            return Err(Stop::StoppedOnFailure(text));
        }
        Ok(())
    }
}
