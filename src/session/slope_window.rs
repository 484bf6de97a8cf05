//! The slope of a sampled value over the last stretch of a window (how fast a temperature
//! still rises), streaming in bounded memory however long the run: time is cut into at
//! most [`SLOPE_BUCKETS`] buckets, each keeping the sums a least-squares line needs, so the
//! line through every sample of the buckets inside the stretch is exact; the stretch is
//! rounded to whole buckets (a day sampled for a 10 min slope uses buckets of at most
//! 24 h / 1000 = 86 s). With a horizon, buckets older than it are dropped instead of
//! widened (a `wait_until` that watches for days). Pure arithmetic.

use std::collections::VecDeque;

/// Most buckets one window keeps.
pub const SLOPE_BUCKETS: usize = 1000;

#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Sums {
    n: f64,
    t: f64,
    v: f64,
    tt: f64,
    tv: f64,
}

impl Sums {
    fn add(&mut self, other: &Sums) {
        self.n += other.n;
        self.t += other.t;
        self.v += other.v;
        self.tt += other.tt;
        self.tv += other.tv;
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct SlopeWindow {
    start: f64,
    width: f64,
    /// Kept buckets by index from `start`, oldest first.
    buckets: VecDeque<(u64, Sums)>,
    /// Seconds of history to keep; `None`: the whole window, widening buckets as needed.
    horizon: Option<f64>,
    last: f64,
}

/// A least-squares line through the samples of a stretch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slope {
    /// Change per second, in the value's unit.
    pub per_second: f64,
    /// The seconds the samples used span (first to last).
    pub span: f64,
    pub samples: u64,
}

impl SlopeWindow {
    /// A window from `start` (seconds) expected to last `duration`: buckets of
    /// `duration / SLOPE_BUCKETS`, at least `every` wide.
    pub fn new(start: f64, duration: f64, every: f64) -> SlopeWindow {
        Self::with_width(start, (duration / SLOPE_BUCKETS as f64).max(every), None)
    }

    /// A window that only ever needs the last `horizon` seconds.
    pub fn with_horizon(start: f64, horizon: f64, every: f64) -> SlopeWindow {
        Self::with_width(start, (horizon / 100.0).max(every), Some(horizon))
    }

    fn with_width(start: f64, width: f64, horizon: Option<f64>) -> SlopeWindow {
        SlopeWindow {
            start,
            width: super::bucket_series::bucket_width(width),
            buckets: VecDeque::new(),
            horizon,
            last: start,
        }
    }

    pub fn push(&mut self, t: f64, v: f64) {
        self.last = self.last.max(t);
        // Never negative nor NaN: the cast's truncation is the floor, without a call.
        let index = ((t - self.start).max(0.0) / self.width) as u64;
        // Times relative to the window's start keep the sums' precision over days.
        let x = t - self.start;
        let sample = Sums {
            n: 1.0,
            t: x,
            v,
            tt: x * x,
            tv: x * v,
        };
        match self.buckets.back_mut() {
            Some((i, sums)) if *i == index => sums.add(&sample),
            _ => self.buckets.push_back((index, sample)),
        }
        match self.horizon {
            Some(h) => {
                let oldest = ((self.last - self.start - h) / self.width).floor() - 1.0;
                while self.buckets.front().is_some_and(|(i, _)| (*i as f64) < oldest) {
                    self.buckets.pop_front();
                }
            }
            None => {
                while self.buckets.len() > SLOPE_BUCKETS {
                    self.widen();
                }
            }
        }
    }

    fn widen(&mut self) {
        self.width *= 2.0;
        let mut merged: VecDeque<(u64, Sums)> = VecDeque::with_capacity(self.buckets.len() / 2 + 1);
        for (i, sums) in self.buckets.drain(..) {
            let j = i / 2;
            match merged.back_mut() {
                Some((k, s)) if *k == j => s.add(&sums),
                _ => merged.push_back((j, sums)),
            }
        }
        self.buckets = merged;
    }

    /// The line through the samples of the buckets that lie within the last `over`
    /// seconds; `None` with fewer than two samples there, or when the window is shorter
    /// than `over` (a slope over 10 min needs 10 min of samples).
    pub fn slope_over(&self, over: f64) -> Option<Slope> {
        if self.last - self.start < over * (1.0 - 1e-9) - self.width {
            return None;
        }
        let from = self.last - self.start - over;
        let mut s = Sums::default();
        let mut first = f64::INFINITY;
        for (i, sums) in &self.buckets {
            let bucket_start = *i as f64 * self.width;
            if bucket_start >= from - 1e-9 * over.abs().max(1.0) {
                s.add(sums);
                first = first.min(bucket_start);
            }
        }
        let denominator = s.n * s.tt - s.t * s.t;
        if s.n < 2.0 || denominator <= 0.0 {
            return None;
        }
        Some(Slope {
            per_second: (s.n * s.tv - s.t * s.v) / denominator,
            span: self.last - self.start - first,
            samples: s.n as u64,
        })
    }

    /// Buckets kept now (for the memory bound's tests).
    pub fn kept(&self) -> usize {
        self.buckets.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_has_its_own_slope_over_any_stretch() {
        let mut w = SlopeWindow::new(0.0, 3600.0, 1.0);
        for k in 0..=3600 {
            let t = f64::from(k);
            w.push(t, 20.0 + 0.01 * t);
        }
        let s = w.slope_over(600.0).unwrap();
        assert!((s.per_second - 0.01).abs() < 1e-9, "{s:?}");
        assert!((s.span - 600.0).abs() <= 3.6 + 1e-9, "{s:?}");
        assert!(w.slope_over(7200.0).is_none(), "longer than the window");
    }

    #[test]
    fn the_slope_of_a_settling_exponential_is_its_derivative_over_the_stretch() {
        // T = 60 - 35 e^(-t/τ): over [t1, t2] the least-squares slope of a sampled
        // exponential is close to the mean derivative (T(t2) - T(t1)) / (t2 - t1).
        let tau = 1200.0;
        let temp = |t: f64| 60.0 - 35.0 * (-t / tau).exp();
        let mut w = SlopeWindow::new(0.0, 7200.0, 10.0);
        for k in 0..=720 {
            let t = f64::from(k) * 10.0;
            w.push(t, temp(t));
        }
        let s = w.slope_over(600.0).unwrap();
        let mean = (temp(7200.0) - temp(6600.0)) / 600.0;
        assert!(
            (s.per_second - mean).abs() / mean < 0.02,
            "{} vs {mean}",
            s.per_second
        );
    }

    #[test]
    fn days_of_samples_stay_within_the_bucket_bound() {
        let mut w = SlopeWindow::new(0.0, 60.0, 0.1);
        for k in 0..864_000u32 {
            w.push(f64::from(k) * 0.1, 1.0);
        }
        assert!(w.kept() <= SLOPE_BUCKETS, "{}", w.kept());
        assert_eq!(w.slope_over(600.0).map(|s| s.per_second), Some(0.0));
        let mut h = SlopeWindow::with_horizon(0.0, 600.0, 1.0);
        for k in 0..86_400u32 {
            h.push(f64::from(k), f64::from(k) * 0.5);
        }
        assert!(h.kept() <= 102, "{}", h.kept());
        assert!((h.slope_over(600.0).unwrap().per_second - 0.5).abs() < 1e-9);
    }
}
