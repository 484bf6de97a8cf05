//! The operator station's runs: one at a time, each on its own thread through the one run
//! pipeline (`run::run`) with the results store's recorder and the page's observer beside
//! the console, answered through the terminal's operator seam, stopped through the same
//! stop requests as Ctrl-C. What the page may ask of a run is here — start one of the
//! recipes given, answer the open question, press Stop — and nothing else: no path, recipe
//! text or command reaches it from the browser. Must not serve HTTP (the web layer does).

use super::event_log::EventLog;
use super::page_answers::{answer_channel, AnswerSender};
use super::page_observer::PageObserver;
use super::station_setup::StationSetup;
use super::station_view::{ResultView, RunView, StationView};
use crate::run::{self, outputs_for, outputs_named, RunRequest, RunResult, SharedObserver, TerminalInput};
use crate::session::{RunReport, Verdict};
use crate::stop_request::{StopRequests, StopSignal};
use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;

/// Why the page's request was refused, said to the operator as it is.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct Refused(pub String);

/// The run under way, as the station holds it.
struct Current {
    stop: Arc<StopRequests>,
    answers: AnswerSender,
    thread: JoinHandle<()>,
    /// The run's HTML report, once written.
    report: Option<PathBuf>,
    serial: String,
}

pub struct Station {
    setup: Arc<StationSetup>,
    log: Arc<EventLog>,
    current: Mutex<Option<Current>>,
    /// The last run's report and serial, kept for the result screen's links.
    last: Arc<Mutex<(Option<PathBuf>, Option<String>)>>,
    next_run: Mutex<u64>,
}

fn locked<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

impl Station {
    pub fn new(setup: StationSetup) -> Self {
        let view = StationView::new(setup.recipe_views(), setup.station_name());
        Station {
            setup: Arc::new(setup),
            log: Arc::new(EventLog::new(view)),
            current: Mutex::new(None),
            last: Arc::new(Mutex::new((None, None))),
            next_run: Mutex::new(1),
        }
    }

    pub fn log(&self) -> &Arc<EventLog> {
        &self.log
    }

    pub fn setup(&self) -> &StationSetup {
        &self.setup
    }

    /// Whether a run is under way (its thread has not ended).
    pub fn running(&self) -> bool {
        locked(&self.current)
            .as_ref()
            .is_some_and(|c| !c.thread.is_finished())
    }

    /// Starts recipe number `recipe` for the unit `serial`, answered by `operator`; refused,
    /// saying why, while a run is under way (one run per drive), while the station shuts
    /// down, or without a serial or an operator's name.
    pub fn start(&self, recipe: usize, serial: &str, operator: &str) -> Result<u64, Refused> {
        let serial = serial.trim();
        let operator = operator.trim();
        let Some(chosen) = self.setup.recipes.get(recipe) else {
            return Err(Refused(format!(
                "there is no recipe number {recipe}: this station runs {} recipe(s)",
                self.setup.recipes.len()
            )));
        };
        if serial.is_empty() {
            return Err(Refused("scan or type the unit's serial number first".into()));
        }
        let cli_operator = self.setup.options.operator.identity().operator;
        if operator.is_empty() && cli_operator.is_none() {
            return Err(Refused(
                "type your name in the operator field first: every answer is recorded with it".into(),
            ));
        }
        let mut current = locked(&self.current);
        if let Some(c) = current.as_ref().filter(|c| !c.thread.is_finished()) {
            let who = self.log.read(|v| {
                v.run
                    .as_ref()
                    .map(|r| format!("{} for unit {} (operator {})", r.recipe, r.serial, r.operator))
            });
            return Err(Refused(format!(
                "a run is under way on this drive ({}); one run per drive at a time — wait for its result, or press Stop",
                who.unwrap_or_else(|| format!("unit {}", c.serial))
            )));
        }
        if self.log.read(|v| v.closing) {
            return Err(Refused(
                "the station is shutting down (a stop signal): no new run starts".into(),
            ));
        }
        // The earlier run's thread has ended: its report is the last one now.
        if let Some(done) = current.take() {
            let _ = done.thread.join();
            *locked(&self.last) = (done.report, Some(done.serial));
        }
        let id = {
            let mut n = locked(&self.next_run);
            *n += 1;
            *n - 1
        };
        let operator = if operator.is_empty() {
            cli_operator.unwrap_or_default()
        } else {
            operator.to_string()
        };
        let view = RunView::new(
            id,
            &chosen.name,
            serial,
            &operator,
            chosen.planned.map(|d| d.as_secs_f64()),
        );
        self.log.change(|v| ((), Some(v.start(view))));
        let stop = Arc::new(StopRequests::new());
        let (answers, lines) = answer_channel();
        let job = RunJob {
            setup: self.setup.clone(),
            log: self.log.clone(),
            last: self.last.clone(),
            recipe,
            serial: serial.to_string(),
            operator,
            stop: stop.clone(),
            input: TerminalInput::typed_elsewhere(lines),
        };
        let thread = std::thread::Builder::new()
            .name(format!("station run {id}"))
            .spawn(move || job.run())
            .map_err(|e| Refused(format!("the run could not start: {e}")))?;
        *current = Some(Current {
            stop,
            answers,
            thread,
            report: None,
            serial: serial.to_string(),
        });
        Ok(id)
    }

