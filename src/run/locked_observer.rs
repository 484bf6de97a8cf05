//! A shared observer (one its caller keeps a handle on: the results store, the station's
//! page) as the run's observers list sees it. Its lock is taken once per event, except for
//! the rows of a sampling loop: those are held and handed over together, under one lock,
//! at most [`HELD_FOR`] of the run's time after the last ones (a long run at 100 Hz would
//! otherwise take the lock twice per row, for the row and for the wait after it). Every
//! event still reaches the observer, in the order the run made them: any other event hands
//! the held rows over first. Must not fail the run, nor drop, reorder or change an event.

use crate::session::{ObjectRef, RunObserver};
use std::sync::{Mutex, PoisonError};
use std::time::Duration;

/// The most run time between one hand-over of rows and the next while rows keep coming
/// (a page's plot lags by at most this, plus one sample interval shorter than it).
pub const HELD_FOR: Duration = Duration::from_millis(100);
/// The most rows held, so that a fast sample of many objects holds little.
pub const HELD_ROWS: usize = 64;

pub struct LockedObserver<'a> {
    observer: &'a Mutex<dyn RunObserver>,
    /// Whether it shows live progress, asked once: it is what the observer is, and the run
    /// asks for every sample row.
    wants_progress: bool,
    /// The objects of the rows held (a new allocation whenever they change, so that the
    /// observer, handed this slice, may tell them apart by their place).
    objects: Vec<ObjectRef>,
    /// Where the caller kept the objects of the last row (address and number): a sampling
    /// loop hands the same slice with every row, so a row there names the objects held
    /// without comparing names. Forgotten at every other event (a new step may keep other
    /// objects at that place).
    objects_at: Option<(usize, usize)>,
    /// The rows held: their times, and their values one row after the other.
    at: Vec<Duration>,
    values: Vec<f64>,
    /// From when a row is due: [`HELD_FOR`] after the last row handed over (zero before
    /// the first: it goes at once).
    due_from: Duration,
    /// The rows held are due: they go with the wait that follows them, under its lock.
    due: bool,
}

impl<'a> LockedObserver<'a> {
    pub fn new(observer: &'a Mutex<dyn RunObserver>) -> Self {
        // A poisoned lock still gets every event: an observer must never fail the run.
        let wants_progress = observer
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .wants_progress();
        LockedObserver {
            observer,
            wants_progress,
            objects: Vec::new(),
            objects_at: None,
            at: Vec::new(),
            values: Vec::with_capacity(HELD_ROWS * 2),
            due_from: Duration::ZERO,
            due: false,
        }
    }

    /// An event other than a row or a wait: the rows held, then `f`, under the lock.
    fn relay<T>(&mut self, f: impl FnOnce(&mut dyn RunObserver) -> T) -> T {
        self.objects_at = None;
        self.with(f)
    }

    /// Under the observer's lock: the rows held, then `f`.
    fn with<T>(&mut self, f: impl FnOnce(&mut dyn RunObserver) -> T) -> T {
        let observer = self.observer;
        let mut observer = observer.lock().unwrap_or_else(PoisonError::into_inner);
        self.hand_over(&mut *observer);
        f(&mut *observer)
    }

    fn hand_over(&mut self, observer: &mut dyn RunObserver) {
        let width = self.objects.len();
        for (i, at) in self.at.iter().enumerate() {
            observer.sample(*at, &self.objects, &self.values[i * width..(i + 1) * width]);
        }
        if let Some(last) = self.at.last() {
            self.due_from = last.saturating_add(HELD_FOR);
        }
        self.at.clear();
        self.values.clear();
        self.due = false;
    }
}

impl RunObserver for LockedObserver<'_> {
    crate::relayed_events!();
    fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
        if values.len() != objects.len() {
            // Held rows are sliced by the number of objects: a row of another width
            // goes on its own, after those held.
            self.relay(|o| o.sample(at, objects, values));
            return;
        }
        let place = (objects.as_ptr() as usize, objects.len());
        if self.objects_at != Some(place) {
            self.objects_at = Some(place);
            if self.objects != objects {
                // The rows held name the objects before: they go first.
                self.with(|_| ());
                self.objects = objects.to_vec();
            }
        }
        // Rows due whose wait never came go first too.
        if self.due {
            self.with(|_| ());
        }
        self.at.push(at);
        self.values.extend_from_slice(values);
        self.due = at >= self.due_from || self.at.len() >= HELD_ROWS;
    }
    fn wants_progress(&self) -> bool {
        self.wants_progress
    }
    fn idle(&mut self) {
        // A wait between rows not yet due is the sampling loop's own: the rows go with a
        // later one, at most HELD_FOR on.
        if self.at.is_empty() || self.due {
            self.with(|o| o.idle());
        }
    }
}

