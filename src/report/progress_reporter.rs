//! Live progress on a terminal: an indicatif line showing the running step, elapsed and
//! remaining time of long steps (run clock, so virtual time reads right) and the live
//! values, with every finished step, check and message printed above it as the same
//! permanent lines as [`ConsoleReporter`](super::ConsoleReporter).
//! Only for a terminal (the CLI decides: stdout is a TTY, no `--quiet`/`--no-progress`);
//! in a log file or pipe the redrawn line would garble it. Never fails the run.

use super::console_reporter::{
    asked_line, check_line, container_line, header_lines, message_line, step_line, summary_lines,
};
use super::OpenAttempts;
use crate::session::{CheckResult, RunInfo, RunObserver, RunReport, StepInfo, StepRecord, UnitIdentity};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressFinish, ProgressStyle};
use std::io::Write;
use std::time::Duration;

const SPINNER: &str = "{spinner} {prefix:>6}  {msg}";
/// Columns the spinner and the step number take before the message.
const LEAD: usize = 10;

pub struct ProgressReporter<W: Write> {
    /// Where the permanent lines go (the terminal the bar is drawn on).
    out: W,
    bar: ProgressBar,
    virtual_time: bool,
    /// The running leaf step: (number, label).
    current: Option<(String, String)>,
    /// Running containers (`repeat`, `include`): (number, label, progress text).
    containers: Vec<(String, String, String)>,
    /// Whether the bar shows a bar (a step with a known total) or only the spinner.
    with_bar: bool,
    color: bool,
    /// Terminal columns: the live line never wraps (a wrapped line is redrawn as garbage).
    width: usize,
    /// The recipe's longest possible time (every timeout in full), for overall progress.
    planned: Option<Duration>,
    /// Run-clock time of the first step's start, and how far finished steps got.
    first_start: Option<Duration>,
    done_until: Duration,
    /// So that a failure another attempt will try again says so.
    attempts: OpenAttempts,
}

impl ProgressReporter<std::io::Stdout> {
    /// Progress on standard output, which must be a terminal.
    pub fn stdout(virtual_time: bool) -> Self {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stdout());
        bar.enable_steady_tick(Duration::from_millis(120));
        ProgressReporter::new(std::io::stdout(), bar, virtual_time)
    }
}

impl<W: Write> ProgressReporter<W> {
    /// Permanent lines to `out`, the live line on `bar` (`ProgressBar::hidden()` in tests).
    /// `out` and the bar's target should be the same terminal: lines are printed with the
    /// bar suspended so the two never interleave.
    pub fn new(out: W, bar: ProgressBar, virtual_time: bool) -> Self {
        let bar = bar.with_finish(ProgressFinish::AndClear);
        bar.set_style(style(SPINNER));
        ProgressReporter {
            out,
            bar,
            virtual_time,
            current: None,
            containers: Vec::new(),
            with_bar: false,
            color: false,
            width: terminal_width().unwrap_or(80),
            planned: None,
            first_start: None,
            done_until: Duration::ZERO,
            attempts: OpenAttempts::default(),
        }
    }

    /// The live line fits `columns` (default: the terminal's, else 80).
    pub fn with_width(mut self, columns: usize) -> Self {
        self.width = columns;
        self
    }

    /// The run's longest possible time, so the live line shows overall progress.
    pub fn with_planned(mut self, total: Duration) -> Self {
        self.planned = Some(total);
        self
    }

    /// `run 35m of ≤ 2h 20m`: the planned time counts every timeout in full, so it is an
    /// upper bound.
    fn overall(&self, elapsed: Duration) -> Option<String> {
        let planned = self.planned.filter(|p| !p.is_zero())?;
        let done = self
            .done_until
            .saturating_sub(self.first_start.unwrap_or_default())
            .saturating_add(elapsed);
        Some(format!(
            "run {} of ≤ {}",
            short_duration(done.min(planned)),
            short_duration(planned)
        ))
    }

    /// PASS/FAIL and the verdict in colour (see [`super::color_wanted`]).
    pub fn with_color(mut self, color: bool) -> Self {
        self.color = color;
        self
    }

    /// The live line (for tests and for a caller that wants to tick or hide it).
    pub fn bar(&self) -> &ProgressBar {
        &self.bar
    }

    pub fn into_inner(self) -> W {
        self.bar.finish_and_clear();
        self.out
    }

    /// A permanent line above the live one.
    fn line(&mut self, text: &str) {
        // A serial number or an answer never acts on the terminal.
        let text = &*super::visible(text);
        let painted;
        let text = if self.color {
            painted = super::paint(text);
            painted.as_str()
        } else {
            text
        };
        let out = &mut self.out;
        self.bar.suspend(|| {
            // A closed terminal must not stop the run or its safe stop.
            let _ = writeln!(out, "{text}");
            let _ = out.flush();
        });
    }

