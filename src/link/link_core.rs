//! What every family's link shares around its own framing: the clock, the telegram
//! observer, the stop requests, the counters, and the ways of listening to the line (stale
//! input dropped before a request; the reply window from the end of sending; the reply, in
//! slices that let a stop request end the wait, over bytes or CAN frames; and late bytes
//! let settle before a retry). It must not know any family's telegrams.

use super::{Direction, LinkStats, TelegramObserver};
use crate::bus::{CanFrame, Transport, TransportError};
use crate::clock::SharedClock;
use crate::drive::AccessError;
use crate::stop_request::StopRequests;
use std::sync::Arc;
use std::time::Duration;

/// While waiting for a reply after the grace, the line is read in slices this long so a
/// stop request is seen within it.
const STOP_POLL: Duration = Duration::from_millis(10);

/// How listening for a reply ended without bytes.
#[derive(Debug)]
pub enum ReplyWait {
    /// The reply's time is over.
    Timeout,
    /// A stop was requested (after the grace).
    Interrupted,
    Transport(TransportError),
}

impl<B> From<ReplyWait> for super::AttemptFailure<B> {
    fn from(wait: ReplyWait) -> Self {
        match wait {
            ReplyWait::Timeout => super::AttemptFailure::Timeout { note: "" },
            ReplyWait::Interrupted => super::AttemptFailure::Interrupted,
            ReplyWait::Transport(e) => super::AttemptFailure::Transport(e),
        }
    }
}

pub struct LinkCore {
    pub clock: SharedClock,
    pub stats: LinkStats,
    observer: Option<Box<dyn TelegramObserver>>,
    stop: Option<Arc<StopRequests>>,
    /// A telegram under way gets this long for its reply before a stop request ends the
    /// wait, so the drive's answer to a command already sent is still read.
    grace: Duration,
    buf: [u8; 256],
}

impl LinkCore {
    pub fn new(clock: SharedClock, grace: Duration) -> Self {
        LinkCore {
            clock,
            stats: LinkStats::default(),
            observer: None,
            stop: None,
            grace,
            buf: [0; 256],
        }
    }

    pub fn set_observer(&mut self, observer: Box<dyn TelegramObserver>) {
        self.observer = Some(observer);
    }

    pub fn take_observer(&mut self) -> Option<Box<dyn TelegramObserver>> {
        self.observer.take()
    }

    pub fn set_stop_requests(&mut self, stop: Arc<StopRequests>) {
        self.stop = Some(stop);
    }

    pub fn stop_pending(&self) -> bool {
        self.stop.as_ref().is_some_and(|s| s.pending_at(self.clock.now()))
    }

    // The clock is read only for an observer: without a trace it would be read twice per
    // telegram for nothing.
    pub fn notify(&mut self, direction: Direction, bytes: &[u8]) {
        if let Some(o) = self.observer.as_mut() {
            o.telegram(self.clock.now(), direction, bytes);
        }
    }

    pub fn notify_frame(&mut self, direction: Direction, frame: &CanFrame) {
        if let Some(o) = self.observer.as_mut() {
            o.frame(self.clock.now(), direction, frame);
        }
    }

    pub fn event(&mut self, text: &str) {
        if let Some(o) = self.observer.as_mut() {
            o.event(self.clock.now(), text);
        }
    }

    /// Drops the input waiting on the line before a request, together with the `unread`
    /// bytes the link's own framing still held, and says so when there were any: a late
    /// reply to an earlier request must not be taken for this one's.
    pub fn drop_stale_input(&mut self, t: &mut dyn Transport, unread: usize) -> Result<(), TransportError> {
        let dropped = t.discard_input()? + unread;
        if dropped > 0 {
            self.event(&format!("discarded {dropped} stale byte(s) before sending"));
        }
        Ok(())
    }

    /// When the request just written has left the line, and when its reply's time is over:
    /// the reply timeout and the stop grace count from the last byte, not the write.
    pub fn reply_window(&self, t: &dyn Transport, reply_timeout: Duration) -> (Duration, Duration) {
        let sent = self.clock.now() + t.still_sending();
        (sent, sent + reply_timeout)
    }

