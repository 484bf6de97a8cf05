//! `wait_until` a value is stable: poll it, keep the slope of the last stretch in bounded
//! memory (a day of polls costs the same as ten minutes), and end when the slope holds, or
//! fail at the timeout. The polls are a series in the report, so the plot and the timeline
//! show the approach. It must not know recipes or scripts.

use super::session::{show_duration, value_of, Session};
use super::stop::Stop;
use super::wait_until::{wait_ended, Polling};
use super::{BucketSeries, Condition, ObjectRef, Series, SlopeWindow, Stats, StepOrigin, SERIES_BUCKETS};

impl Session<'_> {
    pub(super) fn wait_until_stable(
        &mut self,
        condition: &Condition,
        poll: Polling,
        origin: &StepOrigin,
        number: &str,
    ) -> Result<String, Stop> {
        let Condition::Stable {
            object,
            over,
            predicate,
            rate_unit,
        } = condition
        else {
            return Err(Stop::Failed(format!("{condition} is not a stabilisation")));
        };
        let Polling {
            started,
            timeout,
            every,
        } = poll;
        let origin_s = started.saturating_sub(self.run_start).as_secs_f64();
        let mut slope = SlopeWindow::with_horizon(origin_s, over.as_secs_f64(), every.as_secs_f64());
        let width = (timeout.as_secs_f64() / SERIES_BUCKETS as f64).max(every.as_secs_f64());
        let mut series = BucketSeries::new(origin_s, width);
        let mut stats = Stats::default();
        let name = self.select_object(&object.name)?.to_string();
        loop {
            let v = self.drive().read_number(&name)?;
            let now = self.clock.now();
            let t = now.saturating_sub(self.run_start).as_secs_f64();
            slope.push(t, v);
            series.push(t, v);
            stats.push(v);
            // The samples CSV holds what the report plots.
            self.observer.sample(
                now.saturating_sub(self.run_start),
                std::slice::from_ref(object),
                &[v],
            );
            let waited = now.saturating_sub(started);
            let per_minute = slope.slope_over(over.as_secs_f64()).map(|s| s.per_second * 60.0);
            let holds = per_minute.is_some_and(|m| predicate.holds(m));
            let ends = holds || waited >= timeout;
            // Text only where someone reads it: a day of 10 ms polls builds none.
            let seen = match (ends || self.observer.wants_progress(), per_minute) {
                (false, _) => String::new(),
                (true, Some(m)) => format!(
                    "{}, slope {}",
                    value_of(v, object),
                    super::with_unit((m * 1000.0).round() / 1000.0, Some(rate_unit))
                ),
                (true, None) => format!(
                    "{} (less than {} seen)",
                    value_of(v, object),
                    show_duration(*over)
                ),
            };
            if ends {
                self.keep_series(object, &series, stats);
                let message = (!holds).then(|| {
                    format!(
                        "timed out after {} waiting for {condition}; last seen: {seen}",
                        show_duration(timeout)
                    )
                });
                self.record_check(
                    origin,
                    &condition.to_string(),
                    holds,
                    per_minute,
                    Some(seen.clone()),
                    condition,
                    message.clone(),
                    started,
                );
                return wait_ended(message, &seen, waited);
            }
            self.watch_fault(false)?;
            self.between_polls(number, waited, timeout, &seen, poll.next_after(now))?;
        }
    }

    /// The polls of a wait or coast-down as a series of the report (plotted like a window).
    pub(super) fn keep_series(&mut self, object: &ObjectRef, series: &BucketSeries, stats: Stats) {
        self.report.series.push(Series {
            object: object.name.clone(),
            unit: object.unit.clone(),
            step: self.path.id(),
            points: series.points(),
            samples: Some(stats),
            marks: None,
        });
    }
}