    fn set_bar(&mut self, with_bar: bool) {
        self.with_bar = with_bar;
    }

    /// The containers' progress, appended to the live line: `[repeat 3 times: iteration 2 of 3]`.
    fn context(&self) -> String {
        self.containers
            .iter()
            .map(|(_, label, progress)| {
                if progress.is_empty() {
                    format!(" [{label}]")
                } else {
                    format!(" [{label}: {progress}]")
                }
            })
            .collect()
    }
}

fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template)
        .unwrap_or_else(|_| ProgressStyle::default_spinner())
        .progress_chars("=> ")
}

fn display_number(number: &str, phase: &str) -> String {
    if phase == "steps" {
        number.to_string()
    } else {
        number.replace('.', " ")
    }
}

/// The live line within `budget` characters: the parts of `first` (time, live values,
/// overall progress) joined by ` · `, then `last` (what the step is) with what room is
/// left; whatever does not fit ends in `…`, the live values before the step's label.
pub fn fit_line(first: &[String], last: &str, budget: usize) -> String {
    let mut parts = first.to_vec();
    let len =
        |p: &[String]| p.iter().map(|s| s.chars().count()).sum::<usize>() + 3 * p.len().saturating_sub(1);
    // Too long: the longest part (the live values, as a rule) gives up its end first.
    if let Some(i) = (0..parts.len()).max_by_key(|&i| parts[i].chars().count()) {
        let over = len(&parts).saturating_sub(budget);
        if over > 0 {
            let keep = parts[i].chars().count().saturating_sub(over).max(8);
            parts[i] = cut(&parts[i], keep);
        }
    }
    let head = parts.join(" · ");
    let head_len = head.chars().count();
    if head_len >= budget {
        return cut(&head, budget);
    }
    let room = budget - head_len;
    if room <= 4 || last.is_empty() {
        return head;
    }
    format!("{head} · {}", cut(last, room - 3))
}

/// `text` in at most `n` characters, ending in `…` when cut.
fn cut(text: &str, n: usize) -> String {
    if text.chars().count() <= n {
        return text.to_string();
    }
    let mut s: String = text.chars().take(n.saturating_sub(1)).collect();
    s.push('…');
    s
}

/// The columns of the terminal on standard output, when it is one.
fn terminal_width() -> Option<usize> {
    #[cfg(unix)]
    {
        // SAFETY: TIOCGWINSZ fills a winsize struct we own; a failure leaves it zeroed.
        let mut size: libc::winsize = unsafe { std::mem::zeroed() };
        let ok = unsafe { libc::ioctl(libc::STDOUT_FILENO, libc::TIOCGWINSZ, &mut size) } == 0;
        if ok && size.ws_col > 0 {
            return Some(usize::from(size.ws_col));
        }
    }
    None
}

/// `12.3 s` under a minute, then `1h 2m 3s` to the second.
pub fn short_duration(d: Duration) -> String {
    if d < Duration::from_secs(60) {
        format!("{:.1} s", d.as_secs_f64())
    } else {
        humantime::format_duration(Duration::from_secs(d.as_secs())).to_string()
    }
}

/// `12.0 s of 60.0 s, 48.0 s left` (or `12.0 s` without a total).
pub fn progress_text(elapsed: Duration, total: Option<Duration>) -> String {
    match total {
        Some(t) => format!(
            "{} of {}, {} left",
            short_duration(elapsed.min(t)),
            short_duration(t),
            short_duration(t.saturating_sub(elapsed))
        ),
        None => short_duration(elapsed),
    }
}

impl<W: Write> RunObserver for ProgressReporter<W> {
    fn run_started(&mut self, recipe: &RunInfo, drive: &str) {
        for line in header_lines(recipe, drive) {
            self.line(&line);
        }
    }

    fn step_started(&mut self, step: &StepInfo) {
        let (number, phase) = (step.number.as_str(), step.phase);
        if let Some(line) = container_line(step) {
            self.line(&line);
        }
        if step.container {
            self.containers
                .push((number.to_string(), step.label.clone(), String::new()));
            return;
        }
        self.current = Some((number.to_string(), step.label.clone()));
        self.set_bar(false);
        self.bar.unset_length();
        self.bar.set_position(0);
        self.bar.set_prefix(display_number(number, phase));
        self.bar.set_message(format!("{}{}", step.label, self.context()));
    }

