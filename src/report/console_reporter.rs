//! Plain console output of a run: one line per step with its number, what it did, ok/FAIL
//! and the values, one line per check, the safe stop, and a summary. Line-oriented so it
//! never garbles a log file. The line formats are pub functions so the live progress
//! display prints exactly the same permanent lines.

use crate::session::{number, with_unit, CheckResult, RunInfo, RunObserver, RunReport, StepInfo, StepRecord};
use std::io::Write;

pub struct ConsoleReporter<W: Write> {
    out: W,
    /// Whether the clock is virtual (said in the summary, since durations are simulated).
    virtual_time: bool,
    color: bool,
}

impl<W: Write> ConsoleReporter<W> {
    pub fn new(out: W, virtual_time: bool) -> Self {
        ConsoleReporter {
            out,
            virtual_time,
            color: false,
        }
    }

    /// PASS/FAIL and the verdict in colour (see [`super::color_wanted`]).
    pub fn with_color(mut self, color: bool) -> Self {
        self.color = color;
        self
    }

    pub fn into_inner(self) -> W {
        self.out
    }

    fn line(&mut self, text: &str) {
        // A closed pipe (`| head`) must not stop the run or its safe stop.
        let _ = if self.color {
            writeln!(self.out, "{}", super::paint(text))
        } else {
            writeln!(self.out, "{text}")
        };
        let _ = self.out.flush();
    }
}

impl<W: Write> RunObserver for ConsoleReporter<W> {
    fn run_started(&mut self, recipe: &RunInfo, drive: &str) {
        for line in header_lines(recipe, drive) {
            self.line(&line);
        }
    }

    fn step_started(&mut self, step: &StepInfo) {
        if let Some(line) = container_line(step) {
            self.line(&line);
        }
    }

    fn step_finished(&mut self, r: &StepRecord) {
        self.line(&step_line(r));
    }

    fn check(&mut self, c: &CheckResult) {
        if let Some(line) = check_line(c) {
            self.line(&line);
        }
    }

    fn message(&mut self, text: &str) {
        self.line(&message_line(text));
    }

    fn run_finished(&mut self, report: &RunReport) {
        for line in summary_lines(report, self.virtual_time) {
            self.line(&line);
        }
    }
}

/// `recipe  NAME (PATH)` (or `script`), `drive   DRIVE` and, when there are any,
/// `params  a = 1, b = 2`.
pub fn header_lines(run: &RunInfo, drive: &str) -> Vec<String> {
    let mut lines = vec![
        format!("{:<7} {} ({})", run.kind, run.name, run.path),
        format!("drive   {drive}"),
    ];
    if !run.params.is_empty() {
        let params = run
            .params
            .iter()
            .map(|(name, value)| format!("{name} = {value}"))
            .collect::<Vec<_>>()
            .join(", ");
        lines.push(format!("params  {params}"));
    }
    lines
}

/// The announcement of a container step (`repeat`, `include`), so its nested steps read in
/// order; `None` for every other step.
pub fn container_line(step: &StepInfo) -> Option<String> {
    if step.container {
        let number = if step.phase == "steps" {
            step.number.clone()
        } else {
            step.number.replace('.', " ")
        };
        Some(format!("{number:>6}  ...   {}", step.label))
    } else {
        None
    }
}

/// `     3  ok    switch_on  switched on`.
pub fn step_line(r: &StepRecord) -> String {
    let mark = if r.ok { "ok  " } else { "FAIL" };
    let number = if r.phase == "steps" {
        r.number.clone()
    } else {
        r.number.replace('.', " ")
    };
    let detail = if r.detail.is_empty() {
        String::new()
    } else {
        format!("  {}", r.detail)
    };
    format!("{number:>6}  {mark}  {}{detail}", r.label)
}

/// `        PASS  name: message (limits 5940 .. 6060 rpm)`; `None` for `wait until` checks,
/// whose step line already says it.
pub fn check_line(c: &CheckResult) -> Option<String> {
    if c.name.starts_with("wait until") {
        return None;
    }
    let mark = if c.passed { "PASS" } else { "FAIL" };
    let limits = match (c.low, c.high) {
        (Some(lo), Some(hi)) if lo == hi => format!(" (expected {})", with_unit(lo, c.unit.as_deref())),
        (Some(lo), Some(hi)) => {
            format!(" (limits {} .. {})", number(lo), with_unit(hi, c.unit.as_deref()))
        }
        (Some(lo), None) => format!(" (limit > {})", with_unit(lo, c.unit.as_deref())),
        (None, Some(hi)) => format!(" (limit < {})", with_unit(hi, c.unit.as_deref())),
        (None, None) => String::new(),
    };
    Some(format!("        {mark}  {}: {}{limits}", c.name, c.message))
}

/// A value read by `read`/`print`, or a message, indented under its step.
pub fn message_line(text: &str) -> String {
    format!("        {text}")
}

/// The safe-stop notes, the final state and the one-line verdict.
pub fn summary_lines(report: &RunReport, virtual_time: bool) -> Vec<String> {
    let mut lines = Vec::new();
    for note in &report.safe_stop {
        lines.push(format!("safe stop: {note}"));
    }
    lines.push(report.drive_left());
    if report.check_by_hand() {
        lines.push("CHECK THE DRIVE BY HAND: the safe stop could not be confirmed (see above)".to_string());
    }
    let steps = report
        .steps
        .iter()
        .filter(|s| s.phase == "steps" && !s.number.contains('.'))
        .count();
    let time = humantime::format_duration(std::time::Duration::from_millis(
        report.duration.as_millis() as u64
    ));
    let clock = if virtual_time { " of virtual time" } else { "" };
    let why = match report.verdict.reason() {
        Some(m) => format!(": {m}"),
        None => String::new(),
    };
    lines.push(format!(
        "{}{why} — {steps} step(s), {} check(s) passed, {} failed, {time}{clock}, exit code {}",
        report.verdict.word(),
        report.checks_passed(),
        report.checks_failed(),
        report.exit_code()
    ));
    lines
}
