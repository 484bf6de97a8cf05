//! The recipe interpreter: runs validated steps against a [`Drive`], reports through a
//! [`RunObserver`], and ALWAYS ends with the safe stop: `on_fault` after a drive fault,
//! then `finally` (or the default: disable operation, then shutdown), then a check that the
//! power stage is really off. Knows names and units, never bytes.

use super::condition::{number, Check, Condition, Predicate, Stats};
use super::loader::show_duration;
use super::recipe::Recipe;
use super::run_observer::RunObserver;
use super::run_report::{CheckResult, RunReport, Series, StepRecord, Verdict};
use super::step::{ObjectRef, SetValue, Step, StepKind, StepOrigin};
use crate::clock::SharedClock;
use crate::dictionary::Quantity;
use crate::drive::{Drive, DriveError};
use crate::protocol::device_control::{DeviceCommand, DeviceState};
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Duration;

/// How often `dwell` and `repeat` look at the drive for faults.
const FAULT_WATCH: Duration = Duration::from_millis(100);

/// Asks how many times Ctrl-C was pressed.
pub type InterruptCount<'a> = &'a (dyn Fn() -> u32 + 'a);

/// Why the steps stopped early.
#[derive(Debug)]
enum Stop {
    /// An expectation failed in a way the following steps cannot continue from.
    Failed(String),
    /// The drive went to fault.
    Fault(String),
    /// Communication or another drive error.
    Error(String),
    Interrupted,
}

/// Whether a step went well, and what to say about it.
fn outcome(result: &Result<String, Stop>) -> (bool, String) {
    match result {
        Ok(d) => (true, d.clone()),
        Err(Stop::Failed(m)) | Err(Stop::Fault(m)) | Err(Stop::Error(m)) => (false, m.clone()),
        Err(Stop::Interrupted) => (false, "interrupted".to_string()),
    }
}

impl From<DriveError> for Stop {
    fn from(e: DriveError) -> Self {
        match e {
            DriveError::Interrupted => Stop::Interrupted,
            DriveError::Fault { .. } => Stop::Fault(e.to_string()),
            other => Stop::Error(other.to_string()),
        }
    }
}

pub struct Runner<'a> {
    drive: &'a mut Drive,
    observer: &'a mut dyn RunObserver,
    interrupts: InterruptCount<'a>,
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
    /// Ctrl-C presses that do not count: 0 while the steps run, 1 during the safe stop
    /// (only a second press interrupts that).
    interrupt_allowance: u32,
}

