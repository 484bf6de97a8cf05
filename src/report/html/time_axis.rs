//! The time axis of a plot: its range, title and labelled ticks. A run's plots count
//! seconds, minutes or hours from its start. A trend over runs reads as people read time:
//! dates (UTC) with ticks at round calendar points (hours, days, Mondays, the 1st and the
//! 15th, months, quarters, years) when its runs span a day or more, else the time since
//! its first run in the unit that suits the span. Pure arithmetic and text.

use super::plot_axes::{round_to, ticks};
use crate::calendar::{civil_from_days, days_from_civil};
use crate::session::number;

const HOUR: f64 = 3600.0;
const DAY: f64 = 86_400.0;
/// Most ticks a date axis labels: a date takes about 65 px of a plot some 650 px wide.
const MAX_DATE_TICKS: usize = 8;

/// A plot's time axis: x values from `range.0` to `range.1`, in seconds (since a run's
/// start, or since 1970 UTC for [`TimeAxis::calendar`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TimeAxis {
    pub range: (f64, f64),
    /// `time [min]`, `date (UTC)`.
    pub title: String,
    /// (x value, label) in order, each inside the range.
    pub ticks: Vec<(f64, String)>,
}

impl TimeAxis {
    /// Seconds since a run's start from `t0` to `t1`, labelled in s, min or h as suits
    /// the span.
    pub fn elapsed(t0: f64, t1: f64) -> TimeAxis {
        let (unit, div) = time_unit(t1 - t0);
        TimeAxis {
            range: (t0, t1),
            title: format!("time [{unit}]"),
            ticks: elapsed_ticks(t0, t1, 0.0, div),
        }
    }

    /// Runs started from `first` to `last` (seconds since 1970 UTC), with a margin on
    /// each side so that no run sits on the plot's edge: dates when they span a day or
    /// more, else the time since the first run (named in the title) in s, min or h.
    pub fn calendar(first: f64, last: f64) -> TimeAxis {
        let span = last - first;
        let pad = if span > 0.0 { span * 0.03 } else { 60.0 };
        let (t0, t1) = (first - pad, last + pad);
        if span >= DAY {
            return TimeAxis {
                range: (t0, t1),
                title: "date (UTC)".into(),
                ticks: date_ticks(t0, t1),
            };
        }
        let (unit, div) = time_unit(span);
        TimeAxis {
            range: (t0, t1),
            title: format!("time since {} UTC [{unit}]", utc_text(first)),
            ticks: elapsed_ticks(t0, t1, first, div)
                .into_iter()
                .filter(|(t, _)| *t >= first)
                .collect(),
        }
    }
}

/// Seconds for short series, minutes up to 3 h, hours beyond: (its symbol, seconds in it).
pub fn time_unit(span_s: f64) -> (&'static str, f64) {
    if span_s > 3.0 * HOUR {
        ("h", HOUR)
    } else if span_s > 600.0 {
        ("min", 60.0)
    } else {
        ("s", 1.0)
    }
}

/// Round values of the time since `origin` (in units of `div` seconds) from `t0` to `t1`.
fn elapsed_ticks(t0: f64, t1: f64, origin: f64, div: f64) -> Vec<(f64, String)> {
    ticks((t0 - origin) / div, (t1 - origin) / div)
        .into_iter()
        .map(|k| (origin + k * div, number(round_to(k, 9))))
        .collect()
}

/// How far apart the ticks of a date axis are: each a round point of the calendar.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Step {
    /// Every n hours from midnight.
    Hours(i64),
    /// Every n days from 1970-01-01.
    Days(i64),
    Mondays,
    /// The 1st and the 15th of every month.
    HalfMonths,
    /// The 1st of every n-th month from January.
    Months(i64),
    /// January 1st of every year divisible by n.
    Years(i64),
}

#[rustfmt::skip]
const STEPS: [Step; 20] = [
    Step::Hours(1), Step::Hours(2), Step::Hours(3), Step::Hours(6), Step::Hours(12),
    Step::Days(1), Step::Days(2), Step::Mondays, Step::HalfMonths,
    Step::Months(1), Step::Months(2), Step::Months(3), Step::Months(6),
    Step::Years(1), Step::Years(2), Step::Years(5), Step::Years(10), Step::Years(20), Step::Years(50),
    Step::Years(100),
];

