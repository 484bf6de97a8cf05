//! What one sample step keeps of one object for the `expect` steps after it: the streaming
//! statistics, the slope buckets, and the step response when the step declared one. All
//! bounded in memory whatever the window's length. It must not read a drive.

use super::slope_window::SlopeWindow;
use super::step_response::StepResponse;
use super::{Statistic, Stats};

#[derive(Debug, Clone, PartialEq)]
pub struct SampleWindow {
    pub stats: Stats,
    pub slope: SlopeWindow,
    pub response: Option<StepResponse>,
}

/// A statistic's value, or why the window has none.
#[derive(Debug, Clone, PartialEq)]
pub enum Measured {
    Value(f64),
    Missing(String),
}

impl SampleWindow {
    pub fn push(&mut self, t: f64, v: f64) {
        self.stats.push(v);
        self.slope.push(t, v);
        if let Some(r) = self.response.as_mut() {
            r.push(t, v);
        }
    }

    /// `stat` over this window, in the unit the statistic is written in (seconds, %, the
    /// object's difference unit, the slope per minute).
    pub fn measure(&self, stat: Statistic) -> Measured {
        use Measured::{Missing, Value};
        if self.stats.count == 0 {
            return Missing("no samples".into());
        }
        let found = |v: Option<f64>, why: &str| v.map_or_else(|| Missing(why.to_string()), Value);
        // A measure of the step response, or why there is none.
        let of_response = |measure: fn(&StepResponse) -> Option<f64>, why: &str| match &self.response {
            Some(r) => found(measure(r), why),
            None => Missing("no step declared on the sample step".into()),
        };
        match stat {
            Statistic::Mean | Statistic::Min | Statistic::Max | Statistic::Ripple | Statistic::Std => {
                Value(self.stats.get(stat))
            }
            Statistic::RiseTime => of_response(StepResponse::rise_time, "never reached 90 % of the step"),
            Statistic::Overshoot => of_response(StepResponse::overshoot_percent, "a step of size zero"),
            Statistic::SettlingTime => of_response(
                StepResponse::settling_time,
                "still outside the band at the window's end",
            ),
            Statistic::SteadyStateError => of_response(
                StepResponse::steady_state_error,
                "no samples in the window's last tenth",
            ),
            Statistic::Slope(over) => found(
                self.slope
                    .slope_over(over.as_secs_f64())
                    .map(|s| s.per_second * 60.0),
                &format!(
                    "fewer than {} of samples, too few for a slope over it",
                    super::show_duration(over)
                ),
            ),
        }
    }
}