impl<'a> Runner<'a> {
    pub fn new(
        drive: &'a mut Drive,
        observer: &'a mut dyn RunObserver,
        interrupts: InterruptCount<'a>,
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
            safe_stop: Vec::new(),
        };
        Runner {
            drive,
            observer,
            interrupts,
            clock,
            output_dir: PathBuf::from("."),
            windows: HashMap::new(),
            csv_files: std::collections::HashSet::new(),
            report,
            failed_checks: false,
            last_fault_check: Duration::ZERO,
            run_start: clock_now,
            known_fault: false,
            interrupt_allowance: 0,
        }
    }

    /// Where `csv:` files of sample steps go (relative paths).
    pub fn with_output_dir(mut self, dir: PathBuf) -> Self {
        self.output_dir = dir;
        self
    }

    /// Runs the recipe to the end, whatever happens, and returns what happened.
    pub fn run(mut self, recipe: &Recipe) -> RunReport {
        let start = self.clock.now();
        self.run_start = start;
        self.observer.run_started(recipe, &self.report.drive);
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
        let outcome = self.steps(&recipe.steps, "", "steps");
        let stop = outcome.err();
        if let Some(Stop::Fault(_)) = &stop {
            if !recipe.on_fault.is_empty() {
                self.best_effort(&recipe.on_fault, "on_fault");
            }
        }
        self.report.verdict = match &stop {
            None if self.failed_checks => Verdict::Failed,
            None => Verdict::Passed,
            Some(Stop::Failed(_)) => Verdict::Failed,
            Some(Stop::Fault(m)) | Some(Stop::Error(m)) => Verdict::Error(m.clone()),
            Some(Stop::Interrupted) => Verdict::Interrupted,
        };
        self.safe_stop(recipe);
        self.report.duration = self.clock.now() - start;
        self.observer.run_finished(&self.report);
        self.report
    }

    fn identity(&mut self) -> Option<String> {
        let name = self.drive.dictionary().lookup("ident").ok()?.name.clone();
        self.drive.read(&name).ok().map(|v| v.to_string())
    }

    fn interrupted(&self) -> bool {
        (self.interrupts)() > self.interrupt_allowance
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
            let result = self.step(step, &number, phase);
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
            duration: self.clock.now() - started,
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
                let (interrupts, allowance) = (self.interrupts, self.interrupt_allowance);
                let transitions = self
                    .drive
                    .go_to(*state, *timeout, &move || interrupts() > allowance)?;
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
                for (object, value) in writes {
                    match value {
                        SetValue::Number(n) => {
                            let unit = object
                                .unit
                                .as_deref()
                                .and_then(crate::dictionary::Unit::from_symbol);
                            self.drive.write(&object.name, &Quantity::new(*n, unit))?
                        }
                        SetValue::Text(t) => self.drive.write_text(&object.name, t)?,
                    }
                }
                Ok("written".into())
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
        loop {
            let (holds, seen, value) = self.read_condition(condition)?;
            let waited = self.clock.now() - started;
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
            let next = (started + waited + every).min(started + timeout);
            self.clock.sleep_until(next);
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
            duration: self.clock.now() - started,
        };
        self.observer.check(&result);
        self.report.checks.push(result);
    }

    fn dwell(&mut self, d: Duration, number: &str) -> Result<(), Stop> {
        let start = self.clock.now();
        let end = start + d;
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
            self.clock.sleep_until((now + FAULT_WATCH).min(end));
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
        loop {
            let due = start + every * k;
            if due > start + duration {
                break;
            }
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.clock.sleep_until(due);
            let at = self.clock.now();
            if at > due + every {
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
                duration: self.clock.now() - started,
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
        let total = every * points.len().saturating_sub(1) as u32;
        for (i, p) in points.iter().enumerate() {
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.clock.sleep_until(start + every * i as u32);
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
                (_, Some(d)) => self.clock.now() - start < d,
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

    /// Runs steps whatever fails; errors are recorded and the next step is tried. A second
    /// Ctrl-C abandons the rest.
    fn best_effort(&mut self, steps: &[Step], phase: &'static str) {
        self.interrupt_allowance = 1;
        for (i, step) in steps.iter().enumerate() {
            if (self.interrupts)() >= 2 {
                self.report
                    .safe_stop
                    .push(format!("{phase} abandoned at step {} (second Ctrl-C)", i + 1));
                return;
            }
            let number = format!("{phase}.{}", i + 1);
            self.observer.step_started(&number, step, phase);
            let started = self.clock.now();
            let result = self.step(step, &number, phase);
            let (ok, detail) = outcome(&result);
            if !ok {
                self.report.safe_stop.push(format!(
                    "{phase} step {} ({}) failed: {detail}",
                    i + 1,
                    step.label
                ));
            }
            self.record_step(number, step, ok, detail, started, phase);
        }
    }

    /// `finally` (or the default), then make sure the power stage is off unless a
    /// successful recipe asked to leave it on. A second Ctrl-C switches it off at once.
    fn safe_stop(&mut self, recipe: &Recipe) {
        let default_finally;
        let finally: &[Step] = match &recipe.finally {
            Some(steps) => steps,
            None => {
                default_finally = default_finally_steps(&recipe.path);
                &default_finally
            }
        };
        self.best_effort(finally, "finally");
        if (self.interrupts)() >= 2 {
            self.emergency_off();
        }
        let keep = recipe.leave_enabled && self.report.verdict == Verdict::Passed;
        match self.drive.state() {
            Ok(state) => {
                self.report.final_state = Some(state);
                if state.is_powered() && !keep && state != DeviceState::FaultReactionActive {
                    self.report.safe_stop.push(format!(
                        "the drive was still in {state} after finally; disabling it"
                    ));
                    for c in [DeviceCommand::DisableOperation, DeviceCommand::Shutdown] {
                        if let Err(e) = self.drive.command(c) {
                            self.report.safe_stop.push(format!("{c} failed: {e}"));
                            self.emergency_off();
                            break;
                        }
                    }
                    self.report.final_state = self.drive.state().ok();
                }
            }
            Err(e) => self.report.safe_stop.push(format!(
                "could not read the drive's state after the safe stop: {e}; CHECK THE DRIVE BY HAND"
            )),
        }
    }

    fn emergency_off(&mut self) {
        match self.drive.command(DeviceCommand::DisableVoltage) {
            Ok(()) => self
                .report
                .safe_stop
                .push("power stage switched off at once (disable voltage)".into()),
            Err(e) => self
                .report
                .safe_stop
                .push(format!("disable voltage failed: {e}; CHECK THE DRIVE BY HAND")),
        }
    }
}

/// The default `finally`: disable operation, then shutdown.
pub fn default_finally_steps(path: &str) -> Vec<Step> {
    [DeviceCommand::DisableOperation, DeviceCommand::Shutdown]
        .into_iter()
        .map(|c| Step {
            kind: StepKind::Command(c),
            origin: StepOrigin {
                path: path.to_string(),
                line: 0,
                column: 0,
            },
            label: format!("{} (default finally)", c.id()),
        })
        .collect()
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
