//! What the operator's page shows, as data: the recipes it may start, the run under way
//! (its steps, the open question, the live plots, the Stop presses) and the last run's
//! result. Every change is made here and returns the small event a connected page applies
//! to its own copy; a page that (re)connects gets the whole view. Plain data: no I/O, no
//! locking (the [`super::EventLog`] holds it).

use super::plot_buffer::{PlotBuffer, Pushed};
use crate::session::Limits;
use serde::Serialize;
use serde_json::{json, Value};
use std::collections::VecDeque;

/// The most steps the view keeps (the latest; a long repeat runs thousands).
pub const STEPS: usize = 200;
/// The most series plotted (a run sampling more objects plots the first ones).
pub const SERIES: usize = 8;

/// A recipe the station was started with; the page names it by its index.
#[derive(Debug, Clone, Serialize)]
pub struct RecipeView {
    pub name: String,
    pub file: String,
    /// How long it is planned to take (a recipe; a script's is unknown).
    pub planned_s: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct StepView {
    pub number: String,
    pub label: String,
    /// `running`, `ok`, `fail` or `marginal`.
    pub state: &'static str,
}

/// An operator step waiting for its answer.
#[derive(Debug, Clone, Serialize)]
pub struct DialogView {
    /// Changes with each question and each "answer again", so that an answer meant for an
    /// earlier one is refused instead of answering the next.
    pub id: u64,
    pub number: String,
    /// `instruct`, `confirm`, `value` or `text`.
    pub kind: &'static str,
    pub text: String,
    /// What may be answered, as the terminal says it: `[mm/s, at most 2.8]`.
    pub hint: String,
    pub unit: Option<String>,
    #[serde(flatten)]
    pub limits: Limits,
    pub pattern: Option<String>,
    /// Why the last answer was no answer (the terminal's words).
    pub error: Option<String>,
    /// An answer was handed to the run and is being judged.
    pub answered: bool,
}

/// How a run ended, for the result screen.
#[derive(Debug, Clone, Serialize)]
pub struct ResultView {
    /// `PASS`, `FAIL`, `MARGINAL`, or `NOT RUN`.
    pub word: &'static str,
    /// The run's verdict as every report says it: `PASSED`, `FAILED`, `ERROR`, …
    pub verdict: String,
    pub exit_code: i32,
    pub reason: Option<String>,
    /// What failed: each failed check or step, one line each.
    pub failed: Vec<String>,
    /// The drive's end state, as the console says it.
    pub end: Vec<String>,
    pub check_by_hand: bool,
    /// Whether the run's HTML report was written (`/report` serves it).
    pub report: bool,
    /// Whether the unit's certificate can be asked for (a store and a serial).
    pub certificate: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct RunView {
    pub id: u64,
    pub recipe: String,
    pub serial: String,
    pub operator: String,
    pub planned_s: Option<f64>,
    /// The run's clock when the view last heard of it.
    pub elapsed_s: f64,
    pub steps: VecDeque<StepView>,
    /// Steps no longer in `steps`.
    pub earlier_steps: u64,
    pub dialog: Option<DialogView>,
    pub series: Vec<PlotBuffer>,
    /// Stop presses so far (the second switches the power stage off).
    pub stops: u32,
    pub note: Option<String>,
    pub result: Option<ResultView>,
}

impl RunView {
    /// A run just started: no step, point or answer yet.
    pub fn new(id: u64, recipe: &str, serial: &str, operator: &str, planned_s: Option<f64>) -> Self {
        RunView {
            id,
            recipe: recipe.to_string(),
            serial: serial.to_string(),
            operator: operator.to_string(),
            planned_s,
            elapsed_s: 0.0,
            steps: VecDeque::new(),
            earlier_steps: 0,
            dialog: None,
            series: Vec::new(),
            stops: 0,
            note: None,
            result: None,
        }
    }
}

/// The page's whole view.
#[derive(Debug, Clone, Serialize)]
pub struct StationView {
    pub recipes: Vec<RecipeView>,
    /// The bench's name (`--unit station=…`), or the host's.
    pub station: String,
    pub run: Option<RunView>,
    /// The station is shutting down (a stop signal): no new run starts.
    pub closing: bool,
    #[serde(skip)]
    next_dialog: u64,
    #[serde(skip)]
    marginal_step: bool,
}

impl StationView {
    pub fn new(recipes: Vec<RecipeView>, station: String) -> Self {
        StationView {
            recipes,
            station,
            run: None,
            closing: false,
            next_dialog: 1,
            marginal_step: false,
        }
    }

