//! Plain console output of a run: one line per step with its number, what it did, ok/FAIL
//! and the values, one line per check, the safe stop, and a summary. Line-oriented so it
//! never garbles a log file. The line formats are pub functions so the live progress
//! display prints exactly the same permanent lines.

use super::OpenAttempts;
use crate::session::{
    number, with_unit, CheckResult, RunInfo, RunObserver, RunReport, StepInfo, StepRecord, UnitIdentity,
};
use std::io::Write;
use std::time::{Duration, Instant};

pub struct ConsoleReporter<W: Write> {
    /// `None` only after [`ConsoleReporter::into_inner`] took it.
    out: Option<W>,
    /// Whether the clock is virtual (said in the summary, since durations are simulated).
    virtual_time: bool,
    /// Lines not written yet. A burst of quick steps (a `repeat` of reads at the wire's
    /// limit) would otherwise cost a system call per line, as much as the telegram itself.
    pending: Vec<u8>,
    last_flush: Instant,
    color: bool,
    /// Whether lines may be held back at all (not while telegram lines go to another
    /// stream as they happen, see [`ConsoleReporter::holding`]).
    hold: bool,
    /// `--quiet`: failures, the drive's end state and the verdict only.
    quiet: bool,
    /// So that a failure another attempt will try again says so.
    attempts: OpenAttempts,
}

/// How long a line may be held back in a burst; the first line after a quiet spell, and
/// everything before the run waits (see [`RunObserver::idle`]), goes out at once.
const HOLD: Duration = Duration::from_millis(250);
const HOLD_BYTES: usize = 64 * 1024;

impl<W: Write> ConsoleReporter<W> {
    pub fn new(out: W, virtual_time: bool) -> Self {
        ConsoleReporter {
            out: Some(out),
            virtual_time,
            pending: Vec::new(),
            last_flush: Instant::now().checked_sub(HOLD).unwrap_or_else(Instant::now),
            color: false,
            hold: true,
            quiet: false,
            attempts: OpenAttempts::default(),
        }
    }

    /// Whether a burst of lines may be held back (the default); `false` writes every line
    /// at once, for a console interleaved with `-v` telegram lines on standard error.
    pub fn holding(mut self, hold: bool) -> Self {
        self.hold = hold;
        self
    }

    /// Only what a CI log needs: failed steps and checks, the drive's end state, the
    /// safe stop's notes when it could not be confirmed or the drive did not obey, and
    /// the verdict line.
    pub fn quiet(mut self, quiet: bool) -> Self {
        self.quiet = quiet;
        self
    }

    /// PASS/FAIL and the verdict in colour (see [`super::color_wanted`]).
    pub fn with_color(mut self, color: bool) -> Self {
        self.color = color;
        self
    }

    pub fn into_inner(mut self) -> W {
        self.flush();
        match self.out.take() {
            Some(out) => out,
            None => unreachable!("the writer is taken only here, which consumes the reporter"),
        }
    }

    fn line(&mut self, text: &str) {
        // A serial number or an answer never acts on the terminal.
        let text = &*super::visible(text);
        if self.color {
            self.pending.extend_from_slice(super::paint(text).as_bytes());
        } else {
            self.pending.extend_from_slice(text.as_bytes());
        }
        self.pending.push(b'\n');
        if !self.hold || self.last_flush.elapsed() >= HOLD || self.pending.len() >= HOLD_BYTES {
            self.flush();
        }
    }

    fn flush(&mut self) {
        self.last_flush = Instant::now();
        let Some(out) = self.out.as_mut() else { return };
        // A closed pipe (`| head`) must not stop the run or its safe stop.
        if !self.pending.is_empty() {
            let _ = out.write_all(&self.pending);
            self.pending.clear();
        }
        let _ = out.flush();
    }
}

impl<W: Write> Drop for ConsoleReporter<W> {
    fn drop(&mut self) {
        self.flush();
    }
}

impl<W: Write> RunObserver for ConsoleReporter<W> {
    fn run_started(&mut self, recipe: &RunInfo, drive: &str) {
        if self.quiet {
            return;
        }
        for line in header_lines(recipe, drive) {
            self.line(&line);
        }
    }

    fn step_started(&mut self, step: &StepInfo) {
        if self.quiet {
            return;
        }
        if let Some(line) = container_line(step) {
            self.line(&line);
        }
    }

