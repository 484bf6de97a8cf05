//! Runs a checked script against a drive: the script on a thread of its own in the
//! sandboxed engine, every drive call performed here by the [`Session`] (so the reports,
//! the fault watching and the safe stop are those of recipes), and at the end the
//! session's safe stop with the script's `fn finally(d)` in place of the default finally
//! when it has one. Each drive call that is a step is numbered `LINE.PASS` (the script
//! line, and how often that line has run), so loops keep the report bounded like a
//! recipe's repeat. It must not touch the drive other than through the session.

use super::bridge::{copy as copy_stop, Bridge};
use super::drive_api::{register, DriveHandle};
use super::exchange::{Answer, Call, Ending, Request, ToScript, ToSession};
use super::sample_tap::{Capture, Tap};
use super::sandbox::sandbox;
use super::script::Script;
use super::script_error::{eval_error, span_at};
use crate::diag::{Diagnostic, Diagnostics, Source};
use crate::drive::Drive;
use crate::session::{
    CheckResult, Operator, RunInfo, RunObserver, RunReport, SafeStopSettings, Session, StepInfo, StepOrigin,
    Stop, UnitIdentity,
};
use crate::stop_request::StopRequests;
use rhai::{CallFnOptions, Dynamic, Engine, EvalAltResult, Scope, AST};
use std::cell::RefCell;
use std::collections::HashMap;
use std::io::Write;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::rc::Rc;
use std::sync::atomic::Ordering;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Arc;

pub struct ScriptRunner<'a> {
    /// The one drive (unnamed), or the script's named drives.
    drives: Vec<(String, &'a mut Drive)>,
    observer: &'a mut dyn RunObserver,
    stop: Arc<StopRequests>,
    settings: SafeStopSettings,
    output_dir: PathBuf,
    csv_wide: bool,
    unit: UnitIdentity,
    operator: Option<Box<dyn Operator + 'a>>,
    history: Option<Arc<dyn crate::session::History>>,
}

impl<'a> ScriptRunner<'a> {
    /// A runner for a script with `//! drives:`: each drive under its name (all on one
    /// clock); `drive("left")` in the script is that drive.
    pub fn with_drives(
        drives: Vec<(String, &'a mut Drive)>,
        observer: &'a mut dyn RunObserver,
        stop: Arc<StopRequests>,
    ) -> Self {
        ScriptRunner {
            drives,
            observer,
            stop,
            settings: SafeStopSettings::default(),
            output_dir: PathBuf::from("."),
            csv_wide: false,
            unit: UnitIdentity::default(),
            operator: None,
            history: None,
        }
    }

    /// How the safe stop waits for standstill and how long it tries to reopen a lost port.
    pub fn with_settings(mut self, settings: SafeStopSettings) -> Self {
        self.settings = settings;
        self
    }

    /// The unit under test as known at the start, and where the answers to the script's
    /// operator calls come from.
    pub fn with_operator(mut self, unit: UnitIdentity, operator: Box<dyn Operator + 'a>) -> Self {
        self.unit = unit;
        self.operator = Some(operator);
        self
    }

    /// Where the unit's past runs are read, for `expect_compared_with_last_pass`.
    pub fn with_history(mut self, history: Option<Arc<dyn crate::session::History>>) -> Self {
        self.history = history;
        self
    }

    /// Where files the session writes go (relative paths).
    pub fn with_output_dir(mut self, dir: PathBuf) -> Self {
        self.output_dir = dir;
        self
    }

    /// The `csv:` files of `sample` with one column per object (`--csv-wide`).
    pub fn with_csv_wide(mut self, wide: bool) -> Self {
        self.csv_wide = wide;
        self
    }

    /// Runs the script to the end, whatever happens, and returns what happened. A script
    /// error is written to `errors` (file:line:column, underlined) when it happens, before
    /// the safe stop.
    pub fn run(self, script: &Script, errors: &mut dyn Write) -> RunReport {
        let dictionary = self.drives[0].1.dictionary().clone();
        let clock = self.drives[0].1.clock().clone();
        let named: Vec<(String, Arc<crate::dictionary::Dictionary>)> = self
            .drives
            .iter()
            .filter(|(n, _)| !n.is_empty())
            .map(|(n, d)| (n.clone(), d.dictionary().clone()))
            .collect();
        let capture = Rc::new(RefCell::new(Capture::default()));
        let mut tap = Tap {
            inner: self.observer,
            capture: capture.clone(),
        };
        let info = RunInfo {
            kind: "script",
            name: script.name.clone(),
            path: script.path.clone(),
            params: script.params.clone(),
            unit: self.unit.clone(),
            text_sha256: None,
        };
        let (to_session, from_script) = channel();
        let (to_script, from_session) = channel();
        let bridge = Arc::new(
            Bridge::new(
                to_session,
                from_session,
                dictionary,
                script.params.clone(),
                self.stop.clone(),
                clock,
            )
            .with_drives(named),
        );
        let mut engine = sandbox();
        register(&mut engine, &bridge);
        let stop = self.stop.clone();
        let mut session = Session::with_drives(self.drives, &mut tap, &stop, info)
            .with_settings(self.settings)
            .with_output_dir(self.output_dir)
            .with_csv_wide(self.csv_wide)
            .with_history(self.history, Vec::new());
        if let Some(operator) = self.operator {
            session = session.with_operator(operator);
        }
        let mut host = Host {
            from_script,
            to_script,
            capture,
            passes: HashMap::new(),
            finally_steps: 0,
            path: script.path.clone(),
            errors,
        };
        std::thread::scope(|scope| {
            let worker = {
                let (ast, source, bridge) = (script.ast.clone(), script.source.clone(), bridge.clone());
                std::thread::Builder::new()
                    .name("script".into())
                    .spawn_scoped(scope, move || script_thread(engine, ast, source, bridge))
            };
            session.begin();
            let ended = match &worker {
                Ok(_) => host.serve(&mut session, "steps"),
                Err(e) => Some(Stop::Error(format!("the script could not start: {e}"))),
            };
            let mut finally = |s: &mut Session| host.finally(s);
            let finally: Option<&mut dyn FnMut(&mut Session)> =
                (script.has_finally && worker.is_ok()).then_some(&mut finally);
            let report = session.end(ended, script.leave_enabled, None, finally);
            let _ = host.to_script.send(ToScript::Finish);
            if let Ok(w) = worker {
                let _ = w.join();
            }
            report
        })
    }
}

/// The refusal of a drive call made inside a `wait_until` condition.
const CONDITION_CALLS_THE_DRIVE: &str = "a wait_until condition must not call the drive: it judges the value it is given; read any other value before the wait";

/// The session thread's side: performs the script's requests.
struct Host<'e> {
    from_script: Receiver<ToSession>,
    to_script: Sender<ToScript>,
    capture: Rc<RefCell<Capture>>,
    /// How often each script line made a step.
    passes: HashMap<usize, u32>,
    finally_steps: u32,
    path: String,
    errors: &'e mut dyn Write,
}