    /// The page answers question `dialog` with `answer`: handed to the run as a typed
    /// line when it is the open question and no answer to it is being judged.
    pub fn answer(&self, dialog: u64, answer: &str) -> Result<(), Refused> {
        let current = locked(&self.current);
        let Some(c) = current.as_ref().filter(|c| !c.thread.is_finished()) else {
            return Err(Refused("no run is under way".into()));
        };
        self.log.change(|v| match v.answer(dialog) {
            Ok(event) => (Ok(()), Some(event)),
            Err(why) => (Err(Refused(why.into())), None),
        })?;
        if !c.answers.send(answer) {
            return Err(Refused("the run no longer reads answers".into()));
        }
        Ok(())
    }

    /// The Stop button: a stop request, as Ctrl-C; the second switches the power stage
    /// off at once, as a second signal does.
    pub fn stop(&self) -> Result<u32, Refused> {
        self.request_stop(StopSignal::STOP_BUTTON)
    }

    fn request_stop(&self, signal: StopSignal) -> Result<u32, Refused> {
        let current = locked(&self.current);
        let Some(c) = current.as_ref().filter(|c| !c.thread.is_finished()) else {
            return Err(Refused("no run is under way".into()));
        };
        c.stop.request(signal);
        Ok(self.log.change(|v| {
            let event = v.stop_pressed();
            (v.run.as_ref().map_or(0, |r| r.stops), event)
        }))
    }

    /// A stop signal to the station process (or its server failing): no new run starts,
    /// and the run under way gets the same stop request (each signal, so a second one
    /// switches the power stage off).
    pub fn shut_down(&self, signal: StopSignal) {
        self.log.change(|v| {
            let first = !v.closing;
            let event = v.close();
            ((), first.then_some(event))
        });
        let _ = self.request_stop(signal);
    }

    /// Waits for the run under way to end (after [`Self::shut_down`]).
    pub fn join(&self) {
        let taken = locked(&self.current).take();
        if let Some(c) = taken {
            let _ = c.thread.join();
        }
    }

    /// The last finished run's HTML report and its unit's serial.
    pub fn last_run(&self) -> (Option<PathBuf>, Option<String>) {
        locked(&self.last).clone()
    }
}

/// One run, on its own thread.
struct RunJob {
    setup: Arc<StationSetup>,
    log: Arc<EventLog>,
    last: Arc<Mutex<(Option<PathBuf>, Option<String>)>>,
    recipe: usize,
    serial: String,
    operator: String,
    stop: Arc<StopRequests>,
    input: Arc<TerminalInput>,
}

