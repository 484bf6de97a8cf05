//! What every run (recipe or script, one drive or several) sets up around the session,
//! one way each: the telegram observers (`--trace`, `-v`), the `--csv` recorder, the
//! placeholder reports that replace an earlier run's at once, the console or live progress
//! and the observers list, and the JUnit and HTML reports at the end. Must not open a
//! drive or decide exit codes.

use super::locked_observer::LockedObserver;
use super::{ConnectionArgs, OutputArgs, RunError, SharedObserver};
use crate::dictionary::Dictionary;
use crate::family::Family;
use crate::link::{Direction, TelegramObserver};
use crate::report::{
    color_wanted, html_unfinished, junit_unfinished, write_html, write_junit, write_unfinished,
    ConsoleReporter, CsvRecorder, ProgressReporter, TelegramFanOut, TraceHeader, TraceWriter,
};
use crate::session::PlannedCheck;
use crate::session::{ObjectRef, Observers, RunReport};
use std::io::Write;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// The `--trace` file (with `header` at its top) and `-v` lines, explaining the telegrams
/// of `family` with `dictionary`.
pub fn telegram_outputs(
    outputs: &OutputArgs,
    family: &dyn Family,
    dictionary: &Arc<Dictionary>,
    header: &TraceHeader,
) -> Result<TelegramFanOut, RunError> {
    let mut telegrams = TelegramFanOut::new();
    let frames = family.bus_kind() == crate::bus::BusKind::Frames;
    if let Some(path) = &outputs.trace {
        let t = TraceWriter::create(path, header, frames, family.explainer(dictionary.clone()))
            .map_err(|e| RunError::Invalid(format!("error: {e}")))?;
        telegrams.push(Box::new(t));
    }
    if outputs.verbose {
        telegrams.push(Box::new(TraceWriter::new(
            std::io::stderr(),
            family.explainer(dictionary.clone()),
        )));
    }
    Ok(telegrams)
}

/// What a trace says about the run it records, so that `decode` explains it without
/// flags: the dictionary (and `--dictionary` files, as absolute paths), `address` and the
/// line `connection` opens.
pub fn trace_header(
    family: &dyn Family,
    dictionary: &Dictionary,
    extra: &[std::path::PathBuf],
    connection: &ConnectionArgs,
    address: String,
) -> TraceHeader {
    TraceHeader {
        drive: dictionary.name().to_string(),
        dictionaries: extra
            .iter()
            .map(|p| std::fs::canonicalize(p).unwrap_or_else(|_| p.clone()))
            .collect(),
        address,
        line: connection.line_text(family),
        pole_pairs: dictionary.pole_pairs().map(|p| p.count),
    }
}

/// One trace shared by the links of several drives: each drive's link gets a tap that
/// writes into it, a line at a time, and says which drive the telegrams that follow are
/// of whenever the drive changes (`-- drive `left``).
#[derive(Clone)]
pub struct SharedTelegrams(Arc<Mutex<(TelegramFanOut, String)>>);

impl SharedTelegrams {
    pub fn new(telegrams: TelegramFanOut) -> Self {
        SharedTelegrams(Arc::new(Mutex::new((telegrams, String::new()))))
    }

    /// The observer of the drive called `name`, or `None` when nothing is traced.
    pub fn tap(&self, name: &str) -> Option<Box<dyn TelegramObserver>> {
        let empty = self.0.lock().unwrap_or_else(PoisonError::into_inner).0.is_empty();
        (!empty).then(|| {
            Box::new(Tap {
                shared: self.clone(),
                name: name.to_string(),
            }) as Box<dyn TelegramObserver>
        })
    }
}

struct Tap {
    shared: SharedTelegrams,
    name: String,
}

impl Tap {
    fn with(&self, at: Duration, f: impl FnOnce(&mut TelegramFanOut)) {
        let mut guard = self.shared.0.lock().unwrap_or_else(PoisonError::into_inner);
        let (telegrams, last) = &mut *guard;
        if *last != self.name {
            telegrams.event(at, &format!("drive `{}`", self.name));
            last.clone_from(&self.name);
        }
        f(telegrams);
    }
}

impl TelegramObserver for Tap {
    fn telegram(&mut self, at: Duration, direction: Direction, bytes: &[u8]) {
        self.with(at, |t| t.telegram(at, direction, bytes));
    }

    fn event(&mut self, at: Duration, text: &str) {
        self.with(at, |t| t.event(at, text));
    }