/// The ticks of the finest calendar step that puts at most [`MAX_DATE_TICKS`] between
/// `t0` and `t1` (seconds since 1970 UTC), each labelled as precisely as its step needs.
fn date_ticks(t0: f64, t1: f64) -> Vec<(f64, String)> {
    let (step, at) = STEPS
        .iter()
        .find_map(|s| step_ticks(*s, t0, t1, MAX_DATE_TICKS).map(|at| (*s, at)))
        .unwrap_or_else(|| {
            let last = STEPS[STEPS.len() - 1];
            (last, step_ticks(last, t0, t1, usize::MAX).unwrap_or_default())
        });
    at.into_iter().map(|t| (t, date_label(step, t))).collect()
}

/// The instants of `step` from `t0` to `t1`; `None` when there are more than `most`.
fn step_ticks(step: Step, t0: f64, t1: f64, most: usize) -> Option<Vec<f64>> {
    // Beyond a 100-year step's reach the last step takes what it finds: bounded anyway.
    let most = most.min(1000);
    let mut out = Vec::new();
    let first_day = (t0 / DAY).floor() as i64;
    let (y, m, _) = civil_from_days(first_day);
    let mut k: i64 = 0;
    loop {
        let at = match step {
            Step::Hours(n) => ((t0 / (n as f64 * HOUR)).ceil() as i64 + k) as f64 * n as f64 * HOUR,
            Step::Days(n) => ((t0 / (n as f64 * DAY)).ceil() as i64 + k) as f64 * n as f64 * DAY,
            // 1970-01-05 (day 4) was a Monday.
            Step::Mondays => {
                let monday = first_day + (4 - first_day).rem_euclid(7);
                (monday + 7 * k) as f64 * DAY
            }
            Step::HalfMonths => {
                let month = y * 12 + i64::from(m) - 1 + k / 2;
                let day = if k % 2 == 0 { 1 } else { 15 };
                days_from_civil(month.div_euclid(12), month.rem_euclid(12) as u32 + 1, day) as f64 * DAY
            }
            Step::Months(n) => {
                let month = (y * 12 + i64::from(m) - 1).div_euclid(n) * n + n * k;
                days_from_civil(month.div_euclid(12), month.rem_euclid(12) as u32 + 1, 1) as f64 * DAY
            }
            Step::Years(n) => days_from_civil(y.div_euclid(n) * n + n * k, 1, 1) as f64 * DAY,
        };
        k += 1;
        if at < t0 {
            continue;
        }
        if at > t1 {
            return Some(out);
        }
        if out.len() == most {
            return None;
        }
        out.push(at);
    }
}

/// `11-25 06:00` for hours, `2026-11-25` for days, `2026-11` for months, `2026` for years.
fn date_label(step: Step, t: f64) -> String {
    let (y, m, d, hh, mm, _) = utc_parts(t);
    match step {
        Step::Hours(_) => format!("{m:02}-{d:02} {hh:02}:{mm:02}"),
        Step::Days(_) | Step::Mondays | Step::HalfMonths => format!("{y:04}-{m:02}-{d:02}"),
        Step::Months(_) => format!("{y:04}-{m:02}"),
        Step::Years(_) => format!("{y:04}"),
    }
}

/// `2026-11-25 05:02:55`: seconds since 1970 as a UTC time, to the second.
pub fn utc_text(t: f64) -> String {
    let (y, m, d, hh, mm, ss) = utc_parts(t);
    format!("{y:04}-{m:02}-{d:02} {hh:02}:{mm:02}:{ss:02}")
}

