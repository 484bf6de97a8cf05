//! The one retry loop every family's link runs: attempts up to the plan's retries, the stop
//! check and the settle before each retry, the counters and trace lines of each attempt,
//! and how an exchange that got no answer becomes an [`AccessError`]. A family supplies
//! only its attempt (encode, send, classify what comes back) and its timing; it must not
//! loop itself. Must not know any family's telegrams.

use super::{LinkCore, LinkStats, ReplyWait, TelegramObserver};
use crate::bus::{FrameBus, Transport, TransportError};
use crate::clock::SharedClock;
use crate::drive::AccessError;
use crate::stop_request::StopRequests;
use std::fmt::Display;
use std::sync::Arc;
use std::time::Duration;

/// A link built on [`LinkCore`]: what the retry loop and a family's `open` reach through,
/// and the wiring every link offers (observer, stop requests, counters, clock).
pub trait CoreLink {
    fn core(&mut self) -> &mut LinkCore;
    fn core_ref(&self) -> &LinkCore;

    fn set_observer(&mut self, observer: Box<dyn TelegramObserver>) {
        self.core().set_observer(observer);
    }

    fn take_observer(&mut self) -> Option<Box<dyn TelegramObserver>> {
        self.core().take_observer()
    }

    /// Lets stop requests end reply waits and retries early (after the family's grace).
    fn set_stop_requests(&mut self, stop: Arc<StopRequests>) {
        self.core().set_stop_requests(stop);
    }

    fn stats(&self) -> LinkStats {
        self.core_ref().stats
    }

    fn clock(&self) -> &SharedClock {
        &self.core_ref().clock
    }
}

/// The [`CoreLink`] accessors of a link that keeps its [`LinkCore`] in a field `core`,
/// written inside its `impl CoreLink`: `core_link_field!();`.
#[macro_export]
macro_rules! core_link_field {
    () => {
        fn core(&mut self) -> &mut $crate::link::LinkCore {
            &mut self.core
        }
        fn core_ref(&self) -> &$crate::link::LinkCore {
            &self.core
        }
    };
}

/// What a link listens to between attempts and before an exchange: a byte line lets late
/// bytes settle and drops them, and waits for the replies still owed to earlier attempts; a
/// CAN bus has nothing to wait for here (its responses name their node and object, and the
/// SDO link drains what its node still owes itself, since other nodes' frames must be seen).
pub trait Settle {
    fn settle(&mut self, core: &mut LinkCore, settle: Duration) -> Result<(), AccessError>;
    /// Before the first attempt: drops the replies earlier attempts still owe (`gap` of
    /// silence ends one).
    fn drain_late(&mut self, core: &mut LinkCore, gap: Duration) -> Result<(), ReplyWait>;
}

impl Settle for dyn Transport + '_ {
    fn settle(&mut self, core: &mut LinkCore, settle: Duration) -> Result<(), AccessError> {
        core.settle(self, settle)
    }
    fn drain_late(&mut self, core: &mut LinkCore, gap: Duration) -> Result<(), ReplyWait> {
        core.drain_late_replies(self, gap)
    }
}

impl Settle for dyn FrameBus + '_ {
    fn settle(&mut self, _core: &mut LinkCore, _settle: Duration) -> Result<(), AccessError> {
        Ok(())
    }
    fn drain_late(&mut self, _core: &mut LinkCore, _gap: Duration) -> Result<(), ReplyWait> {
        Ok(())
    }
}

/// Why one attempt did not produce a reply that answers the request.
#[derive(Debug)]
pub enum AttemptFailure<B> {
    /// Nothing that answers in time; `note` ends the trace line (" after the echo of our
    /// message"), usually empty.
    Timeout { note: &'static str },
    /// Something came that does not answer (corrupt, a protocol error): retried.
    Bad(B),
    /// A valid reply came that answers another request (another slave, function, object or
    /// echo: most often a late answer to an earlier one); the family dropped it (and said so
    /// in the trace) and listened on, and this attempt's own reply did not come in its time.
    /// Retried; its reply is owed, as after a timeout.
    Discarded(B),
    /// A stop was requested while the drive was silent.
    Interrupted,
    /// The line itself failed (closed, unplugged): retrying will not help.
    Transport(TransportError),
}

/// A reply that does not answer: what came and why it was refused (shown as the problem).
#[derive(Debug)]
pub struct Refusal<R, P> {
    pub reply: R,
    pub problem: P,
}

impl<R, P: Display> Display for Refusal<R, P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.problem.fmt(f)
    }
}

