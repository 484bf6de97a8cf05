//! `results capability CHECK`: how capable the process is of one check's measurement
//! across units — n, mean, σ, Cp and Cpk against the spec limits the recipe's check had —
//! and a histogram of the values. The values are the trend's ([`Store::trend`]: one
//! measurement, never several merged). Pure arithmetic over them, and one query.

use super::stored_run::{RunFilter, TrendPoint};
use super::{Store, StoreError};
use crate::session::{Limits, Stats};

/// The capability of one check.
#[derive(Debug, Clone, PartialEq)]
pub struct Capability {
    /// The check as asked for and its key (what the values are of).
    pub check: String,
    pub key: Option<String>,
    pub unit: Option<String>,
    pub n: usize,
    pub mean: Option<f64>,
    /// The sample standard deviation (n − 1); `None` below two values.
    pub sigma: Option<f64>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// The spec limits: the newest run's check's (the recipe as it is now).
    pub limits: Limits,
    /// Cp (both limits), Cpk (the nearer limit, or the only one); `None` where they cannot
    /// be computed (below two values, σ = 0, no limit).
    pub cp: Option<f64>,
    pub cpk: Option<f64>,
    /// Different limits in older runs: (low, high) of each set other than the newest.
    pub other_limits: Vec<Limits>,
    /// The values, oldest first.
    pub values: Vec<f64>,
}

impl Capability {
    /// The capability of the values of `points` (a trend of `check`).
    pub fn of(check: &str, points: &[TrendPoint]) -> Capability {
        let values: Vec<f64> = points
            .iter()
            .filter_map(|p| p.check.measured.filter(|v| v.is_finite()))
            .collect();
        let stats = Stats::of(&values);
        let n = stats.count;
        let some = |v: f64| (n > 0).then_some(v);
        let (mean, sigma) = (some(stats.mean), stats.sample_std());
        let limits = points
            .iter()
            .rev()
            .map(|p| p.check.limits)
            .find(Limits::any)
            .unwrap_or_default();
        let mut other_limits: Vec<Limits> = Vec::new();
        for l in points.iter().map(|p| p.check.limits).filter(Limits::any) {
            if l != limits && !other_limits.contains(&l) {
                other_limits.push(l);
            }
        }
        let Limits { low, high } = limits;
        let s = sigma.filter(|s| *s > 0.0);
        let cp = match (low, high, s) {
            (Some(l), Some(h), Some(s)) => Some((h - l) / (6.0 * s)),
            _ => None,
        };
        let upper = high.zip(mean).zip(s).map(|((h, m), s)| (h - m) / (3.0 * s));
        let lower = low.zip(mean).zip(s).map(|((l, m), s)| (m - l) / (3.0 * s));
        let cpk = match (upper, lower) {
            (Some(u), Some(l)) => Some(u.min(l)),
            (u, l) => u.or(l),
        };
        Capability {
            check: check.to_string(),
            key: points.first().map(|p| p.key().to_string()),
            unit: points.iter().rev().find_map(|p| p.check.unit.clone()),
            n,
            mean,
            sigma,
            min: some(stats.min),
            max: some(stats.max),
            limits,
            cp,
            cpk,
            other_limits,
            values,
        }
    }

    /// Why Cpk is not given, when it is not.
    pub fn why_no_cpk(&self) -> Option<&'static str> {
        if self.cpk.is_some() {
            return None;
        }
        Some(match (self.n, self.sigma, self.limits.low.or(self.limits.high)) {
            (0, _, _) => "no value",
            (1, _, _) => "one value: σ needs two",
            (_, _, None) => "the check has no limit",
            _ => "σ is 0: every value is the same",
        })
    }

    /// The histogram: `bins` counts over equal intervals from `start` of width `width`,
    /// spanning the values and the limits.
    pub fn histogram(&self) -> Histogram {
        let lows = [self.min, self.limits.low].into_iter().flatten();
        let highs = [self.max, self.limits.high].into_iter().flatten();
        let start = lows.reduce(f64::min).unwrap_or(0.0);
        let end = highs.reduce(f64::max).unwrap_or(1.0);
        let bins = ((self.n as f64).sqrt().ceil() as usize).clamp(5, 40);
        let span = end - start;
        let width = if span > 0.0 { span / bins as f64 } else { 1.0 };
        let mut counts = vec![0usize; bins];
        for v in &self.values {
            let at = (((v - start) / width).floor().max(0.0) as usize).min(bins - 1);
            counts[at] += 1;
        }
        Histogram { start, width, counts }
    }
}

