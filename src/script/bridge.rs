//! The script thread's side of a run: it sends each drive call to the session thread and
//! waits for the answer, answers the questions of a `wait_until` in between, and turns a
//! failed call into a Rhai error. Stop requests, a lost port, a panic and `fail` end the
//! script in a way `try`/`catch` cannot swallow (Rhai's termination); errors the script
//! may handle (a drive fault, a refused write, a timeout) are catchable. It also keeps the
//! operation count for the sandbox's limit between drive calls. It must not touch the
//! drive: only the session thread does.

use super::exchange::{Answer, Call, Request, ToScript, ToSession};
use crate::clock::SharedClock;
use crate::dictionary::Dictionary;
use crate::session::Stop;
use crate::stop_request::StopRequests;
use rhai::{Dynamic, EvalAltResult, FnPtr, NativeCallContext, Position};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender};
use std::sync::{Arc, Mutex, PoisonError};

pub type RhaiResult<T> = Result<T, Box<EvalAltResult>>;

pub struct Bridge {
    to_session: Mutex<Sender<ToSession>>,
    from_session: Mutex<Receiver<ToScript>>,
    pub dictionary: Arc<Dictionary>,
    /// Each named drive's dictionary (`//! drives:`); empty for a script with one drive.
    pub drives: Vec<(String, Arc<Dictionary>)>,
    /// `--set` parameters.
    pub params: Vec<(String, String)>,
    stop: Arc<StopRequests>,
    clock: SharedClock,
    /// The script's `finally` runs: only a second stop request ends it.
    pub in_finally: AtomicBool,
    /// Why the script must end whatever it does, when it must.
    ending: Mutex<Option<Stop>>,
    /// The last drive error handed to the script as a catchable error, to tell it apart
    /// from the script's own errors when the script does not catch it.
    last_error: Mutex<Option<(String, Stop)>>,
    /// An error the `wait_until` condition raised, with the condition's own place.
    condition_error: Mutex<Option<Box<EvalAltResult>>>,
    operations: AtomicU64,
    operations_at_call: AtomicU64,
    /// The CSV files `sample` was given, for the sandbox's limit on how many.
    csv_files: Mutex<HashSet<PathBuf>>,
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A copy of a stop (it carries only text).
pub fn copy(stop: &Stop) -> Stop {
    match stop {
        Stop::Failed(m) => Stop::Failed(m.clone()),
        Stop::Unanswered(m) => Stop::Unanswered(m.clone()),
        Stop::OtherUnit(m) => Stop::OtherUnit(m.clone()),
        Stop::StoppedOnFailure(m) => Stop::StoppedOnFailure(m.clone()),
        Stop::Fault(m) => Stop::Fault(m.clone()),
        Stop::LinkLost(m) => Stop::LinkLost(m.clone()),
        Stop::Error(m) => Stop::Error(m.clone()),
        Stop::Interrupted => Stop::Interrupted,
        Stop::Panicked(m) => Stop::Panicked(m.clone()),
    }
}

/// A `wait_until` condition's error in one line, with the place it was raised (the run's
/// diagnostic shows it underlined).
fn condition_failed(e: &EvalAltResult) -> String {
    let mut inner = e;
    while let EvalAltResult::ErrorInFunctionCall(_, _, next, _) = inner {
        inner = next;
    }
    let text = match inner {
        EvalAltResult::ErrorRuntime(v, _) => v.to_string(),
        other => other.to_string(),
    };
    match (inner.position().line(), inner.position().position()) {
        (Some(line), Some(column)) if !text.contains("(line ") => {
            format!("the condition failed at line {line}, column {column}: {text}")
        }
        _ => format!("the condition failed: {text}"),
    }
}

/// Rhai's uncatchable end of a script.
fn terminated() -> Box<EvalAltResult> {
    Box::new(EvalAltResult::ErrorTerminated(Dynamic::UNIT, Position::NONE))
}

impl Bridge {
    /// The named drives' dictionaries, for a script with several drives.
    pub fn with_drives(mut self, drives: Vec<(String, Arc<Dictionary>)>) -> Self {
        self.drives = drives;
        self
    }

    pub fn new(
        to_session: Sender<ToSession>,
        from_session: Receiver<ToScript>,
        dictionary: Arc<Dictionary>,
        params: Vec<(String, String)>,
        stop: Arc<StopRequests>,
        clock: SharedClock,
    ) -> Self {
        Bridge {
            to_session: Mutex::new(to_session),
            from_session: Mutex::new(from_session),
            dictionary,
            drives: Vec::new(),
            params,
            stop,
            clock,
            in_finally: AtomicBool::new(false),
            ending: Mutex::new(None),
            last_error: Mutex::new(None),
            condition_error: Mutex::new(None),
            operations: AtomicU64::new(0),
            operations_at_call: AtomicU64::new(0),
            csv_files: Mutex::new(HashSet::new()),
        }
    }

