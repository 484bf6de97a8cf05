//! One live plot's series, bounded however long the run: every `stride`-th sample is kept,
//! and when the buffer is full every other point is dropped and the stride doubles, so a
//! one-hour run at 100 Hz holds as many points as a one-minute one. Pure data: no I/O.

use serde::Serialize;

/// The most points one series holds (on the server and in the page).
pub const POINTS: usize = 1000;

/// A sampled object's plotted points.
#[derive(Debug, Clone, Serialize)]
pub struct PlotBuffer {
    pub name: String,
    pub unit: Option<String>,
    /// Seconds since the run's start.
    pub t: Vec<f64>,
    pub v: Vec<f64>,
    /// Every `stride`-th sample is kept.
    pub stride: u64,
    /// Samples seen so far (kept or not).
    #[serde(skip)]
    seen: u64,
}

/// What [`PlotBuffer::push`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pushed {
    Dropped,
    Kept,
    /// Kept, after every other point was dropped and the stride doubled.
    Compacted,
}

impl PlotBuffer {
    pub fn new(name: &str, unit: Option<String>) -> Self {
        PlotBuffer {
            name: name.to_string(),
            unit,
            t: Vec::with_capacity(POINTS),
            v: Vec::with_capacity(POINTS),
            stride: 1,
            seen: 0,
        }
    }

    pub fn push(&mut self, t: f64, v: f64) -> Pushed {
        let index = self.seen;
        self.seen += 1;
        if !index.is_multiple_of(self.stride) {
            return Pushed::Dropped;
        }
        let mut pushed = Pushed::Kept;
        if self.t.len() >= POINTS {
            halve(&mut self.t);
            halve(&mut self.v);
            self.stride *= 2;
            pushed = Pushed::Compacted;
            if !index.is_multiple_of(self.stride) {
                return Pushed::Compacted;
            }
        }
        self.t.push(t);
        self.v.push(v);
        pushed
    }

    /// Counts `n` samples that [`PlotBuffer::position`] says are dropped, as `n` pushes of
    /// them would (a writer that knows saves pushing them one by one).
    pub fn skip(&mut self, n: u64) {
        self.seen += n;
    }

    /// Samples seen so far and the stride: the next sample is dropped (and nothing else
    /// changes) unless the samples seen are a multiple of the stride.
    pub fn position(&self) -> (u64, u64) {
        (self.seen, self.stride)
    }

    /// Whether the sample just pushed was kept (for the batch sent to pages).
    pub fn last_kept(&self) -> bool {
        (self.seen - 1).is_multiple_of(self.stride)
    }
}

/// Keeps the points at even positions (the first point is sample 0, so these are the
/// multiples of the doubled stride).
pub fn halve(points: &mut Vec<f64>) {
    let mut i = 0;
    points.retain(|_| {
        i += 1;
        i % 2 == 1
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_series_stays_within_its_bound_and_spans_the_whole_run() {
        let mut b = PlotBuffer::new("speed", Some("rpm".into()));
        let samples = 360_000u64;
        for i in 0..samples {
            b.push(i as f64 / 100.0, i as f64);
        }
        assert!(b.t.len() <= POINTS && b.t.len() > POINTS / 2, "{}", b.t.len());
        assert_eq!(b.t[0], 0.0);
        assert!(*b.t.last().unwrap() > 3500.0, "the end of the run is kept");
        // Evenly spaced: every kept sample is a multiple of the stride.
        assert!(b.v.iter().all(|v| (*v as u64).is_multiple_of(b.stride)));
        let gaps: Vec<f64> = b.v.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().all(|g| *g == b.stride as f64), "{gaps:?}");
    }

    #[test]
    fn a_short_series_keeps_every_sample() {
        let mut b = PlotBuffer::new("current", None);
        for i in 0..10 {
            assert_eq!(b.push(i as f64, 1.0), Pushed::Kept);
        }
        assert_eq!(b.t.len(), 10);
    }
}
