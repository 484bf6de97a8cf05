//! The recipe interpreter: runs validated steps against a [`Drive`], reports through a
//! [`RunObserver`], and ALWAYS ends with the safe stop (see `safe_stop.rs`), whatever ended
//! the steps: success, a failed check, an error, a stop request, a lost link or a panic.
//! Every wait wakes on a stop request. Knows names and units, never bytes.

mod safe_stop;
mod settings;

pub use safe_stop::default_finally_steps;
pub use settings::SafeStopSettings;

use super::loader::show_duration;
use super::recipe::Recipe;
use super::run_observer::RunObserver;
use super::step::{ObjectRef, SetValue, Step, StepKind};
use crate::clock::SharedClock;
use crate::dictionary::Quantity;
use crate::drive::device_control::DeviceState;
use crate::drive::{Drive, DriveError, WriteOutcome};
use crate::session::{number, Check, Condition, Predicate, Stats};
use crate::session::{CheckResult, RunReport, Series, StepRecord, Verdict};
use crate::stop_request::{StopRequests, StopSignal};
use std::collections::HashMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::time::Duration;

/// How often `dwell` and `repeat` look at the drive for faults.
const FAULT_WATCH: Duration = Duration::from_millis(100);

/// Why the steps stopped early.
#[derive(Debug)]
enum Stop {
    /// An expectation failed in a way the following steps cannot continue from.
    Failed(String),
    /// The drive went to fault.
    Fault(String),
    /// The port failed (device gone, connection closed): only reopening it can help.
    LinkLost(String),
    /// Communication or another drive error.
    Error(String),
    /// A stop request (signal).
    Interrupted,
    /// A panic inside the run: a bug, but the drive must still be stopped.
    Panicked(String),
}

/// Whether a step went well, and what to say about it.
fn outcome(result: &Result<String, Stop>) -> (bool, String) {
    match result {
        Ok(d) => (true, d.clone()),
        Err(Stop::Failed(m) | Stop::Fault(m) | Stop::LinkLost(m) | Stop::Error(m)) => (false, m.clone()),
        Err(Stop::Interrupted) => (false, "interrupted".to_string()),
        Err(Stop::Panicked(m)) => (false, format!("internal error (panic): {m}")),
    }
}

impl From<DriveError> for Stop {
    fn from(e: DriveError) -> Self {
        if e.is_interrupted() {
            Stop::Interrupted
        } else if e.is_fault() {
            Stop::Fault(e.to_string())
        } else if e.is_link_lost() {
            Stop::LinkLost(e.to_string())
        } else {
            Stop::Error(e.to_string())
        }
    }
}

/// The text of a panic's payload (`panic!("...")` carries a `&str` or a `String`).
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".to_string())
}

/// `start + every × k`, or an error instead of the overflow panic.
fn nth_tick(start: Duration, every: Duration, k: u32) -> Result<Duration, Stop> {
    every
        .checked_mul(k)
        .and_then(|d| start.checked_add(d))
        .ok_or_else(|| Stop::Error(format!("time overflow: {k} × {every:?} after {start:?}")))
}

pub struct Runner<'a> {
    drive: &'a mut Drive,
    observer: &'a mut dyn RunObserver,
    stop: &'a StopRequests,
    settings: SafeStopSettings,
    clock: SharedClock,
    /// Directory that relative `csv:` paths of sample steps are written to.
    output_dir: PathBuf,
    /// The last sample window per object.
    windows: HashMap<String, Vec<f64>>,
    /// CSV files written in this run: a sample step that runs again (in a repeat) appends
    /// to its file instead of overwriting what the earlier pass recorded.
    csv_files: std::collections::HashSet<PathBuf>,
    report: RunReport,
    failed_checks: bool,
    last_fault_check: Duration,
    /// Clock time the run started; series times count from here.
    run_start: Duration,
    /// Whether the drive was in a fault state when last looked at. Fault watching reacts
    /// to the drive *entering* a fault during the run; a drive already in fault (at the
    /// start, or after a step that waited for it) is the recipe's to reset.
    known_fault: bool,
    /// `on_fault`, `finally` and the verification run: only a second stop request counts.
    in_safe_stop: bool,
    /// Reopening the port was tried for the whole reconnect time and failed: later
    /// failures of the safe stop do not wait for it again.
    link_given_up: bool,
}