/// Counts of values over equal intervals.
#[derive(Debug, Clone, PartialEq)]
pub struct Histogram {
    pub start: f64,
    pub width: f64,
    pub counts: Vec<usize>,
}

impl Store {
    /// The capability of the check `check` (as [`Store::trend`] reads it) over the runs
    /// `filter` takes.
    pub fn capability(&mut self, check: &str, filter: &RunFilter) -> Result<Capability, StoreError> {
        let points = self.trend(check, filter)?;
        Ok(Capability::of(check, &points))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::{CheckRow, RunRow};

    fn point(v: f64, low: Option<f64>, high: Option<f64>) -> TrendPoint {
        TrendPoint {
            check: CheckRow {
                name: "speed_actual mean near 6000 rpm ± 1 %".into(),
                key: Some("speed_actual mean near".into()),
                run: "r".into(),
                measured: Some(v),
                unit: Some("rpm".into()),
                limits: Limits::new(low, high),
                passed: true,
                step: "2".into(),
                ..CheckRow::default()
            },
            run: RunRow {
                id: "r".into(),
                started_at: "2026-01-01T00:00:00.000Z".into(),
                recipe: "R".into(),
                ..RunRow::default()
            },
        }
    }

    #[test]
    fn cp_and_cpk_follow_their_definitions_against_the_newest_limits() {
        // mean 6000, σ 10 (values 5990, 6000, 6010), limits 5940 .. 6060 → Cp 2, Cpk 2.
        let points: Vec<TrendPoint> = [5990.0, 6000.0, 6010.0]
            .into_iter()
            .map(|v| point(v, Some(5940.0), Some(6060.0)))
            .collect();
        let c = Capability::of("x", &points);
        assert_eq!((c.n, c.mean), (3, Some(6000.0)));
        assert!((c.sigma.unwrap_or(0.0) - 10.0).abs() < 1e-9);
        assert!((c.cp.unwrap_or(0.0) - 2.0).abs() < 1e-9);
        assert!((c.cpk.unwrap_or(0.0) - 2.0).abs() < 1e-9);
        // Off-centre toward the high limit: Cpk is the nearer side's.
        let mut shifted = points.clone();
        shifted.push(point(6030.0, Some(5940.0), Some(6030.0)));
        let c = Capability::of("x", &shifted);
        assert_eq!(c.limits.high, Some(6030.0), "the newest run's limits");
        assert_eq!(c.other_limits, [Limits::new(Some(5940.0), Some(6060.0))]);
        let (m, s) = (c.mean.unwrap_or(0.0), c.sigma.unwrap_or(0.0));
        assert!((c.cpk.unwrap_or(0.0) - (6030.0 - m) / (3.0 * s)).abs() < 1e-9);
        // One-sided: no Cp, Cpk of that side.
        let below: Vec<TrendPoint> = [1.0, 2.0, 3.0]
            .into_iter()
            .map(|v| point(v, None, Some(5.0)))
            .collect();
        let c = Capability::of("x", &below);
        assert_eq!(c.cp, None);
        assert!((c.cpk.unwrap_or(0.0) - 1.0).abs() < 1e-9);
        assert_eq!(c.histogram().counts.iter().sum::<usize>(), 3);
        assert_eq!(
            Capability::of("x", &below[..1]).why_no_cpk(),
            Some("one value: σ needs two")
        );
    }
}
