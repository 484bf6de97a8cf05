//! A sampled series for plots in bounded memory: time is cut into a fixed number of
//! buckets, each keeping its lowest and its highest point, so peaks survive however long the
//! run. When the samples outrun the buckets, the buckets double in width and pairs merge.
//! Pure data and arithmetic.

/// Most buckets one series keeps; a plot gets at most twice as many points.
pub const SERIES_BUCKETS: usize = 1000;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Bucket {
    low: (f64, f64),
    high: (f64, f64),
}

impl Bucket {
    fn of(t: f64, v: f64) -> Bucket {
        Bucket {
            low: (t, v),
            high: (t, v),
        }
    }

    fn take(&mut self, t: f64, v: f64) {
        if v < self.low.1 {
            self.low = (t, v);
        }
        if v > self.high.1 {
            self.high = (t, v);
        }
    }

    fn merge(mut self, other: Bucket) -> Bucket {
        self.take(other.low.0, other.low.1);
        self.take(other.high.0, other.high.1);
        self
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct BucketSeries {
    start: f64,
    /// Seconds per bucket; grows by doubling.
    width: f64,
    buckets: Vec<Option<Bucket>>,
    count: u64,
}

impl BucketSeries {
    /// A series whose first bucket starts at `start` (seconds) and spans `width`; a width of
    /// the expected duration divided by [`SERIES_BUCKETS`] keeps every sample apart when
    /// the run is as long as planned.
    pub fn new(start: f64, width: f64) -> BucketSeries {
        BucketSeries {
            start,
            width: bucket_width(width),
            buckets: Vec::new(),
            count: 0,
        }
    }

    /// Takes one sample at time `t` (seconds, not before `start`).
    pub fn push(&mut self, t: f64, v: f64) {
        self.count += 1;
        let mut i = self.index(t);
        while i >= SERIES_BUCKETS {
            self.widen();
            i = self.index(t);
        }
        if self.buckets.len() <= i {
            self.buckets.resize(i + 1, None);
        }
        match &mut self.buckets[i] {
            Some(b) => b.take(t, v),
            slot => *slot = Some(Bucket::of(t, v)),
        }
    }

    fn index(&self, t: f64) -> usize {
        // Never negative nor NaN, so the cast's truncation is the floor (without a call
        // to `floor` per sample where the CPU has no rounding instruction).
        let i = (t - self.start).max(0.0) / self.width;
        if i < usize::MAX as f64 {
            i as usize
        } else {
            usize::MAX
        }
    }

    fn widen(&mut self) {
        self.width *= 2.0;
        let merged = self
            .buckets
            .chunks(2)
            .map(|pair| match pair {
                [Some(a), Some(b)] => Some(a.merge(*b)),
                [Some(a), None] | [None, Some(a)] | [Some(a)] => Some(*a),
                _ => None,
            })
            .collect();
        self.buckets = merged;
    }

    /// Samples taken.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The points to plot, in time order: each bucket's low and high (once if the same).
    pub fn points(&self) -> Vec<(f64, f64)> {
        let mut out = Vec::with_capacity(self.buckets.len() * 2);
        for b in self.buckets.iter().flatten() {
            let (first, second) = if b.low.0 <= b.high.0 {
                (b.low, b.high)
            } else {
                (b.high, b.low)
            };
            out.push(first);
            if second != first {
                out.push(second);
            }
        }
        out
    }
}

/// A bucket width time can be divided by: a width that is not a positive number (a
/// window of no duration) becomes a millisecond.
pub(super) fn bucket_width(width: f64) -> f64 {
    if width > 0.0 && width.is_finite() {
        width
    } else {
        1e-3
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_million_samples_keep_at_most_twice_the_bucket_count_and_every_peak() {
        let mut s = BucketSeries::new(0.0, 0.01);
        for i in 0..1_000_000u32 {
            let t = f64::from(i) * 0.01;
            let v = if i == 777_777 {
                9999.0
            } else if i == 123_456 {
                -5.0
            } else {
                6000.0
            };
            s.push(t, v);
        }
        let points = s.points();
        assert!(points.len() <= 2 * SERIES_BUCKETS, "{} points", points.len());
        assert_eq!(s.count(), 1_000_000);
        assert!(points.contains(&(7_777.77, 9999.0)));
        assert!(points.iter().any(|p| p.1 == -5.0));
        assert!(points.windows(2).all(|w| w[0].0 <= w[1].0), "time order");
    }

    #[test]
    fn a_short_series_keeps_every_sample() {
        let mut s = BucketSeries::new(5.0, 0.1);
        for i in 0..50 {
            s.push(5.0 + f64::from(i) * 0.1, f64::from(i));
        }
        assert_eq!(s.points().len(), 50);
    }
}