    /// How long the next read of a reply wait may block, for a request that left the line
    /// at `sent`: the whole rest without stop requests, the rest of the grace within it,
    /// then slices that let a stop request end the wait. `None` once `deadline` has passed.
    pub fn next_slice(&self, sent: Duration, deadline: Duration) -> Option<Duration> {
        let now = self.clock.now();
        if now >= deadline {
            return None;
        }
        Some(match &self.stop {
            None => deadline - now,
            Some(_) if now.saturating_sub(sent) < self.grace => {
                (sent + self.grace).min(deadline).saturating_sub(now)
            }
            Some(_) => STOP_POLL.min(deadline - now),
        })
    }

    /// After a slice passed without anything: whether the wait ends (its time is over, or a
    /// stop was requested after the grace); `None` to listen on.
    pub fn after_quiet(&self, sent: Duration, deadline: Duration) -> Option<ReplyWait> {
        let now = self.clock.now();
        if now >= deadline {
            Some(ReplyWait::Timeout)
        } else if now.saturating_sub(sent) >= self.grace && self.stop_pending() {
            Some(ReplyWait::Interrupted)
        } else {
            None
        }
    }

    /// Reads what has arrived of a reply to a request that left the line at `sent` (a
    /// time that may still lie ahead while its bytes are on their way), waiting at most until
    /// `deadline` and, once the grace is over, in slices that end early for a stop request.
    /// `Ok(bytes)` may be empty: a slice passed without bytes and without a stop.
    pub fn read_reply(
        &mut self,
        t: &mut dyn Transport,
        sent: Duration,
        deadline: Duration,
    ) -> Result<&[u8], ReplyWait> {
        let slice = self.next_slice(sent, deadline).ok_or(ReplyWait::Timeout)?;
        match t.read(&mut self.buf, slice) {
            Ok(n) => Ok(&self.buf[..n]),
            Err(TransportError::Timeout { .. }) => match self.after_quiet(sent, deadline) {
                Some(end) => Err(end),
                None => Ok(&[]),
            },
            Err(e) => Err(ReplyWait::Transport(e)),
        }
    }

    /// Listens for `settle` and drops whatever arrives: the protocols have no sequence
    /// numbers, so a late answer to a failed attempt would be taken for the retry's.
    pub fn settle(&mut self, t: &mut dyn Transport, settle: Duration) -> Result<(), AccessError> {
        let until = self.clock.now() + settle;
        let mut dropped = 0;
        loop {
            let now = self.clock.now();
            if now >= until {
                break;
            }
            match t.read(&mut self.buf, until - now) {
                Ok(n) => dropped += n,
                Err(TransportError::Timeout { .. }) => break,
                Err(e) => return Err(AccessError::Transport(e)),
            }
        }
        if dropped > 0 {
            self.event(&format!("dropped {dropped} late byte(s) before retrying"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::VirtualClock;
    use crate::stop_request::StopSignal;

    /// A link waiting for a slow reply, past its grace: what a stop request does to it.
    fn slow_reply(stop: &Arc<StopRequests>) -> (LinkCore, Duration, Duration) {
        let clock = Arc::new(VirtualClock::new());
        let mut core = LinkCore::new(clock.clone(), Duration::from_millis(50));
        core.set_stop_requests(stop.clone());
        clock.advance(Duration::from_millis(200));
        (core, Duration::ZERO, Duration::from_secs(1))
    }

    #[test]
    fn a_first_request_during_the_safe_stop_does_not_cut_off_a_reply() {
        let stop = Arc::new(StopRequests::new());
        let (core, sent, deadline) = slow_reply(&stop);
        stop.enter_safe_stop();
        stop.request(StopSignal::INT);
        assert!(
            core.after_quiet(sent, deadline).is_none(),
            "the reply is still awaited"
        );
        stop.request(StopSignal::INT);
        assert!(matches!(
            core.after_quiet(sent, deadline),
            Some(ReplyWait::Interrupted)
        ));
    }

    #[test]
    fn a_first_request_during_the_steps_ends_a_reply_wait_after_the_grace() {
        let stop = Arc::new(StopRequests::new());
        let (core, sent, deadline) = slow_reply(&stop);
        stop.request(StopSignal::INT);
        assert!(matches!(
            core.after_quiet(sent, deadline),
            Some(ReplyWait::Interrupted)
        ));
    }
}