/// How an exchange ended without an answer.
#[derive(Debug)]
pub enum Unanswered<B> {
    Interrupted,
    Transport(TransportError),
    /// Every attempt failed; the last bad reply, if any came.
    GaveUp {
        last_bad: Option<B>,
        attempts: u32,
    },
    /// Settling or the family's step between attempts failed.
    Failed(AccessError),
}

/// The replies an exchange's unanswered attempts may still get, and when the last attempt
/// started.
#[derive(Default)]
struct Owed {
    replies: u32,
    last_start: Duration,
}

impl Owed {
    /// Tells the core what is owed: until the last attempt's reply window is over and, after
    /// it, as long again as the slave took to answer (`latency`; at least a reply timeout).
    fn settle(&self, core: &mut LinkCore, plan: &RetryPlan, latency: Duration) {
        if plan.sequenced || self.replies == 0 {
            return;
        }
        let until = self.last_start + plan.reply_timeout + plan.reply_timeout.max(latency);
        core.owe_late_replies(self.replies, until);
    }
}

/// What the errors of one exchange name.
pub struct ExchangeText {
    pub port: String,
    pub address: String,
    /// `` `00 09 02 …` (read object 67) ``.
    pub request: String,
    /// What to check when the drive stayed silent.
    pub hint: String,
}

impl<B> Unanswered<B> {
    /// The error a user sees; `bad` shows a bad reply as (reply, problem).
    pub fn into_error(
        self,
        text: ExchangeText,
        timeout: Duration,
        bad: impl FnOnce(B) -> (String, String),
    ) -> AccessError {
        match self {
            Unanswered::Interrupted => AccessError::Interrupted {
                port: text.port,
                address: text.address,
                request: text.request,
            },
            Unanswered::Transport(e) => AccessError::Transport(e),
            Unanswered::Failed(e) => e,
            Unanswered::GaveUp {
                last_bad: Some(b),
                attempts,
            } => {
                let (reply, problem) = bad(b);
                AccessError::BadReply {
                    port: text.port,
                    address: text.address,
                    request: text.request,
                    reply,
                    problem,
                    attempts,
                }
            }
            Unanswered::GaveUp {
                last_bad: None,
                attempts,
            } => AccessError::NoReply {
                port: text.port,
                address: text.address,
                request: text.request,
                attempts,
                timeout_ms: timeout.as_millis(),
                hint: text.hint,
            },
        }
    }
}

/// A family's timing and words for the retry loop.
#[derive(Debug, Clone, Copy)]
pub struct RetryPlan {
    /// Further attempts after a timeout or a bad reply.
    pub retries: u32,
    /// Listened to (and dropped) before a retry; the protocols have no sequence numbers.
    /// Also the silence that ends a late reply dropped before an exchange.
    pub settle: Duration,
    pub reply_timeout: Duration,
    /// How the trace names an answer (`reply`, `response`) and the line (`transport`,
    /// `CAN adapter`).
    pub reply_word: &'static str,
    pub line_word: &'static str,
    /// Replies carry the request's sequence number (Modbus TCP's transaction id), so a
    /// late one is told apart without waiting for it before the next exchange.
    pub sequenced: bool,
}

impl RetryPlan {
    /// A byte line's plan: a `reply` over the `transport`.
    pub fn new(retries: u32, settle: Duration, reply_timeout: Duration) -> Self {
        RetryPlan {
            retries,
            settle,
            reply_timeout,
            reply_word: "reply",
            line_word: "transport",
            sequenced: false,
        }
    }