impl<'a> Runner<'a> {
    pub fn new(
        drive: &'a mut Drive,
        observer: &'a mut dyn RunObserver,
        stop: &'a StopRequests,
        recipe: &Recipe,
    ) -> Self {
        let clock = drive.clock().clone();
        let clock_now = clock.now();
        let report = RunReport {
            recipe: recipe.name.clone(),
            recipe_path: recipe.path.clone(),
            drive: drive.port(),
            identity: None,
            params: recipe
                .params
                .iter()
                .map(|p| (p.name.clone(), p.value.clone()))
                .collect(),
            started_at: clock.wall_time(),
            duration: Duration::ZERO,
            verdict: Verdict::Passed,
            steps: Vec::new(),
            checks: Vec::new(),
            series: Vec::new(),
            final_state: None,
            final_speed: None,
            speed_unit: None,
            coasting: false,
            stop_confirmed: false,
            disobeyed: false,
            safe_stop: Vec::new(),
        };
        Runner {
            drive,
            observer,
            stop,
            settings: SafeStopSettings::default(),
            clock,
            output_dir: PathBuf::from("."),
            windows: HashMap::new(),
            csv_files: std::collections::HashSet::new(),
            report,
            failed_checks: false,
            last_fault_check: Duration::ZERO,
            run_start: clock_now,
            known_fault: false,
            in_safe_stop: false,
            link_given_up: false,
        }
    }

    /// How the safe stop waits for standstill and how long it tries to reopen a lost port.
    pub fn with_settings(mut self, settings: SafeStopSettings) -> Self {
        self.settings = settings;
        self
    }

    /// Where `csv:` files of sample steps go (relative paths).
    pub fn with_output_dir(mut self, dir: PathBuf) -> Self {
        self.output_dir = dir;
        self
    }

    /// Runs the recipe to the end, whatever happens, and returns what happened. A panic in
    /// the steps is caught here so that the safe stop still runs; the caller exits 101.
    pub fn run(mut self, recipe: &Recipe) -> RunReport {
        let start = self.clock.now();
        self.run_start = start;
        self.observer.run_started(recipe, &self.report.drive);
        let ended = self.guarded(|r| {
            r.look_at_the_drive();
            r.steps(&recipe.steps, "", "steps")
        });
        let stop = ended.err();
        if let Some(Stop::Fault(_)) = &stop {
            if !recipe.on_fault.is_empty() {
                self.stop.acknowledge();
                self.in_safe_stop = true;
                let on_fault = self.guarded(|r| {
                    r.best_effort(&recipe.on_fault, "on_fault");
                    Ok(())
                });
                if let Err(e) = on_fault {
                    let (_, why) = outcome(&Err(e));
                    self.report.safe_stop.push(format!("on_fault ended early: {why}"));
                }
            }
        }
        let link_lost = matches!(stop, Some(Stop::LinkLost(_)));
        self.report.verdict = match &stop {
            None if self.failed_checks => Verdict::Failed,
            None => Verdict::Passed,
            Some(Stop::Failed(_)) => Verdict::Failed,
            Some(Stop::Fault(m) | Stop::Error(m) | Stop::LinkLost(m)) => Verdict::Error(m.clone()),
            Some(Stop::Interrupted) => Verdict::Interrupted(self.stop.first().unwrap_or(StopSignal::INT)),
            Some(Stop::Panicked(m)) => Verdict::Panicked(m.clone()),
        };
        self.run_safe_stop(recipe, link_lost);
        self.report.duration = self.clock.now().saturating_sub(start);
        self.observer.run_finished(&self.report);
        self.report
    }