    fn frame(&mut self, at: Duration, direction: Direction, frame: &crate::bus::CanFrame) {
        self.with(at, |t| t.frame(at, direction, frame));
    }
}

/// The `--csv` recorder (`wide`: its columns; `drives`: a run with several drives, whose
/// long layout has a `drive` column), when asked for.
pub fn open_csv(
    outputs: &OutputArgs,
    wide: Option<&[ObjectRef]>,
    drives: bool,
) -> Result<Option<CsvRecorder>, RunError> {
    match &outputs.csv {
        Some(path) => CsvRecorder::create_for(path, wide, drives)
            .map(Some)
            .map_err(|e| RunError::Invalid(format!("error: {e}"))),
        None => Ok(None),
    }
}

/// A report left from an earlier run is replaced at once by one that says this run has
/// not finished: a run killed beyond any safe stop (SIGKILL, power loss) must never leave
/// an old PASS for CI to read.
pub fn write_placeholders(outputs: &OutputArgs, name: &str, path: &str) -> Result<(), RunError> {
    let placeholders = [
        outputs
            .junit
            .as_ref()
            .map(|p| write_unfinished(junit_unfinished, name, path, p)),
        outputs
            .report
            .as_ref()
            .map(|p| write_unfinished(html_unfinished, name, path, p)),
    ];
    match placeholders.into_iter().flatten().find_map(Result::err) {
        Some(e) => Err(RunError::Invalid(format!("error: {e}"))),
        None => Ok(()),
    }
}

/// How the console shows a run.
pub struct Look {
    pub virtual_time: bool,
    /// A live bar (on a terminal, not quiet, not under -v lines).
    pub live: bool,
    pub color: bool,
    /// The longest the run can take, for the bar (recipes know it).
    pub planned: Option<Duration>,
    /// `-v` writes telegram lines to standard error as they happen; step lines then go out
    /// at once too, so a merged log keeps them in order.
    pub verbose: bool,
    /// `--quiet`: only failures, the drive's end state and the verdict.
    pub quiet: bool,
}

impl Look {
    /// The look a run with `outputs` gets on standard output (`terminal`: is it one).
    pub fn of(
        outputs: &OutputArgs,
        terminal: bool,
        virtual_time: bool,
        colored: bool,
        planned: Option<Duration>,
    ) -> Look {
        Look {
            virtual_time,
            live: terminal && !outputs.quiet && !outputs.no_progress && !outputs.verbose,
            color: colored && color_wanted(outputs.color.choice(), terminal),
            planned,
            verbose: outputs.verbose,
            quiet: outputs.quiet,
        }
    }
}

/// Runs `run` with the console (or the live bar) and the CSV recorder observing it.
pub fn observed(
    out: &mut dyn Write,
    look: &Look,
    csv: Option<&mut CsvRecorder>,
    shared: &[SharedObserver],
    run: impl FnOnce(&mut Observers) -> RunReport,
) -> RunReport {
    let mut console = ConsoleReporter::new(&mut *out, look.virtual_time)
        .with_color(look.color)
        .holding(!look.verbose)
        .quiet(look.quiet);
    let mut progress = look.live.then(|| {
        let p = ProgressReporter::stdout(look.virtual_time).with_color(look.color);
        match look.planned {
            Some(t) => p.with_planned(t),
            None => p,
        }
    });
    let mut observers = Observers::default();
    match progress.as_mut() {
        Some(p) => observers.push(p),
        None => observers.push(&mut console),
    }
    if let Some(c) = csv {
        observers.push(c);
    }
    let mut shared: Vec<LockedObserver> = shared.iter().map(|o| LockedObserver::new(o.as_ref())).collect();
    for o in shared.iter_mut() {
        observers.push(o);
    }
    run(&mut observers)
}

/// After the run: a CSV write error as a warning, then the JUnit and HTML reports.
pub fn finish_reports(
    report: &RunReport,
    planned: &[PlannedCheck],
    csv: Option<&CsvRecorder>,
    outputs: &OutputArgs,
    err: &mut dyn Write,
) {
    if let Some(e) = csv.and_then(|c| c.error()) {
        let _ = writeln!(err, "warning: {e}");
    }
    if let Some(path) = &outputs.junit {
        if let Err(e) = write_junit(report, planned, path) {
            let _ = writeln!(err, "error: {e}");
        }
    }
    if let Some(path) = &outputs.report {
        if let Err(e) = write_html(report, path) {
            let _ = writeln!(err, "error: {e}");
        }
    }
}
