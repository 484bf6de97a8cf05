//! Plain console output of a run: one line per step with its number, what it did, ok/FAIL
//! and the values, one line per check, the safe stop, and a summary. Line-oriented so it
//! never garbles a log file.

use crate::recipe::{
    number, CheckResult, Recipe, RunObserver, RunReport, Step, StepKind, StepRecord, Verdict,
};
use std::io::Write;

pub struct ConsoleReporter<W: Write> {
    out: W,
    /// Whether the clock is virtual (said in the summary, since durations are simulated).
    virtual_time: bool,
}

impl<W: Write> ConsoleReporter<W> {
    pub fn new(out: W, virtual_time: bool) -> Self {
        ConsoleReporter { out, virtual_time }
    }

    pub fn into_inner(self) -> W {
        self.out
    }

    fn line(&mut self, text: &str) {
        // A closed pipe (`| head`) must not stop the run or its safe stop.
        let _ = writeln!(self.out, "{text}");
        let _ = self.out.flush();
    }
}

impl<W: Write> RunObserver for ConsoleReporter<W> {
    fn run_started(&mut self, recipe: &Recipe, drive: &str) {
        self.line(&format!("recipe  {} ({})", recipe.name, recipe.path));
        self.line(&format!("drive   {drive}"));
        if !recipe.params.is_empty() {
            let params = recipe
                .params
                .iter()
                .map(|p| format!("{} = {}", p.name, p.value))
                .collect::<Vec<_>>()
                .join(", ");
            self.line(&format!("params  {params}"));
        }
    }

    fn step_started(&mut self, number: &str, step: &Step, phase: &'static str) {
        // Containers announce themselves, so their nested steps read in order.
        if matches!(step.kind, StepKind::Repeat { .. } | StepKind::Include { .. }) {
            let number = if phase == "steps" {
                number.to_string()
            } else {
                number.replace('.', " ")
            };
            self.line(&format!("{number:>6}  ...   {}", step.label));
        }
    }

    fn step_finished(&mut self, r: &StepRecord) {
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
        self.line(&format!("{number:>6}  {mark}  {}{detail}", r.label));
    }

    fn check(&mut self, c: &CheckResult) {
        if c.name.starts_with("wait until") {
            return;
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
        self.line(&format!("        {mark}  {}: {}{limits}", c.name, c.message));
    }

    fn message(&mut self, text: &str) {
        self.line(&format!("        {text}"));
    }

    fn run_finished(&mut self, report: &RunReport) {
        for note in &report.safe_stop {
            self.line(&format!("safe stop: {note}"));
        }
        if let Some(state) = report.final_state {
            self.line(&format!("drive left in {state}"));
        }
        let steps = report
            .steps
            .iter()
            .filter(|s| s.phase == "steps" && !s.number.contains('.'))
            .count();
        let time = humantime::format_duration(std::time::Duration::from_millis(
            report.duration.as_millis() as u64
        ));
        let clock = if self.virtual_time { " of virtual time" } else { "" };
        let why = match &report.verdict {
            Verdict::Error(m) => format!(": {m}"),
            _ => String::new(),
        };
        self.line(&format!(
            "{}{why} — {steps} step(s), {} check(s) passed, {} failed, {time}{clock}",
            report.verdict.word(),
            report.checks_passed(),
            report.checks_failed()
        ));
    }
}

fn with_unit(v: f64, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{} {u}", number(v)),
        None => number(v),
    }
}