fn utc_parts(t: f64) -> (i64, u32, u32, i64, i64, i64) {
    let secs = t.floor() as i64;
    let (days, rest) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let (y, m, d) = civil_from_days(days);
    (y, m, d, rest / 3600, rest % 3600 / 60, rest % 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2026-11-25T05:02:55Z.
    const T: f64 = 1_795_582_975.0;

    /// The axis's tick labels, one after the other.
    fn labels(axis: &TimeAxis) -> String {
        let labels: Vec<&str> = axis.ticks.iter().map(|t| t.1.as_str()).collect();
        labels.join(", ")
    }

    fn day(y: i64, m: u32, d: u32) -> f64 {
        days_from_civil(y, m, d) as f64 * DAY
    }

    #[test]
    fn a_span_under_a_day_counts_from_the_first_run_in_a_unit_that_suits_it() {
        assert_eq!(utc_text(T), "2026-11-25 05:02:55");
        for (span, unit) in [
            (0.0, "s"),
            (40.0, "s"),
            (600.0, "s"),
            (25.0 * 60.0, "min"),
            (3.0 * HOUR, "min"),
            (5.0 * HOUR, "h"),
            (DAY - 1.0, "h"),
        ] {
            let axis = TimeAxis::calendar(T, T + span);
            assert_eq!(
                axis.title,
                format!("time since 2026-11-25 05:02:55 UTC [{unit}]"),
                "{span} s"
            );
            assert!(axis.range.0 < T && axis.range.1 > T + span, "{span} s: {axis:?}");
            assert!(axis.ticks.len() >= 2, "{span} s: {axis:?}");
            assert_eq!(
                axis.ticks[0],
                (T, "0".to_string()),
                "{span} s: from the first run"
            );
            assert!(axis.ticks.iter().all(|t| t.0 >= T && t.0 <= axis.range.1));
        }
        let minutes = TimeAxis::calendar(T, T + 25.0 * 60.0);
        assert_eq!(labels(&minutes), "0, 5, 10, 15, 20, 25");
        assert_eq!(minutes.ticks[2].0, T + 600.0);
        let hours = TimeAxis::calendar(T, T + 20.0 * HOUR);
        assert_eq!(labels(&hours), "0, 5, 10, 15, 20");
    }

    #[test]
    fn a_run_counts_from_its_start() {
        let axis = TimeAxis::elapsed(0.0, 7200.0);
        assert_eq!(axis.title, "time [min]");
        assert_eq!(axis.ticks[1], (1200.0, "20".to_string()));
        assert_eq!(TimeAxis::elapsed(0.0, 30.0).title, "time [s]");
    }

    #[test]
    fn a_day_or_more_reads_as_dates_at_round_calendar_points() {
        let axis = |days: f64| TimeAxis::calendar(T, T + days * DAY);
        #[rustfmt::skip]
        let spans = [
            // A day and a half: every 6 hours from midnight.
            (1.5, "11-25 06:00, 11-25 12:00, 11-25 18:00, 11-26 00:00, 11-26 06:00, 11-26 12:00, 11-26 18:00"),
            // Five days: each midnight.
            (5.0, "2026-11-26, 2026-11-27, 2026-11-28, 2026-11-29, 2026-11-30"),
            // Five weeks: Mondays.
            (35.0, "2026-11-30, 2026-12-07, 2026-12-14, 2026-12-21, 2026-12-28"),
            // Three months: the 1st and the 15th.
            (92.0, "2026-12-01, 2026-12-15, 2027-01-01, 2027-01-15, 2027-02-01, 2027-02-15"),
            // Seven months: the 1st of each month.
            (210.0, "2026-12, 2027-01, 2027-02, 2027-03, 2027-04, 2027-05, 2027-06"),
            // Two years: quarters.
            (730.0, "2027-01, 2027-04, 2027-07, 2027-10, 2028-01, 2028-04, 2028-07, 2028-10"),
            // Twelve years: every other year; sixty: every ten.
            (12.0 * 365.25, "2028, 2030, 2032, 2034, 2036, 2038"),
            (60.0 * 365.25, "2030, 2040, 2050, 2060, 2070, 2080"),
        ];
        for (days, shown) in spans {
            assert_eq!(labels(&axis(days)), shown, "{days} days");
        }
        assert_eq!(axis(1.5).title, "date (UTC)");
        // Each tick stands at the moment its label names.
        assert_eq!(axis(1.5).ticks[3].0, day(2026, 11, 26));
        assert_eq!(axis(92.0).ticks[2].0, day(2027, 1, 1));
        assert_eq!(axis(210.0).ticks[1].0, day(2027, 1, 1));
        assert_eq!(axis(12.0 * 365.25).ticks[0].0, day(2028, 1, 1));
    }

    #[test]
    fn every_span_has_a_few_ticks_inside_it() {
        let mut span = 1.0;
        while span < 500.0 * 365.25 * DAY {
            let axis = TimeAxis::calendar(T, T + span);
            let n = axis.ticks.len();
            assert!((2..=MAX_DATE_TICKS.max(11)).contains(&n), "{span} s: {axis:?}");
            assert!(axis.ticks.windows(2).all(|w| w[0].0 < w[1].0), "{axis:?}");
            assert!(
                axis.ticks
                    .iter()
                    .all(|t| t.0 >= axis.range.0 && t.0 <= axis.range.1),
                "{axis:?}"
            );
            span *= 1.37;
        }
    }
}