    /// Runs `attempt` until it answers, up to `retries` more times. `attempt` is given its
    /// number, from 1.
    pub fn run<K, L, R, B>(
        &self,
        link: &mut K,
        line: &mut L,
        attempt: impl FnMut(&mut K, &mut L, u32) -> Result<R, AttemptFailure<B>>,
    ) -> Result<R, Unanswered<B>>
    where
        K: CoreLink + ?Sized,
        L: Settle + ?Sized,
        B: Display,
    {
        self.run_with_step(link, line, |_, _| Ok(None), attempt)
    }

    /// [`run`](Self::run), with `between` after a failed attempt before the next (a write's
    /// read-back), which may end the exchange with a result.
    pub fn run_with_step<K, L, R, B>(
        &self,
        link: &mut K,
        line: &mut L,
        mut between: impl FnMut(&mut K, &mut L) -> Result<Option<R>, AccessError>,
        mut attempt: impl FnMut(&mut K, &mut L, u32) -> Result<R, AttemptFailure<B>>,
    ) -> Result<R, Unanswered<B>>
    where
        K: CoreLink + ?Sized,
        L: Settle + ?Sized,
        B: Display,
    {
        let attempts = self.retries + 1;
        let mut last_bad = None;
        if !self.sequenced {
            line.drain_late(link.core(), self.settle)
                .map_err(|wait| match wait {
                    ReplyWait::Transport(e) => Unanswered::Transport(e),
                    _ => Unanswered::Interrupted,
                })?;
        }
        let first_start = link.core().clock.now();
        let mut owed = Owed::default();
        for number in 1..=attempts {
            if number > 1 {
                if let Some(done) = between(link, line).map_err(Unanswered::Failed)? {
                    return Ok(done);
                }
                let core = link.core();
                if core.stop_pending() {
                    return Err(Unanswered::Interrupted);
                }
                core.stats.retries += 1;
                line.settle(core, self.settle).map_err(Unanswered::Failed)?;
                core.event(&format!("retry {} of {}", number - 1, self.retries));
            }
            owed.last_start = link.core().clock.now();
            let result = attempt(link, line, number);
            self.record(link.core(), &result);
            match result {
                Ok(done) => {
                    // The reply may have answered the first attempt: the slave is as slow as
                    // that, and each later attempt's reply is as late.
                    let latency = link.core().clock.now().saturating_sub(first_start);
                    owed.settle(link.core(), self, latency);
                    return Ok(done);
                }
                Err(AttemptFailure::Timeout { .. }) => owed.replies += 1,
                Err(AttemptFailure::Bad(b)) => last_bad = Some(b),
                Err(AttemptFailure::Discarded(b)) => {
                    owed.replies += 1;
                    last_bad = Some(b);
                }
                Err(AttemptFailure::Interrupted) => {
                    owed.replies += 1;
                    owed.settle(link.core(), self, Duration::ZERO);
                    return Err(Unanswered::Interrupted);
                }
                Err(AttemptFailure::Transport(e)) => return Err(Unanswered::Transport(e)),
            }
        }
        owed.settle(link.core(), self, Duration::ZERO);
        Err(Unanswered::GaveUp { last_bad, attempts })
    }

    /// Counts and traces how one attempt ended; for an attempt made outside [`run`](Self::run)
    /// (a read-back) too.
    pub fn record<R, B: Display>(&self, core: &mut LinkCore, result: &Result<R, AttemptFailure<B>>) {
        let reply = self.reply_word;
        match result {
            Ok(_) => core.stats.replies += 1,
            Err(AttemptFailure::Timeout { note }) => {
                core.stats.timeouts += 1;
                let ms = self.reply_timeout.as_millis();
                core.event(&format!("no {reply} within {ms} ms{note}"));
            }
            Err(AttemptFailure::Bad(problem)) => core.event(&format!("{reply} refused: {problem}")),
            Err(AttemptFailure::Discarded(problem)) => {
                core.stats.timeouts += 1;
                let ms = self.reply_timeout.as_millis();
                core.event(&format!(
                    "no {reply} within {ms} ms (one that answers another request was dropped: {problem})"
                ));
            }
            Err(AttemptFailure::Transport(e)) => core.event(&format!("{} failed: {e}", self.line_word)),
            Err(AttemptFailure::Interrupted) => {
                core.event(&format!("stop requested while waiting for the {reply}"))
            }
        }
    }
}