    /// Whether a run is under way (started and without its result).
    pub fn running(&self) -> bool {
        self.run.as_ref().is_some_and(|r| r.result.is_none())
    }

    pub fn start(&mut self, run: RunView) -> Value {
        let event = json!({"kind": "run", "run": &run});
        self.run = Some(run);
        event
    }

    fn current(&mut self) -> Option<&mut RunView> {
        self.run.as_mut().filter(|r| r.result.is_none())
    }

    pub fn step_started(&mut self, number: &str, label: &str) -> Option<Value> {
        self.marginal_step = false;
        let run = self.current()?;
        let step = StepView {
            number: number.to_string(),
            label: label.to_string(),
            state: "running",
        };
        let event = json!({"kind": "step", "step": &step});
        if run.steps.len() >= STEPS {
            run.steps.pop_front();
            run.earlier_steps += 1;
        }
        run.steps.push_back(step);
        Some(event)
    }

    /// A check of the running step: a marginal one marks it amber at its end.
    pub fn checked(&mut self, passed: bool, marginal: bool) {
        self.marginal_step |= passed && marginal;
    }

    pub fn step_finished(&mut self, number: &str, label: &str, ok: bool, at_s: f64) -> Option<Value> {
        let marginal = std::mem::take(&mut self.marginal_step);
        let run = self.current()?;
        run.elapsed_s = run.elapsed_s.max(at_s);
        let state = match (ok, marginal) {
            (false, _) => "fail",
            (true, true) => "marginal",
            (true, false) => "ok",
        };
        // The latest line of this step (a container's nested steps come after it).
        let step = match run.steps.iter_mut().rev().find(|s| s.number == number) {
            Some(s) => {
                s.state = state;
                s.clone()
            }
            None => StepView {
                number: number.to_string(),
                label: label.to_string(),
                state,
            },
        };
        let closes = run.dialog.as_ref().is_some_and(|d| d.number == number);
        if closes {
            run.dialog = None;
        }
        Some(json!({"kind": "step", "step": step, "elapsed_s": run.elapsed_s, "dialog_closed": closes}))
    }

    pub fn progress(&mut self, at_s: f64) -> Option<Value> {
        let run = self.current()?;
        run.elapsed_s = run.elapsed_s.max(at_s);
        Some(json!({"kind": "progress", "elapsed_s": run.elapsed_s}))
    }

    pub fn ask(&mut self, mut dialog: DialogView) -> Option<Value> {
        dialog.id = self.next_dialog;
        self.next_dialog += 1;
        let run = self.current()?;
        let event = json!({"kind": "dialog", "dialog": &dialog});
        run.dialog = Some(dialog);
        Some(event)
    }

    /// The page answers the question `id`: `Ok(())` when it is the open one and no answer
    /// to it is being judged (the answer then goes to the run); why not otherwise.
    pub fn answer(&mut self, id: u64) -> Result<Value, &'static str> {
        let Some(run) = self.current() else {
            return Err("no run is under way");
        };
        let Some(dialog) = run.dialog.as_mut() else {
            return Err("no question is open");
        };
        if dialog.id != id {
            return Err("that question is no longer open (it was answered, or asked again)");
        }
        if dialog.answered {
            return Err("that question was already answered");
        }
        dialog.answered = true;
        dialog.error = None;
        Ok(json!({"kind": "dialog", "dialog": &*dialog}))
    }

    /// A message of the run; while an answer is judged, it is why it was no answer, and
    /// the question is open again (under a new id).
    pub fn message(&mut self, text: &str) -> Option<Value> {
        let id = self.next_dialog;
        let run = self.run.as_mut().filter(|r| r.result.is_none())?;
        if let Some(dialog) = run.dialog.as_mut().filter(|d| d.answered) {
            dialog.answered = false;
            dialog.error = Some(text.to_string());
            dialog.id = id;
            let event = json!({"kind": "dialog", "dialog": &*dialog});
            self.next_dialog += 1;
            return Some(event);
        }
        run.note = Some(text.to_string());
        Some(json!({"kind": "note", "text": text}))
    }

