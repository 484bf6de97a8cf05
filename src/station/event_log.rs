//! The station's view and the events that changed it, shared by the run's observer (which
//! writes) and every connected page (which reads): a bounded ring of numbered events, so
//! a page follows the run by asking for what came after the last one it has, and one that
//! fell too far behind (or just connected) takes the whole view instead. Memory is bounded
//! by the ring and the view's own bounds, however long the run and however many pages.

use super::station_view::StationView;
use serde_json::Value;
use std::collections::VecDeque;
use std::sync::{Mutex, MutexGuard, PoisonError};
use tokio::sync::Notify;

/// The most events kept for pages catching up.
pub const EVENTS: usize = 2048;

/// What a page gets next.
#[derive(Debug, Clone, PartialEq)]
pub enum Catch {
    /// The events after the one it has, each with its number.
    Events(Vec<(u64, String)>),
    /// The whole view (JSON) and the number of the last event it holds.
    View(u64, String),
}

struct Inner {
    view: StationView,
    ring: VecDeque<(u64, String)>,
    /// The number of the last event.
    last: u64,
    /// The station has ended: the pages' streams end too (the web server's shutdown waits
    /// for them).
    closed: bool,
}

pub struct EventLog {
    inner: Mutex<Inner>,
    /// Wakes the pages' streams when an event is kept (never while the lock is held).
    changed: Notify,
}

impl EventLog {
    pub fn new(view: StationView) -> Self {
        EventLog {
            inner: Mutex::new(Inner {
                view,
                ring: VecDeque::new(),
                last: 0,
                closed: false,
            }),
            changed: Notify::new(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        // A panic while the view changed leaves at worst one event unsent; the run and
        // its safe stop must not depend on the page's log.
        self.inner.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Changes the view; the event `change` returns is numbered and kept for the pages.
    pub fn change<T>(&self, change: impl FnOnce(&mut StationView) -> (T, Option<Value>)) -> T {
        let mut inner = self.lock();
        let (out, event) = change(&mut inner.view);
        let Some(event) = event else { return out };
        inner.last += 1;
        let number = inner.last;
        if inner.ring.len() >= EVENTS {
            inner.ring.pop_front();
        }
        inner.ring.push_back((number, event.to_string()));
        drop(inner);
        self.changed.notify_waiters();
        out
    }

    /// What a page that has every event up to `after` gets next, waiting for it when
    /// there is nothing yet; `None` once the log is closed and the page has it all.
    pub async fn next(&self, after: Option<u64>) -> Option<Catch> {
        loop {
            let mut notified = std::pin::pin!(self.changed.notified());
            // Registered before looking, so an event kept in between still wakes it.
            notified.as_mut().enable();
            match self.catch_up(after) {
                Catch::Events(e) if e.is_empty() && self.lock().closed => return None,
                Catch::Events(e) if e.is_empty() => notified.await,
                caught => return Some(caught),
            }
        }
    }

    /// The station has ended: each page's stream ends once it has every event.
    pub fn close(&self) {
        self.lock().closed = true;
        self.changed.notify_waiters();
    }

    /// Reads the view.
    pub fn read<T>(&self, read: impl FnOnce(&StationView) -> T) -> T {
        read(&self.lock().view)
    }

    /// What a page that has every event up to `after` gets next (`None`: it has none).
    pub fn catch_up(&self, after: Option<u64>) -> Catch {
        let inner = self.lock();
        let first = inner.ring.front().map_or(inner.last + 1, |(n, _)| *n);
        match after {
            Some(a) if a <= inner.last && a + 1 >= first => {
                Catch::Events(inner.ring.iter().filter(|(n, _)| *n > a).cloned().collect())
            }
            _ => Catch::View(
                inner.last,
                serde_json::to_string(&inner.view).unwrap_or_else(|_| "{}".into()),
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn log() -> EventLog {
        EventLog::new(StationView::new(Vec::new(), "bench".into()))
    }

    #[test]
    fn a_page_gets_the_view_then_follows_the_events() {
        let log = log();
        let Catch::View(n, view) = log.catch_up(None) else {
            panic!("a new page gets the view")
        };
        assert_eq!(n, 0);
        assert!(view.contains("\"station\":\"bench\""), "{view}");
        log.change(|_| ((), Some(json!({"kind": "note"}))));
        log.change(|_| ((), None));
        log.change(|_| ((), Some(json!({"kind": "other"}))));
        let Catch::Events(events) = log.catch_up(Some(n)) else {
            panic!("a page that kept up gets events")
        };
        assert_eq!(events.len(), 2);
        assert_eq!(events[1].0, 2);
        assert_eq!(log.catch_up(Some(2)), Catch::Events(Vec::new()));
    }

    #[test]
    fn a_page_too_far_behind_gets_the_view_and_the_ring_stays_bounded() {
        let log = log();
        for _ in 0..EVENTS * 3 {
            log.change(|_| ((), Some(json!({"kind": "note"}))));
        }
        assert!(matches!(log.catch_up(Some(1)), Catch::View(n, _) if n == (EVENTS * 3) as u64));
        assert_eq!(log.lock().ring.len(), EVENTS);
        // A number from a station that restarted is no number of this one.
        assert!(matches!(log.catch_up(Some(u64::MAX)), Catch::View(..)));
    }
}