    /// Runs `f`, turning a panic inside it into [`Stop::Panicked`].
    fn guarded(&mut self, f: impl FnOnce(&mut Self) -> Result<(), Stop>) -> Result<(), Stop> {
        match catch_unwind(AssertUnwindSafe(|| f(self))) {
            Ok(result) => result,
            Err(payload) => Err(Stop::Panicked(panic_message(payload.as_ref()))),
        }
    }

    /// Identity and fault state at the start, both best effort.
    fn look_at_the_drive(&mut self) {
        self.report.identity = self.identity();
        self.known_fault = matches!(
            self.drive.state(),
            Ok(DeviceState::Fault | DeviceState::FaultReactionActive)
        );
        if self.known_fault {
            let code = self
                .drive
                .drive_error()
                .map(|c| format!(" (drive error {c}, 0x{c:04x})"))
                .unwrap_or_default();
            self.observer
                .message(&format!("the drive is in fault at the start{code}"));
        }
    }

    fn identity(&mut self) -> Option<String> {
        let name = self.drive.dictionary().lookup("ident").ok()?.name.clone();
        self.drive.read(&name).ok().map(|v| v.to_string())
    }

    /// A stop request that nobody answers yet. During the safe stop only a second request
    /// counts: the first one, arriving while `finally` already runs, asks for what is
    /// being done anyway.
    fn interrupted(&self) -> bool {
        let now = self.clock.now();
        if !self.stop.pending_at(now) {
            return false;
        }
        if self.in_safe_stop && self.stop.count_at(now) < 2 {
            self.stop.acknowledge();
            return false;
        }
        true
    }

    /// Waits until `deadline` on the run's clock; a stop request (see
    /// [`Runner::interrupted`]) ends the wait at once.
    fn wait(&self, deadline: Duration) -> Result<(), Stop> {
        while self.clock.wait_until(deadline, self.stop) {
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
        }
        Ok(())
    }

    fn steps(&mut self, steps: &[Step], prefix: &str, phase: &'static str) -> Result<(), Stop> {
        for (i, step) in steps.iter().enumerate() {
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            let number = if prefix.is_empty() {
                format!("{}", i + 1)
            } else {
                format!("{prefix}.{}", i + 1)
            };
            self.observer.step_started(&number, step, phase);
            let started = self.clock.now();
            // A panic is caught here too, so that the step it happened in is recorded.
            let result = match catch_unwind(AssertUnwindSafe(|| self.step(step, &number, phase))) {
                Ok(r) => r,
                Err(payload) => Err(Stop::Panicked(panic_message(payload.as_ref()))),
            };
            let (ok, detail) = outcome(&result);
            let ok = ok && !matches!(step.kind, StepKind::Expect(_) if detail.starts_with("FAILED"));
            // Nested steps were recorded by their own records; keep the container too.
            self.record_step(number.clone(), step, ok, detail, started, phase);
            result?;
            if phase == "steps" {
                self.watch_fault(true)?;
            }
        }
        Ok(())
    }

    fn record_step(
        &mut self,
        number: String,
        step: &Step,
        ok: bool,
        detail: String,
        started: Duration,
        phase: &'static str,
    ) {
        let record = StepRecord {
            number,
            label: step.label.clone(),
            origin: step.origin.clone(),
            ok,
            detail,
            started,
            duration: self.clock.now().saturating_sub(started),
            phase,
        };
        self.observer.step_finished(&record);
        self.report.steps.push(record);
    }