impl Host<'_> {
    /// Performs requests until the script (or its `finally`) ends; why it ended early.
    fn serve(&mut self, s: &mut Session, phase: &'static str) -> Option<Stop> {
        loop {
            match self.from_script.recv() {
                Err(_) => return Some(Stop::Panicked("the script thread ended without a word".into())),
                Ok(ToSession::Ended(Ending::Completed)) => return None,
                Ok(ToSession::Ended(Ending::Stopped(stop, diagnostic))) => {
                    if let Some(d) = diagnostic {
                        let rendered = Diagnostics::from_iter([*d]).render(false);
                        let _ = self.errors.write_all(rendered.as_bytes());
                        let _ = self.errors.flush();
                    }
                    return Some(stop);
                }
                Ok(ToSession::Holds(_)) => {}
                Ok(ToSession::Request(r)) => {
                    let answer = self.perform(s, r, phase);
                    if self.to_script.send(ToScript::Answer(answer)).is_err() {
                        return Some(Stop::Panicked("the script thread ended without a word".into()));
                    }
                }
            }
        }
    }

    /// The script's `fn finally(d)`, in place of the default finally.
    fn finally(&mut self, s: &mut Session) {
        if self.to_script.send(ToScript::RunFinally).is_err() {
            s.note("the script's finally could not run: the script thread has ended".into());
            return;
        }
        match self.serve(s, "finally") {
            None => {}
            Some(Stop::Interrupted) => s.note("finally abandoned (a second stop request)".into()),
            Some(stop) => {
                let (_, why) = crate::session::outcome(&Err(stop));
                s.note(format!("the script's finally ended early: {why}"));
            }
        }
    }

    fn perform(&mut self, s: &mut Session, r: Request, phase: &'static str) -> Result<Answer, Stop> {
        if let Call::Message(text) = &r.call {
            s.message(text);
            return Ok(Answer::Done);
        }
        if phase == "steps" && s.interrupted() {
            return Err(Stop::Interrupted);
        }
        match r.call {
            Call::Read(object) => return s.read_number(&object).map(Answer::Number),
            Call::State(drive) => {
                if let Some(d) = &drive {
                    s.select(d)?;
                }
                return s.state().map(Answer::State);
            }
            Call::Watch(watch) if phase == "steps" => {
                let origin = StepOrigin {
                    path: self.path.clone(),
                    line: r.line,
                    column: r.column,
                };
                s.watch_from_here(crate::session::Watch { origin, ..*watch })?;
                // The first reading is now: a limit already crossed ends the run here.
                return s.watch_fault(false).map(|_| Answer::Done);
            }
            // The steps are over: a watch holds for them, not for the script's finally.
            Call::Watch(_) => return Ok(Answer::Done),
            _ => {}
        }
        let number = match phase {
            "steps" => {
                let pass = self.passes.entry(r.line).or_insert(0);
                *pass += 1;
                match *pass {
                    1 => r.line.to_string(),
                    n => format!("{}.{n}", r.line),
                }
            }
            _ => {
                self.finally_steps += 1;
                format!("{phase}.{}", self.finally_steps)
            }
        };
        let origin = StepOrigin {
            path: self.path.clone(),
            line: r.line,
            column: r.column,
        };
        let info = StepInfo {
            number: number.clone(),
            label: r.label,
            origin: origin.clone(),
            phase,
            container: false,
        };
        let mut answer = Answer::Done;
        let call = r.call;
        let mark = s.check_mark();
        let result = s.perform(&info, |s| self.exec(s, call, &origin, &number, &mut answer));
        // `run -x`: a failed check (a wait that timed out included) ends the script, and no
        // `catch` in it goes on from there.
        let failed = match &result {
            Ok(_) | Err(Stop::Failed(_)) if phase == "steps" && s.stops_on_failure() => {
                s.failed_check_since(mark)
            }
            _ => None,
        };
        if let Some(check) = failed {
            return Err(s.stop_on_failure(&check, &number, "run --stop-on-failure"));
        }
        match result {
            Ok(_) if phase == "steps" => s.watch_fault(false).map(|_| answer),
            Ok(_) => Ok(answer),
            Err(e) => {
                if let Stop::Fault(_) = e {
                    // The session learns the drive is in fault, so that a script that
                    // catches the fault and resets it is not told of it again.
                    let _ = s.watch_fault(true);
                }
                if phase != "steps" {
                    let (_, why) = crate::session::outcome(&Err(copy_stop(&e)));
                    s.note(format!("{phase} step {number} ({}) failed: {why}", info.label));
                }
                Err(e)
            }
        }
    }

    fn exec(
        &self,
        s: &mut Session,
        call: Call,
        origin: &StepOrigin,
        number: &str,
        answer: &mut Answer,
    ) -> Result<String, Stop> {
        match call {
            Call::Command(c, None) => s.command_all(c),
            Call::Command(c, Some(d)) => s.command_on(&d, c),
            Call::GoTo(state, timeout, None) => s.go_to_all(state, timeout),
            Call::GoTo(state, timeout, Some(d)) => s.go_to_on(&d, state, timeout),
            Call::Set(object, value) => s.set(&[(object, value)]),
            Call::WaitUntil {
                object,
                timeout,
                every,
            } => {
                let what = format!("{} meets the script's condition", object.name);
                s.wait_until_value(
                    &object,
                    &what,
                    &mut |v| self.ask(v),
                    timeout,
                    every,
                    origin,
                    number,
                )
            }
            Call::WaitStable {
                condition,
                timeout,
                every,
            } => s.wait_until(&condition, timeout, every, origin, number),
            Call::CoastDown(c) => s.coast_down(&c, origin, number),
            Call::Dwell(d) => {
                s.dwell(d, number)?;
                Ok(format!("{} dwelt", crate::session::show_duration(d)))
            }
            Call::Sample(x) => {
                self.capture.borrow_mut().start(&x.objects);
                let result = s.sample(&x, &[], number);
                let windows = self.capture.borrow_mut().finish();
                *answer = Answer::Sampled(windows);
                result
            }
            Call::Expect(check) => {
                let check = CheckResult {
                    origin: origin.clone(),
                    ..*check
                };
                s.expect_result(check)
            }
            Call::CompareLastPass(c) => s.expect_compared_with_last_pass(&c.0, c.1, &c.2, origin),
            Call::Fail(message) => Err(Stop::Failed(message)),
            Call::Ask(prompt) => {
                let (detail, accepted) = s.ask(&prompt, origin, number)?;
                *answer = Answer::Asked(accepted);
                Ok(detail)
            }
            Call::Read(_) | Call::State(_) | Call::Message(_) | Call::Watch(_) => Ok(String::new()),
        }
    }

    /// Asks the script whether its `wait_until` condition holds for `value`.
    fn ask(&self, value: f64) -> Result<bool, Stop> {
        if self.to_script.send(ToScript::Ask(value)).is_err() {
            return Err(Stop::Panicked("the script thread ended without a word".into()));
        }
        loop {
            match self.from_script.recv() {
                Ok(ToSession::Holds(r)) => return r,
                Ok(ToSession::Request(_)) => {
                    // A call from inside the condition: conditions judge a value, they
                    // must not drive. Refused, and the wait ends with it.
                    let _ = self.to_script.send(ToScript::Answer(Err(Stop::Error(
                        CONDITION_CALLS_THE_DRIVE.into(),
                    ))));
                }
                Ok(ToSession::Ended(_)) | Err(_) => {
                    return Err(Stop::Panicked(
                        "the script thread ended during a wait_until".into(),
                    ))
                }
            }
        }
    }
}