impl Drop for LockedObserver<'_> {
    /// A run that ends without its last event (a panic) still hands over its rows.
    fn drop(&mut self) {
        if !self.at.is_empty() {
            self.with(|_| ());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    /// Every event as a line, in the order received.
    #[derive(Default)]
    struct Lines(Vec<String>);

    impl RunObserver for Lines {
        fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
            let names: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
            self.0.push(format!("{} {names:?} {values:?}", at.as_millis()));
        }
        fn message(&mut self, text: &str) {
            self.0.push(text.to_string());
        }
        fn idle(&mut self) {
            self.0.push("idle".into());
        }
    }

    fn objects(names: &[&str]) -> Vec<ObjectRef> {
        names
            .iter()
            .map(|n| ObjectRef {
                name: n.to_string(),
                unit: None,
            })
            .collect()
    }

    /// An observer that keeps its events as lines, and the same as the run's observer.
    fn lines_observer() -> (Arc<Mutex<Lines>>, Arc<Mutex<dyn RunObserver>>) {
        let shared = Arc::new(Mutex::new(Lines::default()));
        let dynamic: Arc<Mutex<dyn RunObserver>> = shared.clone();
        (shared, dynamic)
    }

    fn lines(shared: &Arc<Mutex<Lines>>) -> Vec<String> {
        shared.lock().expect("lines").0.clone()
    }

    #[test]
    fn rows_reach_the_observer_in_order_at_most_held_for_after_the_last_ones() {
        let (shared, dynamic) = lines_observer();
        let mut locked = LockedObserver::new(&dynamic);
        let two = objects(&["speed", "current"]);
        // A sampling loop at 100 Hz: a row, then the wait before the next.
        for k in 0..25u64 {
            locked.sample(Duration::from_millis(10 * k), &two, &[k as f64, -(k as f64)]);
            locked.idle();
            let seen = lines(&shared);
            let rows = seen.iter().filter(|l| *l != "idle").count() as u64;
            // The first row at once; then every row within HELD_FOR of the run's time.
            assert!(
                rows >= 1 && (k + 1 - rows) * 10 < HELD_FOR.as_millis() as u64,
                "{k}: {seen:?}"
            );
        }
        // Far fewer waits passed on than rows: the lock is taken once per batch.
        let idles = lines(&shared).iter().filter(|l| *l == "idle").count();
        assert!(idles <= 4, "{idles}");
        // Rows of other objects, and any other event, hand over what is held first.
        let one = objects(&["torque"]);
        locked.sample(Duration::from_millis(251), &two, &[1.0, 2.0]);
        locked.sample(Duration::from_millis(252), &one, &[3.0]);
        locked.message("done");
        let seen = lines(&shared);
        let rows: Vec<&String> = seen.iter().filter(|l| *l != "idle").collect();
        assert_eq!(rows.len(), 28, "{seen:?}");
        for (k, row) in rows.iter().take(25).enumerate() {
            assert_eq!(
                **row,
                format!("{} [\"speed\", \"current\"] [{}.0, {}.0]", 10 * k, k, -(k as f64)),
                "{seen:?}"
            );
        }
        assert_eq!(rows[25], "251 [\"speed\", \"current\"] [1.0, 2.0]");
        assert_eq!(rows[26], "252 [\"torque\"] [3.0]");
        assert_eq!(rows[27], "done");
    }

    #[test]
    fn rows_held_when_the_run_ends_without_its_last_event_are_handed_over() {
        let (shared, dynamic) = lines_observer();
        let mut locked = LockedObserver::new(&dynamic);
        let one = objects(&["speed"]);
        for k in 0..5u64 {
            locked.sample(Duration::from_millis(k), &one, &[k as f64]);
        }
        drop(locked);
        assert_eq!(lines(&shared).len(), 5);
    }

    #[test]
    fn slow_rows_are_each_handed_over_at_once() {
        let (shared, dynamic) = lines_observer();
        let mut locked = LockedObserver::new(&dynamic);
        let one = objects(&["speed"]);
        for k in 0..5u64 {
            locked.sample(Duration::from_secs(k), &one, &[k as f64]);
            locked.idle();
            assert_eq!(lines(&shared).len() as u64, 2 * (k + 1), "{:?}", lines(&shared));
        }
    }

    #[test]
    fn a_row_of_another_width_than_its_objects_follows_the_held_rows_unsliced() {
        let (shared, dynamic) = lines_observer();
        let mut locked = LockedObserver::new(&dynamic);
        let two = objects(&["speed", "current"]);
        locked.sample(Duration::from_millis(1), &two, &[1.0, 2.0]);
        locked.sample(Duration::from_millis(2), &two, &[3.0]);
        locked.sample(Duration::from_millis(3), &two, &[4.0, 5.0]);
        drop(locked);
        assert_eq!(
            lines(&shared),
            [
                "1 [\"speed\", \"current\"] [1.0, 2.0]",
                "2 [\"speed\", \"current\"] [3.0]",
                "3 [\"speed\", \"current\"] [4.0, 5.0]"
            ]
        );
    }
}