    fn step(&mut self, step: &Step, number: &str, phase: &'static str) -> Result<String, Stop> {
        match &step.kind {
            StepKind::Command(c) => {
                self.drive.command(*c)?;
                let value = self.drive.profile()?.command_value(*c);
                Ok(format!("control word {value}"))
            }
            StepKind::GoTo { state, timeout } => {
                // The same rule as `interrupted`, without borrowing the runner, whose drive
                // the walk borrows.
                let (stop, clock, in_safe_stop) = (self.stop, self.clock.clone(), self.in_safe_stop);
                let transitions = self.drive.go_to(*state, *timeout, &move || {
                    let now = clock.now();
                    stop.pending_at(now) && !(in_safe_stop && stop.count_at(now) < 2)
                })?;
                if transitions.is_empty() {
                    Ok(format!("already {state}"))
                } else {
                    Ok(transitions
                        .iter()
                        .map(|t| format!("{} → {}", t.command, t.to))
                        .collect::<Vec<_>>()
                        .join(", "))
                }
            }
            StepKind::Set(writes) => {
                let mut limited = Vec::new();
                for (object, value) in writes {
                    let outcome = match value {
                        SetValue::Number(n) => {
                            let unit = object
                                .unit
                                .as_deref()
                                .and_then(crate::dictionary::Unit::from_symbol);
                            self.drive.write(&object.name, &Quantity::new(*n, unit))?
                        }
                        SetValue::Text(t) => self.drive.write_text(&object.name, t)?,
                    };
                    if let WriteOutcome::Limited(stored) = outcome {
                        limited.push(format!(
                            "{} limited by the drive (stored raw {stored})",
                            object.name
                        ));
                    }
                }
                if limited.is_empty() {
                    Ok("written".into())
                } else {
                    Ok(format!("written; warning: {}", limited.join(", ")))
                }
            }
            StepKind::Read(objects) => {
                let mut shown = Vec::new();
                for o in objects {
                    let v = self.drive.read(&o.name)?;
                    let line = format!("{} = {v}", o.name);
                    self.observer.message(&line);
                    shown.push(line);
                }
                Ok(shown.join(", "))
            }
            StepKind::Print(text) => {
                self.observer.message(text);
                Ok(String::new())
            }
            StepKind::WaitUntil {
                condition,
                timeout,
                every,
            } => self.wait_until(condition, *timeout, *every, step, number),
            StepKind::Dwell(d) => {
                self.dwell(*d, number)?;
                Ok(format!("{} dwelt", show_duration(*d)))
            }
            StepKind::Sample {
                objects,
                every,
                duration,
                csv,
            } => self.sample(objects, *every, *duration, csv.as_ref(), number),
            StepKind::Expect(checks) => self.expect(checks, step),
            StepKind::Ramp {
                object,
                points,
                every,
            } => self.ramp(object, points, *every, number),
            StepKind::Repeat {
                times,
                duration,
                steps,
            } => self.repeat(*times, *duration, steps, number, phase),
            StepKind::Include { steps, .. } => {
                self.steps(steps, number, phase)?;
                Ok(format!("{} steps", steps.len()))
            }
            StepKind::Standstill { below, timeout } => self.standstill(*below, *timeout, number),
        }
    }

    /// Reads the state now and then (at most every [`FAULT_WATCH`], or at once when
    /// `now`); a fault stops the recipe.
    fn watch_fault(&mut self, now: bool) -> Result<(), Stop> {
        let t = self.clock.now();
        if !now && t < self.last_fault_check + FAULT_WATCH {
            return Ok(());
        }
        self.last_fault_check = t;
        let state = self.drive.state()?;
        let faulted = matches!(state, DeviceState::Fault | DeviceState::FaultReactionActive);
        let entered = faulted && !self.known_fault;
        self.known_fault = faulted;
        if entered {
            let code = self.drive.drive_error();
            let code = match code {
                Some(c) if c != 0 => format!(" (drive error {c}, 0x{c:04x})"),
                _ => String::new(),
            };
            return Err(Stop::Fault(format!(
                "drive fault: the drive went to {state}{code}"
            )));
        }
        Ok(())
    }

    fn read_condition(&mut self, condition: &Condition) -> Result<(bool, String, Option<f64>), Stop> {
        match condition {
            Condition::State(target) => {
                let state = self.drive.state()?;
                Ok((state == *target, state.to_string(), None))
            }
            Condition::Value { object, predicate } => {
                if let Predicate::EqualsText(_) = predicate {
                    let v = self.drive.read(&object.name)?.to_string();
                    let text = v.trim_matches('"').to_string();
                    return Ok((predicate.holds_text(&text), v, None));
                }
                let v = self.drive.read_number(&object.name)?;
                Ok((predicate.holds(v), with_unit(v, object), Some(v)))
            }
        }
    }