    /// One sample row; the points kept go to `batch` (series index, t, v) for the next
    /// event; a compacted series drops the batch's points that are no longer kept.
    pub fn sample(
        &mut self,
        at_s: f64,
        objects: &[(String, Option<String>)],
        values: &[f64],
        batch: &mut Vec<(usize, u64, f64, f64)>,
    ) {
        let Some(run) = self.current() else { return };
        run.elapsed_s = run.elapsed_s.max(at_s);
        for ((name, unit), v) in objects.iter().zip(values) {
            let i = match run.series.iter().position(|s| s.name == *name) {
                Some(i) => i,
                None if run.series.len() < SERIES => {
                    run.series.push(PlotBuffer::new(name, unit.clone()));
                    run.series.len() - 1
                }
                None => continue,
            };
            let series = &mut run.series[i];
            let pushed = series.push(at_s, *v);
            if pushed == Pushed::Compacted {
                let stride = series.stride;
                // Keep the batch's points the doubled stride still keeps, as the page will.
                batch.retain(|(s, index, _, _)| *s != i || index.is_multiple_of(stride));
            }
            if pushed != Pushed::Dropped && series.last_kept() {
                batch.push((i, series_index(series), at_s, *v));
            }
        }
    }

    /// Where the series of `objects` stand, in order: (index, samples seen, stride), leaving
    /// out the objects not plotted (beyond [`SERIES`]); `None` without a run under way, or
    /// when two objects are one series (only [`StationView::sample`] counts those right).
    pub fn positions(&self, objects: &[(String, Option<String>)]) -> Option<Vec<(usize, u64, u64)>> {
        let run = self.run.as_ref().filter(|r| r.result.is_none())?;
        let mut found: Vec<(usize, u64, u64)> = Vec::with_capacity(objects.len());
        for (name, _) in objects {
            let Some(i) = run.series.iter().position(|s| s.name == *name) else {
                continue;
            };
            if found.iter().any(|f| f.0 == i) {
                return None;
            }
            let (seen, stride) = run.series[i].position();
            found.push((i, seen, stride));
        }
        Some(found)
    }

    /// `rows` sample rows up to `at_s` that every one of `series` drops (as
    /// [`StationView::positions`] tells): counted as [`StationView::sample`] would.
    pub fn skip(&mut self, at_s: f64, series: &[usize], rows: u64) {
        let Some(run) = self.current() else { return };
        run.elapsed_s = run.elapsed_s.max(at_s);
        for i in series {
            if let Some(s) = run.series.get_mut(*i) {
                s.skip(rows);
            }
        }
    }

    /// The event carrying `batch`, with each series' stride (a page halves its own points
    /// until its stride matches before it appends these).
    pub fn points(&self, batch: &[(usize, u64, f64, f64)]) -> Option<Value> {
        let run = self.run.as_ref()?;
        if batch.is_empty() {
            return None;
        }
        let series: Vec<Value> = run
            .series
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let (t, v): (Vec<f64>, Vec<f64>) =
                    batch.iter().filter(|p| p.0 == i).map(|p| (p.2, p.3)).unzip();
                json!({"name": s.name, "unit": s.unit, "stride": s.stride, "t": t, "v": v})
            })
            .collect();
        Some(json!({"kind": "points", "series": series, "elapsed_s": run.elapsed_s}))
    }

    pub fn stop_pressed(&mut self) -> Option<Value> {
        let run = self.current()?;
        run.stops += 1;
        Some(json!({"kind": "stops", "stops": run.stops}))
    }

    pub fn finish(&mut self, result: ResultView) -> Option<Value> {
        let run = self.run.as_mut()?;
        run.dialog = None;
        let event = json!({"kind": "result", "result": &result});
        run.result = Some(result);
        Some(event)
    }

    pub fn close(&mut self) -> Value {
        self.closing = true;
        json!({"kind": "closing"})
    }
}

/// The index (in samples seen) of the series' last kept point.
fn series_index(series: &PlotBuffer) -> u64 {
    (series.t.len() as u64 - 1) * series.stride
}
