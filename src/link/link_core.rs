//! What every family's link shares around its own framing: the clock, the telegram
//! observer, the stop requests, the counters, and the ways of listening to the line (stale
//! input dropped before a request; the reply window from the end of sending; the reply, in
//! slices that let a stop request end the wait, over bytes or CAN frames; late bytes let
//! settle before a retry; and the replies still owed to attempts that went unanswered, which
//! the next exchange waits for and drops before it sends). It must not know any family's
//! telegrams.

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

impl<B> super::AttemptFailure<B> {
    /// How an attempt ends when listening for its reply ended with `wait`: a timeout after
    /// a reply that answered another request was dropped is that reply's discard (retried,
    /// its own reply owed), not silence.
    pub fn after_wait(wait: ReplyWait, dropped: Option<B>) -> Self {
        match (wait, dropped) {
            (ReplyWait::Timeout, Some(reply)) => super::AttemptFailure::Discarded(reply),
            (wait, _) => wait.into(),
        }
    }
}

/// Replies that may still come to attempts that went unanswered in their time: a slave
/// slower than the reply timeout answers each request during the next one's wait, and on
/// a line without sequence numbers its answer would be taken for the next request's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct LateReplies {
    /// How many replies are owed.
    owed: u32,
    /// Until when they are waited for; what comes later cannot be told from an answer.
    until: Duration,
}

pub struct LinkCore {
    pub clock: SharedClock,
    pub stats: LinkStats,
    observer: Option<Box<dyn TelegramObserver>>,
    stop: Option<Arc<StopRequests>>,
    /// A telegram under way gets this long for its reply before a stop request ends the
    /// wait, so the drive's answer to a command already sent is still read.
    grace: Duration,
    late: Option<LateReplies>,
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
            late: None,
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

    /// After an exchange: `owed` replies to its attempts may still come, until `until`.
    /// Earlier debts still open are kept with it (the later time counts).
    pub fn owe_late_replies(&mut self, owed: u32, until: Duration) {
        if owed == 0 {
            return;
        }
        self.late = Some(match self.late {
            Some(l) if l.until > self.clock.now() => LateReplies {
                owed: l.owed + owed,
                until: l.until.max(until),
            },
            _ => LateReplies { owed, until },
        });
    }

    /// Until when a late reply to an earlier request may still come, if one is owed.
    pub fn late_reply_until(&mut self) -> Option<Duration> {
        match self.late {
            Some(l) if l.owed > 0 && l.until > self.clock.now() => Some(l.until),
            Some(_) => {
                self.late = None;
                None
            }
            None => None,
        }
    }

    /// One owed reply came (and was dropped).
    pub fn late_reply_came(&mut self) {
        if let Some(l) = self.late.as_mut() {
            l.owed = l.owed.saturating_sub(1);
        }
    }

    /// Before the first attempt of an exchange on a byte line: listens for the replies still
    /// owed to earlier attempts and drops them, so none is taken for this request's. A reply
    /// is a burst of bytes that ends with `gap` of silence; the wait ends when every owed
    /// reply came (and the line fell quiet) or when their time is over. A stop request ends
    /// it as it ends a reply wait.
    pub fn drain_late_replies(&mut self, t: &mut dyn Transport, gap: Duration) -> Result<(), ReplyWait> {
        let Some(until) = self.late_reply_until() else {
            return Ok(());
        };
        let started = self.clock.now();
        let (mut dropped, mut replies) = (0usize, 0u32);
        // When the last byte of a burst not yet counted came.
        let mut burst: Option<Duration> = None;
        let gap = gap.max(Duration::from_millis(1));
        loop {
            let now = self.clock.now();
            if burst.is_some_and(|last| now >= last + gap) {
                burst = None;
                replies += 1;
                self.late_reply_came();
            }
            let owed = self.late.map_or(0, |l| l.owed);
            if (owed == 0 && burst.is_none()) || now >= until {
                break;
            }
            // The debt is kept: the safe stop's exchanges that follow still wait for these
            // replies, or one of them would be taken for the stop's own.
            if self.stop_pending() {
                return Err(ReplyWait::Interrupted);
            }
            let mut slice = (until - now).min(STOP_POLL.max(gap));
            if let Some(last) = burst {
                slice = slice.min((last + gap).saturating_sub(now).max(Duration::from_micros(100)));
            }
            match t.read(&mut self.buf, slice) {
                Ok(n) => {
                    dropped += n;
                    burst = Some(self.clock.now());
                }
                Err(TransportError::Timeout { .. }) => {}
                Err(e) => return Err(ReplyWait::Transport(e)),
            }
        }
        let waited = self.clock.now().saturating_sub(started).as_millis();
        let lost = self.late.map_or(0, |l| l.owed);
        self.late = None;
        self.event(&match (dropped, lost) {
            (0, _) => format!(
                "waited {waited} ms for the late reply to an earlier attempt before sending; none came"
            ),
            (n, 0) => format!(
                "dropped {n} byte(s) ({replies} late reply(ies) to earlier attempts) in {waited} ms before sending: they answer an earlier request, not this one"
            ),
            (n, _) => format!(
                "dropped {n} byte(s) that came late (answers to earlier attempts) in {waited} ms before sending"
            ),
        });
        Ok(())
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
    use crate::clock::{Clock, VirtualClock};
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

    /// A line on which one late reply arrives at a clock time.
    struct LateLine {
        clock: Arc<VirtualClock>,
        reply: Option<(Duration, Vec<u8>)>,
    }

    impl Transport for LateLine {
        fn name(&self) -> &str {
            "late"
        }
        fn write_all(&mut self, _bytes: &[u8]) -> Result<(), TransportError> {
            Ok(())
        }
        fn read(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
            let now = self.clock.now();
            match self.reply.take() {
                Some((at, bytes)) if at <= now + timeout => {
                    self.clock.advance(at.saturating_sub(now));
                    buf[..bytes.len()].copy_from_slice(&bytes);
                    Ok(bytes.len())
                }
                other => {
                    self.reply = other;
                    self.clock.advance(timeout);
                    Err(TransportError::Timeout {
                        port: "late".into(),
                        waited: timeout,
                    })
                }
            }
        }
        fn discard_input(&mut self) -> Result<usize, TransportError> {
            Ok(0)
        }
        fn reopen(&mut self) -> Result<(), TransportError> {
            Ok(())
        }
    }

    #[test]
    fn a_stop_that_cuts_the_drain_short_leaves_the_late_reply_owed_for_the_safe_stop() {
        let stop = Arc::new(StopRequests::new());
        let clock = Arc::new(VirtualClock::new());
        let mut core = LinkCore::new(clock.clone(), Duration::from_millis(50));
        core.set_stop_requests(stop.clone());
        let mut line = LateLine {
            clock: clock.clone(),
            reply: Some((Duration::from_millis(150), vec![1, 3, 2, 0, 0x40])),
        };
        core.owe_late_replies(1, Duration::from_millis(300));
        stop.request(StopSignal::INT);
        assert!(matches!(
            core.drain_late_replies(&mut line, Duration::from_millis(5)),
            Err(ReplyWait::Interrupted)
        ));
        // The safe stop answers the signal; its first exchange must still drop the reply
        // owed to the step's request before it sends its own.
        stop.enter_safe_stop();
        assert_eq!(core.late_reply_until(), Some(Duration::from_millis(300)));
        assert!(core
            .drain_late_replies(&mut line, Duration::from_millis(5))
            .is_ok());
        assert!(line.reply.is_none(), "the late reply was dropped before sending");
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