    crate::follow_attempts!();

    fn step_finished(&mut self, r: &StepRecord) {
        self.attempts.finished(&r.number);
        if !self.quiet || !r.ok {
            self.line(&step_line(r, &self.attempts));
        }
    }

    fn check(&mut self, c: &CheckResult) {
        if self.quiet && c.passed {
            return;
        }
        if let Some(line) = check_line(c, &self.attempts) {
            self.line(&line);
        }
    }

    fn message(&mut self, text: &str) {
        if !self.quiet {
            self.line(&message_line(text));
        }
    }

    /// Said even when quiet: a person must read the question to answer it.
    fn asked(&mut self, number: &str, question: &str) {
        self.line(&asked_line(number, question));
        self.flush();
    }

    fn unit_identified(&mut self, unit: &UnitIdentity) {
        if !self.quiet {
            self.line(&message_line(&format!("unit: {unit}")));
        }
    }

    fn run_finished(&mut self, report: &RunReport) {
        // The safe stop's notes matter to a log only when the stop went wrong.
        let notes = !self.quiet || report.check_by_hand() || report.disobeyed;
        for line in summary_lines(report, self.virtual_time) {
            if !notes && line.starts_with("safe stop: ") {
                continue;
            }
            self.line(&line);
        }
        self.flush();
    }

    fn idle(&mut self) {
        if !self.pending.is_empty() {
            self.flush();
        }
    }
}