/// Runs the script, then waits to run its `finally` or to finish.
fn script_thread(engine: Engine, ast: AST, source: Arc<Source>, bridge: Arc<Bridge>) {
    let mut scope = Scope::new();
    let result = catch_unwind(AssertUnwindSafe(|| engine.run_ast_with_scope(&mut scope, &ast)));
    bridge.send(ToSession::Ended(ending(&bridge, &source, result)));
    loop {
        match bridge.receive() {
            Some(ToScript::RunFinally) => {
                bridge.in_finally.store(true, Ordering::Relaxed);
                bridge.reset_operations();
                let _ = bridge.take_ending();
                let options = CallFnOptions::new().eval_ast(false).rewind_scope(true);
                let result = catch_unwind(AssertUnwindSafe(|| {
                    engine
                        .call_fn_with_options::<Dynamic>(
                            options,
                            &mut scope,
                            &ast,
                            "finally",
                            (DriveHandle::default(),),
                        )
                        .map(|_| ())
                }));
                bridge.send(ToSession::Ended(ending(&bridge, &source, result)));
            }
            Some(ToScript::Finish) | None => return,
            Some(ToScript::Answer(_) | ToScript::Ask(_)) => {}
        }
    }
}

/// How a run of the script (or of its `finally`) ended.
fn ending(
    bridge: &Bridge,
    source: &Arc<Source>,
    result: std::thread::Result<Result<(), Box<EvalAltResult>>>,
) -> Ending {
    let e = match result {
        Ok(Ok(())) => return Ending::Completed,
        Ok(Err(e)) => e,
        Err(payload) => {
            let text = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            return Ending::Stopped(Stop::Panicked(text), None);
        }
    };
    let mut inner = e.as_ref();
    // Where the innermost script function was called: the place to show when the error
    // inside it has none of its own.
    let mut called_at = rhai::Position::NONE;
    while let EvalAltResult::ErrorInFunctionCall(_, _, next, pos) = inner {
        if !pos.is_none() {
            called_at = *pos;
        }
        inner = next;
    }
    match inner {
        EvalAltResult::Exit(..) => Ending::Completed,
        EvalAltResult::ErrorTerminated(_, pos) => match bridge.take_ending().unwrap_or(Stop::Interrupted) {
            // The sandbox's operation limit: a problem of the script, at its place.
            Stop::Error(m) => {
                let pos = if pos.is_none() { called_at } else { *pos };
                let span = span_at(source, pos).or_else(|| finally_span(bridge, source));
                let d = match span {
                    Some(span) => Diagnostic::at(&span, m.clone(), "stopped here")
                        .with_help("a loop must call the drive (read, dwell, ...) or end"),
                    None => Diagnostic::unlocated(source.path(), m.clone()),
                };
                Ending::Stopped(Stop::Error(d.located()), Some(Box::new(d)))
            }
            stop => Ending::Stopped(stop, None),
        },
        EvalAltResult::ErrorRuntime(v, _) => {
            let d = eval_error(source, &e);
            match bridge.drive_error(&v.to_string()) {
                // The script's own mistake, not the drive's: said at its place.
                Some(Stop::Error(m)) if m == CONDITION_CALLS_THE_DRIVE => {
                    Ending::Stopped(Stop::Error(d.located()), Some(Box::new(d)))
                }
                Some(stop) => Ending::Stopped(stop, Some(Box::new(d))),
                None => Ending::Stopped(Stop::Error(d.located()), Some(Box::new(d))),
            }
        }
        _ => {
            let d = eval_error(source, &e);
            Ending::Stopped(Stop::Error(d.located()), Some(Box::new(d)))
        }
    }
}

/// The script's `fn finally` when it runs (Rhai gives no place for a function called
/// from outside the script).
fn finally_span(bridge: &Bridge, source: &Arc<Source>) -> Option<crate::diag::Span> {
    if !bridge.in_finally.load(Ordering::Relaxed) {
        return None;
    }
    let offset = source.text().find("fn finally")?;
    let index = super::literal_calls::LineIndex::new(source.text());
    Some(index.span(source, offset, "fn finally".len()))
}