    fn step_progress(&mut self, number: &str, elapsed: Duration, total: Option<Duration>, values: &str) {
        if let Some(c) = self.containers.iter_mut().find(|c| c.0 == number) {
            let mut text = values.to_string();
            if let Some(t) = total {
                text = format!("{text}, {}", progress_text(elapsed, Some(t)));
            }
            c.2 = text;
            return;
        }
        let Some((current, label)) = self.current.clone() else {
            return;
        };
        if current != number {
            return;
        }
        match total {
            Some(t) if !t.is_zero() => {
                self.set_bar(true);
                self.bar.set_length(t.as_millis() as u64);
                self.bar.set_position(elapsed.min(t).as_millis() as u64);
            }
            _ => self.set_bar(false),
        }
        let time = match total {
            Some(t) => format!("{}/{}", short_duration(elapsed.min(t)), short_duration(t)),
            None => short_duration(elapsed),
        };
        let mut first = vec![time];
        if !values.is_empty() {
            first.push(values.to_string());
        }
        first.extend(self.overall(elapsed));
        let last = format!("{label}{}", self.context());
        let budget = self.width.saturating_sub(LEAD).max(20);
        self.bar.set_message(fit_line(&first, &last, budget));
    }

    fn step_finished(&mut self, record: &StepRecord) {
        self.first_start = Some(self.first_start.map_or(record.started, |f| f.min(record.started)));
        self.done_until = self
            .done_until
            .max(record.started.saturating_add(record.duration));
        if self.containers.last().is_some_and(|c| c.0 == record.number) {
            self.containers.pop();
        }
        if self.current.as_ref().is_some_and(|c| c.0 == record.number) {
            self.current = None;
        }
        self.attempts.finished(&record.number);
        self.line(&step_line(record, &self.attempts));
        self.set_bar(false);
        self.bar.unset_length();
        self.bar.set_message(self.context().trim_start().to_string());
    }

    fn check(&mut self, result: &CheckResult) {
        if let Some(line) = check_line(result, &self.attempts) {
            self.line(&line);
        }
    }

    crate::follow_attempts!();

    fn message(&mut self, text: &str) {
        self.line(&message_line(text));
    }

    fn asked(&mut self, number: &str, question: &str) {
        self.line(&asked_line(number, question));
    }

    fn unit_identified(&mut self, unit: &UnitIdentity) {
        self.line(&message_line(&format!("unit: {unit}")));
    }

    fn wants_progress(&self) -> bool {
        true
    }

    fn run_finished(&mut self, report: &RunReport) {
        self.bar.finish_and_clear();
        for line in summary_lines(report, self.virtual_time) {
            self.line(&line);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_live_line_keeps_values_and_overall_progress_within_80_columns() {
        let first = vec![
            "12m 3s/15m".to_string(),
            "speed_actual 6000.123 rpm, current_actual 0.481 A".to_string(),
            "run 35m of ≤ 2h 20m".to_string(),
        ];
        let label = "sample speed_actual, current_actual every 1s for 15m [Stage 2: iteration 2 of 2]";
        let line = fit_line(&first, label, 80 - LEAD);
        assert!(line.chars().count() <= 80 - LEAD, "{line}");
        assert!(line.contains("speed_actual 6000.123 rpm, current"), "{line}");
        assert!(line.contains("run 35m"), "{line}");
        // Wide terminals show the label too.
        let wide = fit_line(&first, label, 200);
        assert!(wide.ends_with("iteration 2 of 2]"), "{wide}");
        // Too narrow for everything: cut with an ellipsis, never longer.
        assert_eq!(fit_line(&first, label, 20).chars().count(), 20);
        assert!(fit_line(&first, label, 20).ends_with('…'));
    }

    /// The live display prints the same check lines as the plain console: a failure
    /// another attempt follows says so, the last attempt's is a plain FAIL.
    #[test]
    fn a_failure_another_attempt_follows_reads_retrying() {
        let mut live = ProgressReporter::new(Vec::new(), ProgressBar::hidden(), true);
        let failed = CheckResult {
            key: "motor_temperature min above".into(),
            measured: Some(28.6),
            unit: Some("°C".into()),
            limits: crate::session::Limits::new(Some(33.0), None),
            message: "too cold".into(),
            origin: crate::session::StepOrigin {
                path: "r.yaml".into(),
                line: 9,
                column: 11,
            },
            step: "3[1].3".into(),
            ..CheckResult::named("motor_temperature min above 33 °C", false)
        };
        live.attempt_started("3", 1, 2);
        live.check(&failed);
        live.attempt_started("3", 2, 2);
        live.check(&failed);
        let text = String::from_utf8(live.out.clone()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines[0].starts_with("        FAIL (attempt 1 of 2, retrying)  motor_temperature"),
            "{text}"
        );
        assert!(lines[1].starts_with("        FAIL  motor_temperature"), "{text}");
    }

    #[test]
    fn long_times_read_as_hours_and_minutes() {
        assert_eq!(
            progress_text(Duration::from_secs(3_725), Some(Duration::from_secs(7_200))),
            "1h 2m 5s of 2h, 57m 55s left"
        );
        assert_eq!(progress_text(Duration::from_millis(500), None), "0.5 s");
        assert_eq!(
            progress_text(Duration::from_secs(70), Some(Duration::from_secs(60))),
            "1m of 1m, 0.0 s left"
        );
    }
}