/// `recipe  NAME (PATH)` (or `script`), `drive   DRIVE` and, when there are any,
/// `unit    serial SP-104233, operator J. Smith` and `params  a = 1, b = 2`.
pub fn header_lines(run: &RunInfo, drive: &str) -> Vec<String> {
    let mut lines = vec![
        format!("{:<7} {} ({})", run.kind, run.name, run.path),
        format!("drive   {drive}"),
    ];
    if !run.unit.is_empty() {
        lines.push(format!("unit    {}", run.unit));
    }
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

/// `     3  ok    switch_on  switched on`; a failure inside an attempt that another one
/// follows is `FAIL (attempt 1 of 3, retrying)`.
pub fn step_line(r: &StepRecord, attempts: &OpenAttempts) -> String {
    use std::fmt::Write as _;
    let mark = if r.ok {
        "ok  ".to_string()
    } else {
        attempts.fail_mark()
    };
    let mut line = String::with_capacity(16 + r.label.len() + r.detail.len());
    let _ = match r.phase {
        "steps" => write!(line, "{:>6}  {mark}  {}", r.number, r.label),
        _ => write!(line, "{:>6}  {mark}  {}", r.number.replace('.', " "), r.label),
    };
    if !r.detail.is_empty() {
        line.push_str("  ");
        line.push_str(&r.detail);
    }
    line
}

/// `        PASS  name: message (limits 5940 .. 6060 rpm)`; `None` for `wait until` checks,
/// whose step line already says it. A failure inside an attempt that another one follows
/// is `FAIL (attempt 1 of 3, retrying)`.
pub fn check_line(c: &CheckResult, attempts: &OpenAttempts) -> Option<String> {
    if c.name.starts_with("wait until") {
        return None;
    }
    let mark = match (c.passed, c.marginal) {
        (true, false) => "PASS".to_string(),
        (true, true) => "MARGINAL".to_string(),
        (false, _) => attempts.fail_mark(),
    };
    let (above, below) = if c.inclusive { ("≥", "≤") } else { (">", "<") };
    let limits = match (c.limits.low, c.limits.high) {
        (Some(lo), Some(hi)) if lo == hi => format!(" (expected {})", with_unit(lo, c.unit.as_deref())),
        (Some(lo), Some(hi)) => {
            format!(" (limits {} .. {})", number(lo), with_unit(hi, c.unit.as_deref()))
        }
        (Some(lo), None) => format!(" (limit {above} {})", with_unit(lo, c.unit.as_deref())),
        (None, Some(hi)) => format!(" (limit {below} {})", with_unit(hi, c.unit.as_deref())),
        (None, None) => String::new(),
    };
    Some(format!("        {mark}  {}: {}{limits}", c.name, c.message))
}

/// A value read by `read`/`print`, or a message, indented under its step.
pub fn message_line(text: &str) -> String {
    format!("        {text}")
}

/// `     4  ?     Is the spindle running quietly? [yes/no]`: a question to the operator.
pub fn asked_line(number: &str, question: &str) -> String {
    format!("{number:>6}  ?     {question}")
}

/// The safe-stop notes, the final state and the one-line verdict.
pub fn summary_lines(report: &RunReport, virtual_time: bool) -> Vec<String> {
    let mut lines = Vec::new();
    for note in &report.safe_stop {
        lines.push(format!("safe stop: {note}"));
    }
    lines.extend(report.drive_left_lines());
    if report.check_by_hand() {
        lines.push("CHECK THE DRIVE BY HAND: the safe stop could not be confirmed (see above)".to_string());
    }
    // Every step line the run printed: nested steps, each pass of a repeat and `finally`
    // included, and the passed ones the report did not keep.
    let steps = report.steps.len() as u64 + report.omitted_steps;
    let time = humantime::format_duration(std::time::Duration::from_millis(
        report.duration.as_millis() as u64
    ));
    let clock = if virtual_time { " of virtual time" } else { "" };
    let why = match report.verdict.reason() {
        Some(m) => format!(": {m}"),
        None => String::new(),
    };
    let marginal = match report.checks.iter().filter(|c| c.marginal).count() {
        0 => String::new(),
        n => format!(" ({n} marginal)"),
    };
    // Failures of attempts that were tried again: kept, but not the verdict's.
    let retried = match report.checks_retried() {
        0 => String::new(),
        n => format!(", {n} retried"),
    };
    // A met `wait_until` is said on its step line, not as a `PASS` line: counted apart, so
    // that the checks counted passed are the `PASS` lines shown. A wait that timed out is a
    // failure like any other.
    let waits = report
        .checks
        .iter()
        .filter(|c| c.passed && c.name.starts_with(crate::session::WAIT))
        .count();
    let waited = match waits {
        0 => String::new(),
        n => format!(", {n} wait(s) met"),
    };
    lines.push(format!(
        "{}{why} — {steps} step(s), {} check(s) passed{marginal}, {} failed{retried}{waited}, {time}{clock}, exit code {}",
        report.verdict.word(),
        report.checks_passed() - waits,
        report.checks_failed(),
        report.exit_code()
    ));
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;
    use std::rc::Rc;

    /// Records every write the reporter makes.
    #[derive(Clone, Default)]
    struct Writes(Rc<RefCell<Vec<Vec<u8>>>>);

    impl Write for Writes {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.borrow_mut().push(buf.to_vec());
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Writes {
        fn count(&self) -> usize {
            self.0.borrow().len()
        }
        fn text(&self) -> String {
            String::from_utf8(self.0.borrow().concat()).unwrap()
        }
    }

    #[test]
    fn a_burst_of_lines_goes_out_in_few_writes_and_in_order() {
        let writes = Writes::default();
        let mut console = ConsoleReporter::new(writes.clone(), true);
        let started = Instant::now();
        for i in 0..10_000 {
            console.message(&format!("value {i}"));
        }
        console.idle();
        // One write per 250 ms that passed or per 64 KiB held, plus the first line and the
        // flush before the wait; a write per line would be 10 000.
        let bytes = writes.text().len();
        let bound = 2 + started.elapsed().as_millis() as usize / 250 + bytes / HOLD_BYTES;
        assert!(
            writes.count() <= bound,
            "{} writes, at most {bound} expected",
            writes.count()
        );
        let text = writes.text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 10_000);
        assert!(lines[9_999].ends_with("value 9999"), "{}", lines[9_999]);
    }

    #[test]
    fn without_holding_every_line_goes_out_at_once() {
        let writes = Writes::default();
        let mut console = ConsoleReporter::new(writes.clone(), true).holding(false);
        for i in 0..10 {
            console.message(&format!("value {i}"));
            assert!(writes.text().contains(&format!("value {i}")), "{}", writes.text());
        }
    }

    #[test]
    fn nothing_is_held_back_before_a_wait_or_after_the_end() {
        let writes = Writes::default();
        let mut console = ConsoleReporter::new(writes.clone(), true);
        console.message("first");
        console.message("second");
        console.idle();
        assert!(writes.text().contains("second"), "{}", writes.text());
        console.message("third");
        drop(console);
        assert!(writes.text().contains("third"), "{}", writes.text());
    }
}
