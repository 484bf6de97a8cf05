//! The run as the operator's page sees it: an observer of the one run pipeline (beside the
//! console, the CSV and the results store) that turns its events into the station's view
//! and events. Sampled points go out in batches at most a few times a second, so a page
//! costs the run little however fast it samples: a row every series drops (most rows of a
//! long run) is only counted here and given to the view with the next row kept, and the
//! real clock is read only for rows that add points or every [`BATCH_EVERY`] of the run's
//! time. Must not fail or slow the run: it only changes the in-memory view.

use super::event_log::EventLog;
use super::station_view::{DialogView, StationView};
use crate::session::{CheckResult, Limits, ObjectRef, Prompt, PromptKind, RunObserver, StepInfo, StepRecord};
use serde_json::Value;
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
    /// Where the caller kept those objects (address and number): a sampling loop hands the
    /// same slice with every row, so a row there names them without comparing names.
    /// Forgotten at every other event (a new step may keep other objects at that place).
    objects_at: Option<(usize, usize)>,
    /// Their plotted series as the view has them after the rows counted in `skipped`;
    /// `None` until a row went to the view (then every row goes to it).
    plotted: Option<Vec<usize>>,
    /// How many more rows every plotted series drops (counted, not given to the view).
    droppable: u64,
    /// Rows every plotted series drops, not yet given to the view, and the last one's time.
    skipped: u64,
    skipped_at: Duration,
    /// The run's time from which a row reads the real clock for a batch again.
    next_check: Duration,
    /// A row came since the last `idle` (its sampling loop reads the clock itself).
    sampled: bool,
}

impl PageObserver {
    pub fn new(log: Arc<EventLog>, prompts: Vec<Prompt>) -> Self {
        PageObserver {
            log,
            prompts,
            batch: Vec::new(),
            sent: Instant::now(),
            objects: Vec::new(),
            objects_at: None,
            plotted: None,
            droppable: 0,
            skipped: 0,
            skipped_at: Duration::ZERO,
            next_check: Duration::ZERO,
            sampled: false,
        }
    }

    /// Changes the view, after giving it the rows only counted so far.
    fn change(&mut self, change: impl FnOnce(&mut StationView) -> Option<Value>) {
        let rows = std::mem::take(&mut self.skipped);
        let (plotted, at) = (&self.plotted, self.skipped_at.as_secs_f64());
        self.log.change(|view| {
            give_skipped(view, plotted, rows, at);
            ((), change(view))
        });
    }

    fn flush(&mut self) {
        if self.batch.is_empty() && self.skipped == 0 {
            return;
        }
        let batch = std::mem::take(&mut self.batch);
        self.change(|view| view.points(&batch));
        if !batch.is_empty() {
            self.sent = Instant::now();
        }
    }

    fn flush_when_due(&mut self) {
        if !self.batch.is_empty() && self.sent.elapsed() >= BATCH_EVERY {
            self.flush();
        }
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
            limits: Limits::default(),
            pattern: None,
            error: None,
            answered: false,
        };
        let Some(prompt) = found else {
            return dialog;
        };
        dialog.text = prompt.text.clone();
        // The terminal's `[in mm/s, at most 2.8 mm/s]` without the brackets that set it off
        // from the question on one line; the dialog has a line of its own for it.
        let hint = prompt.hint();
        dialog.hint = hint
            .strip_prefix('[')
            .and_then(|h| h.strip_suffix(']'))
            .unwrap_or(&hint)
            .to_string();
        match &prompt.kind {
            PromptKind::Instruction => dialog.kind = "instruct",
            PromptKind::Confirm => dialog.kind = "confirm",
            PromptKind::Value { unit, limits, .. } => {
                dialog.kind = "value";
                dialog.unit = unit.map(|u| u.symbol().to_string());
                dialog.limits = *limits;
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
        self.objects_at = None;
        self.flush();
        self.change(|view| view.step_started(&step.number, &step.label));
    }

    fn check(&mut self, result: &CheckResult) {
        self.objects_at = None;
        self.change(|view| {
            view.checked(result.passed, result.marginal);
            None
        });
    }

    fn step_finished(&mut self, record: &StepRecord) {
        self.objects_at = None;
        self.flush();
        let at = (record.started + record.duration).as_secs_f64();
        self.change(|view| view.step_finished(&record.number, &record.label, record.ok, at));
    }

    fn step_progress(&mut self, _number: &str, _elapsed: Duration, _total: Option<Duration>, _values: &str) {
        self.objects_at = None;
        self.flush_when_due();
    }

    fn asked(&mut self, number: &str, question: &str) {
        self.objects_at = None;
        self.flush();
        let dialog = self.dialog(number, question);
        self.change(|view| view.ask(dialog));
    }

    fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
        self.sampled = true;
        let place = (objects.as_ptr() as usize, objects.len());
        if self.objects_at != Some(place) {
            self.objects_at = Some(place);
            if self.objects.len() != objects.len()
                || self.objects.iter().zip(objects).any(|(a, b)| a.0 != b.name)
            {
                // The rows counted so far belong to the series of the objects before.
                self.flush();
                self.plotted = None;
                self.droppable = 0;
                self.objects = objects.iter().map(|o| (o.name.clone(), o.unit.clone())).collect();
            }
        }
        let mut added = false;
        if self.plotted.is_some() && self.droppable > 0 {
            self.droppable -= 1;
            self.skipped += 1;
            self.skipped_at = at;
        } else {
            let before = self.batch.len();
            let rows = std::mem::take(&mut self.skipped);
            let (names, batch, plotted, at_s) = (
                &self.objects,
                &mut self.batch,
                &mut self.plotted,
                self.skipped_at.as_secs_f64(),
            );
            let positions = self.log.change(|view| {
                give_skipped(view, plotted, rows, at_s);
                view.sample(at.as_secs_f64(), names, values, batch);
                (view.positions(names), None)
            });
            // Every plotted series keeps the samples seen that are a multiple of its stride.
            self.droppable = positions.as_ref().map_or(0, |found| {
                found
                    .iter()
                    .map(|&(_, seen, stride)| (stride - seen % stride) % stride)
                    .min()
                    .unwrap_or(u64::MAX)
            });
            self.plotted = positions.map(|found| found.iter().map(|p| p.0).collect());
            added = self.batch.len() != before;
        }
        // The clock is read for a row that adds points, and otherwise every BATCH_EVERY of
        // the run's time (the same in real time; far fewer reads in virtual time).
        if added || at >= self.next_check {
            self.next_check = at.saturating_add(BATCH_EVERY);
            if self.batch.is_empty() {
                // Only counted rows: the view still learns how far the run is.
                self.flush();
            } else {
                self.flush_when_due();
            }
        }
    }

