//! `watch:` limits that hold for the whole run: each object read every `every`, and a
//! value beyond its limit for `hold` (against noise) ends the run at once through the safe
//! stop. Judges values the session reads; it must not stop the drive itself.

use super::condition::Condition;
use super::session::Session;
use super::stop::Stop;
use super::Limits;
use super::{CheckResult, StepOrigin};
use std::time::Duration;

/// How often a watch reads its object when the recipe or script names no `every`.
pub const DEFAULT_WATCH_EVERY: Duration = Duration::from_secs(1);
/// The shortest interval: a watch must leave the line to the steps.
pub const MIN_WATCH_EVERY: Duration = Duration::from_millis(50);
/// The most limits a script may watch at once: each is read on the line.
pub const MAX_WATCHES: usize = 64;

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

/// The values a sample step read at its last tick, each with its drive and its name in
/// that drive's dictionary: a watch of one of them takes the value instead of sending a
/// telegram of its own. Empty outside a sample step.
#[derive(Debug, Clone, Default)]
pub(super) struct SampledValues {
    /// Drive index, object name, the value last read.
    pub(super) values: Vec<(usize, String, f64)>,
    /// When they were read.
    pub(super) at: Duration,
}

impl Session<'_> {
    /// The limits watched from the run's first step until its steps end.
    pub fn with_watches(mut self, watches: Vec<Watch>) -> Self {
        self.watches = watches.into_iter().map(|w| (w, WatchState::default())).collect();
        self
    }

    /// A script's `d.watch(...)`: held from now until the run's steps end. The same limit
    /// given again (a `d.watch` in a loop) is the one already held; a script that keeps
    /// adding others is stopped at [`MAX_WATCHES`], as each one costs reads on the line.
    pub fn watch_from_here(&mut self, watch: Watch) -> Result<(), Stop> {
        let same =
            |w: &Watch| w.condition == watch.condition && w.hold == watch.hold && w.every == watch.every;
        if self.watches.iter().any(|(w, _)| same(w)) {
            return Ok(());
        }
        if self.watches.len() >= MAX_WATCHES {
            return Err(Stop::Error(format!(
                "watch {} ({}): the run already holds {MAX_WATCHES} watches, the most it reads; watch fewer limits (a d.watch in a loop holds one limit once)",
                watch.condition, watch.origin
            )));
        }
        self.watches.push((watch, WatchState::default()));
        Ok(())
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

    /// The watched value from the running sample step's last tick when that step reads
    /// the object and read it less than `every` ago: the watch shares the sample's
    /// exchange instead of sending one of its own. `None`: the watch reads itself.
    fn sampled_reading(
        &mut self,
        condition: &Condition,
        now: Duration,
        every: Duration,
    ) -> Result<Option<(bool, String, Option<f64>)>, Stop> {
        let Condition::Value { object, predicate } = condition else {
            return Ok(None);
        };
        let fresh = now.saturating_sub(self.sampled.at) < every;
        if self.sampled.values.is_empty() || !fresh || matches!(predicate, super::Predicate::EqualsText(_)) {
            return Ok(None);
        }
        let name = self.select_object(&object.name)?;
        let drive = self.current;
        let found = self
            .sampled
            .values
            .iter()
            .find(|(d, n, _)| *d == drive && n == name);
        Ok(found.map(|(_, _, v)| {
            (
                predicate.holds(*v),
                super::session::value_of(*v, object),
                Some(*v),
            )
        }))
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
            let every = watch.every;
            let (holds, seen, measured) = match self.sampled_reading(&condition, now, every)? {
                Some(reading) => reading,
                None => self.read_condition(&condition)?,
            };
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
                limits: Limits::new(low, high),
                object: object.map(|o| o.name),
                message: message.clone(),
                origin: origin.clone(),
                ..CheckResult::named(name.clone(), false)
            };
            self.expect_result(check)?;
            let (step, _) = self.place();
            // Between steps the watch names the step it follows.
            let after = self.report.steps.last().map(|r| r.number.clone());
            let step = match (step.is_empty(), after) {
                (false, _) => format!(" in step {step}"),
                (true, Some(number)) => format!(" after step {number}"),
                (true, None) => " before the first step".to_string(),
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