impl RunJob {
    fn run(self) {
        let options = &self.setup.options;
        let chosen = &self.setup.recipes[self.recipe];
        let mut operator = options.operator.clone();
        operator
            .unit
            .retain(|(part, _)| part != "serial" && part != "operator");
        operator.unit.push(("serial".into(), self.serial.clone()));
        operator.unit.push(("operator".into(), self.operator.clone()));
        let mut outputs = options.outputs.clone();
        // Every run writes its HTML report: the result screen links to it.
        if outputs.report.is_none() {
            outputs.report = Some(PathBuf::from("{serial}-{date}T{time}.html"));
        }
        let identity = operator.identity();
        let outputs = match outputs_named(&outputs, &identity, std::time::SystemTime::now()) {
            Ok(o) => o,
            Err(e) => return self.refused(&format!("{e}; nothing was sent")),
        };
        // The run writes where `run` would, under --output-dir.
        let placed = outputs_for(&outputs, &options.output_dir, None);
        let report_path = placed.report.clone();
        let files = [chosen.path.clone()];
        let page: SharedObserver = Arc::new(Mutex::new(PageObserver::new(
            self.log.clone(),
            chosen.prompts.clone(),
        )));
        let recorder = options.recorder(&files, &self.setup.registry, &outputs, self.stop.clone());
        let request = RunRequest {
            file: &chosen.path,
            input: Some(self.input.clone()),
            observers: recorder.into_iter().chain([page]).collect(),
            ..options.request(&self.setup.registry, &placed, &operator, self.stop.clone())
        };
        let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            run::run(&request, &mut std::io::stdout(), &mut std::io::stderr())
        }));
        let result = match ran {
            Ok(r) => r,
            Err(_) => {
                return self.refused(
                    "internal error (panic) in the run pipeline: see the station's standard error; check the drive by hand",
                )
            }
        };
        let report = report_path.filter(|p| p.is_file());
        let view = result_view(
            &result,
            report.is_some(),
            options.record.results.is_some() || !options.record.no_results,
        );
        *locked(&self.last) = (report, Some(self.serial.clone()));
        self.log.change(|v| ((), v.finish(view)));
    }

    /// The run never started: the result screen says why.
    fn refused(&self, why: &str) {
        let view = ResultView {
            word: "NOT RUN",
            verdict: "NOT RUN".into(),
            exit_code: run::INVALID,
            reason: Some(why.to_string()),
            failed: Vec::new(),
            end: Vec::new(),
            check_by_hand: false,
            report: false,
            certificate: false,
        };
        self.log.change(|v| ((), v.finish(view)));
    }
}

/// The result screen of a run: the verdict word (never better than the run's own
/// verdict, which already holds the drive's end state), what failed and how the drive
/// was left.
pub fn result_view(result: &RunResult, report: bool, store: bool) -> ResultView {
    let Some(r) = &result.report else {
        return ResultView {
            word: "NOT RUN",
            verdict: "NOT RUN".into(),
            exit_code: result.exit_code,
            reason: Some(format!(
                "the run did not start (exit code {}): see the station's log for why",
                result.exit_code
            )),
            failed: Vec::new(),
            end: Vec::new(),
            check_by_hand: false,
            report,
            certificate: false,
        };
    };
    ResultView {
        word: word(r),
        verdict: r.verdict.word().to_string(),
        exit_code: result.exit_code,
        reason: r.verdict.reason(),
        failed: failed(r),
        end: r.drive_left_lines(),
        check_by_hand: r.check_by_hand(),
        report,
        certificate: store && r.unit.serial.is_some(),
    }
}

fn word(r: &RunReport) -> &'static str {
    match r.verdict {
        Verdict::Passed if r.checks.iter().any(|c| c.marginal && !c.retried) => "MARGINAL",
        Verdict::Passed => "PASS",
        _ => "FAIL",
    }
}

/// Each failed check (the last attempt's) and failed step, one line each.
fn failed(r: &RunReport) -> Vec<String> {
    let mut lines: Vec<String> = r
        .checks
        .iter()
        .filter(|c| !c.passed && !c.retried)
        .map(|c| format!("{}: {}", c.name, c.message))
        .collect();
    lines.extend(
        r.steps
            .iter()
            .filter(|s| !s.ok)
            .map(|s| format!("step {} {}: {}", s.number, s.label, s.detail)),
    );
    lines.truncate(20);
    lines
}