    fn message(&mut self, text: &str) {
        self.objects_at = None;
        self.change(|view| view.message(text));
    }

    fn idle(&mut self) {
        // Between a sampling loop's rows, which read the clock as they need.
        if !std::mem::take(&mut self.sampled) {
            self.flush_when_due();
        }
    }

    fn run_finished(&mut self, _report: &crate::session::RunReport) {
        self.objects_at = None;
        self.flush();
    }
}

/// Gives the view the `rows` up to `at` that every series in `plotted` drops.
fn give_skipped(view: &mut StationView, plotted: &Option<Vec<usize>>, rows: u64, at: f64) {
    if let Some(series) = plotted.as_ref().filter(|_| rows > 0) {
        view.skip(at, series, rows);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::station::station_view::RunView;

    fn view() -> StationView {
        let mut view = StationView::new(Vec::new(), "bench".into());
        view.start(RunView::new(1, "r", "s", "o", None));
        view
    }

    fn objects(names: &[&str]) -> Vec<ObjectRef> {
        names
            .iter()
            .map(|n| ObjectRef {
                name: n.to_string(),
                unit: Some("rpm".into()),
            })
            .collect()
    }

    #[test]
    fn counting_dropped_rows_leaves_the_view_as_sampling_each_row_does() {
        let mut reference = view();
        let log = Arc::new(EventLog::new(view()));
        let mut page = PageObserver::new(log.clone(), Vec::new());
        let many: Vec<String> = (0..10).map(|i| format!("o{i}")).collect();
        let many: Vec<&str> = many.iter().map(String::as_str).collect();
        // Objects that change between steps, a series sampled twice in one row, and more
        // objects than the view plots.
        let phases: [(&[&str], u64); 5] = [
            (&["speed", "current"], 5000),
            (&["speed"], 3001),
            (&["speed", "speed"], 700),
            (&["torque", "speed"], 2500),
            (&many, 1500),
        ];
        let (mut row, mut batch) = (0u64, Vec::new());
        for (names, rows) in phases {
            let objects = objects(names);
            let named: Vec<(String, Option<String>)> =
                objects.iter().map(|o| (o.name.clone(), o.unit.clone())).collect();
            for _ in 0..rows {
                let at = Duration::from_millis(10 * row);
                let values: Vec<f64> = (0..objects.len()).map(|i| (row * 10 + i as u64) as f64).collect();
                reference.sample(at.as_secs_f64(), &named, &values, &mut batch);
                page.sample(at, &objects, &values);
                page.idle();
                row += 1;
            }
            page.message("between steps");
            reference.message("between steps");
            let json = |v: &StationView| serde_json::to_string(&v.run).expect("json");
            // Not assert_eq: the views are thousands of points long.
            assert!(
                log.read(json) == json(&reference),
                "the views differ after {row} rows"
            );
            for name in ["speed", "current", "torque", "o3"] {
                let position = |v: &StationView| v.positions(&[(name.to_string(), None)]);
                assert_eq!(
                    log.read(position),
                    position(&reference),
                    "{name} after {row} rows"
                );
            }
        }
        // As many series as the view plots, and the long ones compacted (rows counted).
        let strides = log.read(|v| {
            v.run
                .as_ref()
                .map(|r| r.series.iter().map(|s| s.stride).collect::<Vec<_>>())
        });
        let strides = strides.expect("the run");
        assert_eq!(strides.len(), crate::station::SERIES);
        assert!(strides[0] >= 16, "{strides:?}");
    }
}