    /// A bridge with no session behind it, for `check`: the drive API can be registered
    /// on it so that the names a script may call are known; a call through it answers
    /// that the session is gone (nothing is ever sent).
    pub fn detached(dictionary: Arc<Dictionary>) -> Self {
        let (to_session, _) = std::sync::mpsc::channel();
        let (_, from_session) = std::sync::mpsc::channel();
        Bridge::new(
            to_session,
            from_session,
            dictionary,
            Vec::new(),
            Arc::new(StopRequests::new()),
            crate::clock::RealClock::shared(),
        )
    }

    /// Rhai's progress hook, after every operation: `Some` ends the script. A stop request
    /// ends it (in `finally`, only a second one), and so does the operation limit.
    pub fn on_progress(&self, count: u64) -> Option<Dynamic> {
        self.operations.store(count, Ordering::Relaxed);
        let now = self.clock.now();
        if self.stop.pending_at(now) {
            let in_finally = self.in_finally.load(Ordering::Relaxed);
            if !in_finally || self.stop.count_at(now) >= 2 {
                self.end_with(Stop::Interrupted);
                return Some(Dynamic::UNIT);
            }
        }
        let since = count.saturating_sub(self.operations_at_call.load(Ordering::Relaxed));
        if since > super::sandbox::MAX_OPERATIONS_BETWEEN_CALLS {
            self.end_with(Stop::Error(format!(
                "the script ran {} operations without calling the drive (an endless loop?); the sandbox stops a script there",
                super::sandbox::MAX_OPERATIONS_BETWEEN_CALLS
            )));
            return Some(Dynamic::UNIT);
        }
        None
    }

    /// Counts a CSV file `sample` writes; refused beyond the sandbox's limit of files per
    /// run (a script computes its names, so a loop could otherwise fill a directory).
    pub fn csv_file(&self, path: &Path) -> Result<(), TooManyCsvFiles> {
        let mut files = lock(&self.csv_files);
        if !files.contains(path) && files.len() >= super::sandbox::MAX_CSV_FILES {
            return Err(TooManyCsvFiles {
                path: path.to_path_buf(),
            });
        }
        files.insert(path.to_path_buf());
        Ok(())
    }

    /// The script's `finally` starts a new count (Rhai counts each evaluation from zero).
    pub fn reset_operations(&self) {
        self.operations.store(0, Ordering::Relaxed);
        self.operations_at_call.store(0, Ordering::Relaxed);
    }

    /// Notes why the script must end (the first reason wins).
    pub fn end_with(&self, stop: Stop) {
        let mut ending = lock(&self.ending);
        if ending.is_none() {
            *ending = Some(stop);
        }
    }

    /// Why the script was ended, if it was.
    pub fn take_ending(&self) -> Option<Stop> {
        lock(&self.ending).take()
    }

    /// The drive error behind an uncaught Rhai error with this text, if it was one.
    pub fn drive_error(&self, text: &str) -> Option<Stop> {
        lock(&self.last_error)
            .as_ref()
            .filter(|(m, _)| m == text)
            .map(|(_, s)| copy(s))
    }

    pub fn send(&self, message: ToSession) {
        let _ = lock(&self.to_session).send(message);
    }

    /// Waits for the session thread; `None` when it has gone.
    pub fn receive(&self) -> Option<ToScript> {
        lock(&self.from_session).recv().ok()
    }

    /// Performs `call` (made at `pos`) on the session thread and waits for its answer.
    pub fn call(&self, pos: Position, call: Call, label: String) -> RhaiResult<Answer> {
        self.exchange(pos, call, label, None)
    }

    /// `wait_until`: the session polls, the script's `condition` judges each value.
    pub fn wait(
        &self,
        ctx: &NativeCallContext,
        call: Call,
        label: String,
        condition: &FnPtr,
    ) -> RhaiResult<Answer> {
        self.exchange(ctx.call_position(), call, label, Some((ctx, condition)))
    }

    fn exchange(
        &self,
        pos: Position,
        call: Call,
        label: String,
        condition: Option<(&NativeCallContext, &FnPtr)>,
    ) -> RhaiResult<Answer> {
        self.operations_at_call
            .store(self.operations.load(Ordering::Relaxed), Ordering::Relaxed);
        self.send(ToSession::Request(Request {
            call,
            label,
            line: pos.line().unwrap_or(0),
            column: pos.position().unwrap_or(0),
        }));
        loop {
            match self.receive() {
                Some(ToScript::Answer(Ok(answer))) => return Ok(answer),
                Some(ToScript::Answer(Err(stop))) => return Err(self.raise(stop)),
                Some(ToScript::Ask(value)) => {
                    let holds = match condition {
                        Some((ctx, f)) => self.judge(ctx, f, value),
                        None => Err(Stop::Error("the session asked a call without a condition".into())),
                    };
                    self.send(ToSession::Holds(holds));
                }
                Some(ToScript::RunFinally | ToScript::Finish) | None => {
                    self.end_with(Stop::Error(
                        "the run ended while the script waited for the drive".into(),
                    ));
                    return Err(terminated());
                }
            }
        }
    }