    fn wait_until(
        &mut self,
        condition: &Condition,
        timeout: Duration,
        every: Duration,
        step: &Step,
        number: &str,
    ) -> Result<String, Stop> {
        let started = self.clock.now();
        let give_up = started.saturating_add(timeout);
        loop {
            let (holds, seen, value) = self.read_condition(condition)?;
            let waited = self.clock.now().saturating_sub(started);
            if holds {
                if matches!(
                    condition,
                    Condition::State(DeviceState::Fault | DeviceState::FaultReactionActive)
                ) {
                    self.known_fault = true;
                }
                self.record_check(
                    step,
                    &condition.to_string(),
                    true,
                    value,
                    Some(seen.clone()),
                    condition,
                    None,
                    started,
                );
                return Ok(format!("{seen} after {}", secs(waited)));
            }
            if !matches!(condition, Condition::State(DeviceState::Fault)) {
                self.watch_fault(false)?;
            }
            if waited >= timeout {
                let message = format!(
                    "timed out after {} waiting for {condition}; last value seen: {seen}",
                    show_duration(timeout)
                );
                self.record_check(
                    step,
                    &condition.to_string(),
                    false,
                    value,
                    Some(seen),
                    condition,
                    Some(message.clone()),
                    started,
                );
                return Err(Stop::Failed(message));
            }
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.observer.step_progress(number, waited, Some(timeout), &seen);
            self.wait(self.clock.now().saturating_add(every).min(give_up))?;
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn record_check(
        &mut self,
        step: &Step,
        name: &str,
        passed: bool,
        value: Option<f64>,
        text: Option<String>,
        condition: &Condition,
        message: Option<String>,
        started: Duration,
    ) {
        let (object, unit, (low, high)) = match condition {
            Condition::State(_) => (None, None, (None, None)),
            Condition::Value { object, predicate } => {
                (Some(object.name.clone()), object.unit.clone(), predicate.limits())
            }
        };
        let result = CheckResult {
            name: format!("wait until {name}"),
            passed,
            measured: value,
            measured_text: text,
            unit,
            low,
            high,
            object,
            statistic: None,
            message: message.unwrap_or_else(|| "reached".into()),
            origin: step.origin.clone(),
            at: self.clock.now(),
            duration: self.clock.now().saturating_sub(started),
        };
        self.observer.check(&result);
        self.report.checks.push(result);
    }

    fn dwell(&mut self, d: Duration, number: &str) -> Result<(), Stop> {
        let start = self.clock.now();
        let end = start.saturating_add(d);
        loop {
            self.watch_fault(true)?;
            let now = self.clock.now();
            if now >= end {
                return Ok(());
            }
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.observer.step_progress(number, now - start, Some(d), "");
            self.wait(now.saturating_add(FAULT_WATCH).min(end))?;
        }
    }

    fn sample(
        &mut self,
        objects: &[ObjectRef],
        every: Duration,
        duration: Duration,
        csv: Option<&PathBuf>,
        number: &str,
    ) -> Result<String, Stop> {
        let mut writer = match csv {
            Some(p) => {
                let path = self.output_dir.join(p);
                let append = !self.csv_files.insert(path.clone());
                Some(SampleCsv::open(&path, objects, append).map_err(Stop::Error)?)
            }
            None => None,
        };
        let start = self.clock.now();
        let run_start = self.run_start;
        let mut series: Vec<Vec<(f64, f64)>> = vec![Vec::new(); objects.len()];
        let mut k: u32 = 0;
        let mut late = 0u32;
        let end = start.saturating_add(duration);
        loop {
            let due = nth_tick(start, every, k)?;
            if due > end {
                break;
            }
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.wait(due)?;
            let at = self.clock.now();
            if at > due.saturating_add(every) {
                late += 1;
            }
            let mut row = Vec::with_capacity(objects.len());
            for (i, o) in objects.iter().enumerate() {
                let v = self.drive.read_number(&o.name)?;
                series[i].push(((at - run_start).as_secs_f64(), v));
                row.push((o.name.clone(), o.unit.clone(), v));
            }
            if let Some(w) = writer.as_mut() {
                w.row((at - run_start).as_secs_f64(), &row).map_err(Stop::Error)?;
            }
            self.observer.sample(at, &row);
            let live = row
                .iter()
                .map(|(n, u, v)| format!("{n} {}", join_unit(*v, u.as_deref())))
                .collect::<Vec<_>>()
                .join(", ");
            self.observer
                .step_progress(number, at - start, Some(duration), &live);
            self.watch_fault(false)?;
            k += 1;
        }
        let mut summary = Vec::new();
        for (i, o) in objects.iter().enumerate() {
            let values: Vec<f64> = series[i].iter().map(|(_, v)| *v).collect();
            let s = Stats::of(&values);
            summary.push(format!(
                "{} mean {} min {} max {}",
                o.name,
                join_unit(round(s.mean), o.unit.as_deref()),
                join_unit(round(s.min), o.unit.as_deref()),
                join_unit(round(s.max), o.unit.as_deref())
            ));
            self.windows.insert(o.name.clone(), values);
            self.report.series.push(Series {
                object: o.name.clone(),
                unit: o.unit.clone(),
                step: number.to_string(),
                points: std::mem::take(&mut series[i]),
            });
        }
        let late_note = if late > 0 {
            format!(
                "; {late} sample(s) late: the line is too slow for every {}",
                show_duration(every)
            )
        } else {
            String::new()
        };
        Ok(format!("{k} samples: {}{late_note}", summary.join("; ")))
    }

    fn expect(&mut self, checks: &[Check], step: &Step) -> Result<String, Stop> {
        let mut failed = Vec::new();
        for c in checks {
            let started = self.clock.now();
            let (passed, measured, text, message) = match c.statistic {
                Some(stat) => {
                    let values = self.windows.get(&c.object.name).cloned().unwrap_or_default();
                    if values.is_empty() {
                        (
                            false,
                            None,
                            None,
                            format!("no samples of {} to check", c.object.name),
                        )
                    } else {
                        let v = Stats::of(&values).get(stat);
                        let ok = c.predicate.holds(v);
                        (
                            ok,
                            Some(v),
                            None,
                            format!("{} {} = {}", c.object.name, stat.id(), with_unit(v, &c.object)),
                        )
                    }
                }
                None => {
                    let cond = Condition::Value {
                        object: c.object.clone(),
                        predicate: c.predicate.clone(),
                    };
                    let (ok, seen, v) = self.read_condition(&cond)?;
                    (ok, v, Some(seen.clone()), format!("{} = {seen}", c.object.name))
                }
            };
            let (low, high) = c.predicate.limits();
            let result = CheckResult {
                name: c.name.clone(),
                passed,
                measured,
                measured_text: text,
                unit: c.object.unit.clone(),
                low,
                high,
                object: Some(c.object.name.clone()),
                statistic: c.statistic.map(|s| s.id().to_string()),
                message: if passed {
                    message
                } else {
                    format!(
                        "{message}, expected {}",
                        c.predicate.describe(c.object.unit.as_deref())
                    )
                },
                origin: step.origin.clone(),
                at: self.clock.now(),
                duration: self.clock.now().saturating_sub(started),
            };
            if !passed {
                self.failed_checks = true;
                failed.push(result.message.clone());
            }
            self.observer.check(&result);
            self.report.checks.push(result);
        }
        if failed.is_empty() {
            Ok(format!("{} check(s) passed", checks.len()))
        } else {
            Ok(format!("FAILED: {}", failed.join("; ")))
        }
    }

    fn ramp(
        &mut self,
        object: &ObjectRef,
        points: &[f64],
        every: Duration,
        number: &str,
    ) -> Result<String, Stop> {
        let unit = object
            .unit
            .as_deref()
            .and_then(crate::dictionary::Unit::from_symbol);
        let start = self.clock.now();
        let last = u32::try_from(points.len().saturating_sub(1)).unwrap_or(u32::MAX);
        let total = every.checked_mul(last).unwrap_or(Duration::MAX);
        for (i, p) in points.iter().enumerate() {
            let due = nth_tick(start, every, u32::try_from(i).unwrap_or(u32::MAX))?;
            self.wait(due)?;
            // Nothing more is written once a stop is requested, not even a point already
            // due: the next setpoint would be a step away from a standstill.
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.drive.write(&object.name, &Quantity::new(*p, unit))?;
            self.observer.step_progress(
                number,
                self.clock.now() - start,
                Some(total),
                &format!("{} = {}", object.name, with_unit(*p, object)),
            );
            self.watch_fault(false)?;
        }
        Ok(format!("{} values written", points.len()))
    }

    fn repeat(
        &mut self,
        times: Option<u32>,
        duration: Option<Duration>,
        steps: &[Step],
        number: &str,
        phase: &'static str,
    ) -> Result<String, Stop> {
        let start = self.clock.now();
        let mut n = 0u32;
        loop {
            let more = match (times, duration) {
                (Some(t), _) => n < t,
                (_, Some(d)) => self.clock.now().saturating_sub(start) < d,
                _ => false,
            };
            if !more {
                break;
            }
            n += 1;
            self.observer.step_progress(
                number,
                self.clock.now() - start,
                duration,
                &format!(
                    "iteration {n}{}",
                    times.map(|t| format!(" of {t}")).unwrap_or_default()
                ),
            );
            self.steps(steps, number, phase)?;
        }
        Ok(format!("{n} iteration(s) in {}", secs(self.clock.now() - start)))
    }
}

fn with_unit(v: f64, o: &ObjectRef) -> String {
    join_unit(round(v), o.unit.as_deref())
}

fn join_unit(v: f64, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{} {u}", number(v)),
        None => number(v),
    }
}

/// Three decimals is finer than any SD2 scale the engineer reads.
fn round(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

fn secs(d: Duration) -> String {
    format!("{:.2} s", d.as_secs_f64())
}

/// A `csv:` file of a sample step, written row by row and flushed, so an aborted run keeps
/// every sample taken.
struct SampleCsv {
    writer: csv::Writer<std::fs::File>,
    path: PathBuf,
}

impl SampleCsv {
    /// Creates the file with its header, or (`append`) continues one this run started.
    fn open(path: &std::path::Path, objects: &[ObjectRef], append: bool) -> Result<Self, String> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(append)
            .write(true)
            .truncate(!append)
            .open(path)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        let mut writer = csv::Writer::from_writer(file);
        if !append {
            let mut header = vec!["time [s]".to_string()];
            header.extend(objects.iter().map(|o| match &o.unit {
                Some(u) => format!("{} [{u}]", o.name),
                None => o.name.clone(),
            }));
            writer
                .write_record(&header)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        let mut s = SampleCsv {
            writer,
            path: path.to_path_buf(),
        };
        s.flush()?;
        Ok(s)
    }

    fn row(&mut self, t: f64, values: &[(String, Option<String>, f64)]) -> Result<(), String> {
        let mut rec = vec![format!("{t:.3}")];
        rec.extend(values.iter().map(|(_, _, v)| number(round(*v))));
        self.writer
            .write_record(&rec)
            .map_err(|e| format!("cannot write {}: {e}", self.path.display()))?;
        self.flush()
    }

    fn flush(&mut self) -> Result<(), String> {
        // csv's flush hands the buffer to the file, which writes it through unbuffered.
        self.writer
            .flush()
            .map_err(|e| format!("cannot write {}: {e}", self.path.display()))
    }
}
