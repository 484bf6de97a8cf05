//! The run as the operator's page sees it: an observer of the one run pipeline (beside the
//! console, the CSV and the results store) that turns its events into the station's view
//! and events. Sampled points go out in batches at most a few times a second, so a page
//! costs the run little however fast it samples. Must not fail or slow the run: it only
//! changes the in-memory view.

use super::event_log::EventLog;
use super::station_view::DialogView;
use crate::session::{CheckResult, ObjectRef, Prompt, PromptKind, RunObserver, StepInfo, StepRecord};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often sampled points go to the pages at most (real time).
const BATCH_EVERY: Duration = Duration::from_millis(250);

pub struct PageObserver {
    log: Arc<EventLog>,
    /// The run's operator steps, to show each question as its kind's dialog.
    prompts: Vec<Prompt>,
    batch: Vec<(usize, u64, f64, f64)>,
    sent: Instant,
    /// The objects of the last sample row, as the view names them.
    objects: Vec<(String, Option<String>)>,
}

impl PageObserver {
    pub fn new(log: Arc<EventLog>, prompts: Vec<Prompt>) -> Self {
        PageObserver {
            log,
            prompts,
            batch: Vec::new(),
            sent: Instant::now(),
            objects: Vec::new(),
        }
    }

    fn flush(&mut self) {
        if self.batch.is_empty() {
            return;
        }
        let batch = std::mem::take(&mut self.batch);
        self.log.change(|view| ((), view.points(&batch)));
        self.sent = Instant::now();
    }

    /// The dialog for `question` (the session's `text [hint]`), from the operator step it
    /// is; a question no step of the plan asks (a script's computed text) is a text field.
    fn dialog(&self, number: &str, question: &str) -> DialogView {
        let found = self
            .prompts
            .iter()
            .find(|p| format!("{} {}", p.text, p.hint()) == question);
        let mut dialog = DialogView {
            id: 0,
            number: number.to_string(),
            kind: "text",
            text: question.to_string(),
            hint: String::new(),
            unit: None,
            low: None,
            high: None,
            pattern: None,
            error: None,
            answered: false,
        };
        let Some(prompt) = found else {
            return dialog;
        };
        dialog.text = prompt.text.clone();
        dialog.hint = prompt.hint();
        match &prompt.kind {
            PromptKind::Instruction => dialog.kind = "instruct",
            PromptKind::Confirm => dialog.kind = "confirm",
            PromptKind::Value { unit, low, high, .. } => {
                dialog.kind = "value";
                dialog.unit = unit.map(|u| u.symbol().to_string());
                dialog.low = *low;
                dialog.high = *high;
            }
            PromptKind::Text { pattern, .. } => {
                dialog.pattern = pattern.as_ref().map(|p| p.source().to_string());
            }
        }
        dialog
    }
}

impl RunObserver for PageObserver {
    fn step_started(&mut self, step: &StepInfo) {
        self.flush();
        self.log
            .change(|view| ((), view.step_started(&step.number, &step.label)));
    }

    fn check(&mut self, result: &CheckResult) {
        self.log
            .change(|view| (view.checked(result.passed, result.marginal), None));
    }

    fn step_finished(&mut self, record: &StepRecord) {
        self.flush();
        let at = (record.started + record.duration).as_secs_f64();
        self.log.change(|view| {
            let event = view.step_finished(&record.number, &record.label, record.ok, at);
            ((), event)
        });
    }

    fn step_progress(&mut self, _number: &str, _elapsed: Duration, _total: Option<Duration>, _values: &str) {
        if self.sent.elapsed() >= BATCH_EVERY {
            self.flush();
        }
    }

    fn asked(&mut self, number: &str, question: &str) {
        self.flush();
        let dialog = self.dialog(number, question);
        self.log.change(|view| ((), view.ask(dialog)));
    }

    fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
        if self.objects.len() != objects.len() || self.objects.iter().zip(objects).any(|(a, b)| a.0 != b.name)
        {
            self.objects = objects.iter().map(|o| (o.name.clone(), o.unit.clone())).collect();
        }
        let at_s = at.as_secs_f64();
        let (names, batch) = (&self.objects, &mut self.batch);
        self.log
            .change(|view| (view.sample(at_s, names, values, batch), None));
        if self.sent.elapsed() >= BATCH_EVERY {
            self.flush();
        }
    }

    fn message(&mut self, text: &str) {
        self.log.change(|view| ((), view.message(text)));
    }

    fn idle(&mut self) {
        if self.sent.elapsed() >= BATCH_EVERY {
            self.flush();
        }
    }

    fn run_finished(&mut self, _report: &crate::session::RunReport) {
        self.flush();
    }
}