    fn judge(&self, ctx: &NativeCallContext, f: &FnPtr, value: f64) -> Result<bool, Stop> {
        match f.call_within_context::<Dynamic>(ctx, (value,)) {
            Ok(v) => v
                .as_bool()
                .map_err(|t| Stop::Error(format!("the wait_until condition gave {t}, not true or false"))),
            Err(e) => {
                let stop = match *e {
                    EvalAltResult::ErrorTerminated(..) => self.take_ending().unwrap_or(Stop::Interrupted),
                    _ => Stop::Error(condition_failed(&e)),
                };
                *lock(&self.condition_error) = Some(e);
                self.end_with(copy(&stop));
                Err(stop)
            }
        }
    }

    /// A failed call as a Rhai error: uncatchable for what must end the script.
    fn raise(&self, stop: Stop) -> Box<EvalAltResult> {
        if let Some(original) = lock(&self.condition_error).take() {
            // The condition's own error, with its place in the script.
            return original;
        }
        match stop {
            Stop::Interrupted | Stop::LinkLost(_) | Stop::Panicked(_) | Stop::StoppedOnFailure(_) => {
                self.end_with(stop);
                terminated()
            }
            Stop::Failed(ref m)
            | Stop::Unanswered(ref m)
            | Stop::OtherUnit(ref m)
            | Stop::Fault(ref m)
            | Stop::Error(ref m) => {
                let text = m.clone();
                *lock(&self.last_error) = Some((text.clone(), stop));
                Box::new(EvalAltResult::ErrorRuntime(text.into(), Position::NONE))
            }
        }
    }

    /// `fail("message")`: the run failed; recorded as a step, then the script ends.
    pub fn fail(&self, ctx: &NativeCallContext, message: String) -> Box<EvalAltResult> {
        let label = "fail".to_string();
        match self.call(ctx.call_position(), Call::Fail(message.clone()), label) {
            Err(e) if matches!(*e, EvalAltResult::ErrorTerminated(..)) => e,
            _ => {
                self.end_with(Stop::Failed(message));
                terminated()
            }
        }
    }
}

/// A `sample` CSV file beyond the sandbox's limit of files per run.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("sample: a script may write at most {max} CSV files; {} would be one more", path.display(), max = super::sandbox::MAX_CSV_FILES)]
pub struct TooManyCsvFiles {
    pub path: PathBuf,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::VirtualClock;
    use crate::stop_request::StopSignal;
    use std::sync::mpsc::channel;

    fn bridge(stop: Arc<StopRequests>) -> Bridge {
        let (tx, _) = channel();
        let (_, rx) = channel();
        let dictionary = std::sync::Arc::new(
            crate::family::Registry::builtin()
                .load_dictionary("sd2")
                .expect("dictionary"),
        );
        Bridge::new(tx, rx, dictionary, Vec::new(), stop, VirtualClock::shared())
    }

    #[test]
    fn a_stop_request_ends_the_script_and_in_finally_only_a_second_one() {
        let stop = Arc::new(StopRequests::new());
        let b = bridge(stop.clone());
        assert!(b.on_progress(1).is_none());
        stop.request(StopSignal::INT);
        assert!(b.on_progress(2).is_some());
        assert!(matches!(b.take_ending(), Some(Stop::Interrupted)));
        b.in_finally.store(true, Ordering::Relaxed);
        stop.acknowledge();
        assert!(
            b.on_progress(3).is_none(),
            "the first request is the safe stop's own"
        );
        stop.request(StopSignal::INT);
        assert!(b.on_progress(4).is_some());
    }

    #[test]
    fn a_script_writes_a_bounded_number_of_csv_files() {
        let b = bridge(Arc::new(StopRequests::new()));
        let limit = super::super::sandbox::MAX_CSV_FILES;
        for i in 0..limit {
            assert!(b.csv_file(Path::new(&format!("f{i}.csv"))).is_ok());
        }
        // The same file again is no new file.
        assert!(b.csv_file(Path::new("f0.csv")).is_ok());
        let e = b.csv_file(Path::new("one-more.csv")).unwrap_err().to_string();
        assert_eq!(
            e,
            format!("sample: a script may write at most {limit} CSV files; one-more.csv would be one more")
        );
    }

    #[test]
    fn the_operation_limit_counts_from_the_last_drive_call() {
        let b = bridge(Arc::new(StopRequests::new()));
        let limit = super::super::sandbox::MAX_OPERATIONS_BETWEEN_CALLS;
        assert!(b.on_progress(limit).is_none());
        b.operations_at_call.store(limit, Ordering::Relaxed);
        assert!(b.on_progress(2 * limit).is_none());
        assert!(b.on_progress(2 * limit + 1).is_some());
        assert!(matches!(b.take_ending(), Some(Stop::Error(m)) if m.contains("endless loop")));
    }
}
