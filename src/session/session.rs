//! A run of drive operations, the same for recipes and scripts: it owns the run report,
//! reports every operation through a [`RunObserver`], wakes every wait on a stop request,
//! catches panics, and watches the drive for faults. The operations themselves live in the
//! files next to this one; the end of every run, the safe stop, in `safe_stop.rs`. Knows
//! names, units and states; never bytes, never a family, never YAML.

use super::session_drive::SessionDrive;
use super::step_path::StepPath;
use super::stop::{outcome, panic_message, Stop};
use super::{
    exact_with_unit, with_unit, CheckResult, Condition, Nobody, ObjectRef, Operator, Predicate, RunInfo,
    RunObserver, RunReport, SafeStopSettings, StepInfo, StepRecord, UnitIdentity, MAX_RECORDS,
};
use crate::clock::SharedClock;
use crate::drive::device_control::DeviceState;
use crate::drive::Drive;
use crate::stop_request::StopRequests;
use std::collections::{HashMap, HashSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::time::Duration;

pub struct Session<'a> {
    /// The drives of the run: one (named ``) for a single-drive recipe or script, or the
    /// recipe's named drives in the order declared.
    pub(super) drives: Vec<SessionDrive<'a>>,
    /// The drive that commands, state reads and the safe stop's steps go to now.
    pub(super) current: usize,
    /// Counts enabling commands, to order the drives for the safe stop.
    pub(super) enable_count: u64,
    pub(super) observer: &'a mut dyn RunObserver,
    pub(super) stop: &'a StopRequests,
    pub(super) settings: SafeStopSettings,
    pub(super) clock: SharedClock,
    /// Directory that relative `csv:` paths of sample steps are written to.
    pub(super) output_dir: PathBuf,
    /// The statistics of the last sample window per object, and the id of the step that
    /// sampled it.
    pub(super) windows: HashMap<String, super::SampleWindow>,
    pub(super) window_steps: HashMap<String, String>,
    /// CSV files written in this run: a sample step that runs again (in a repeat) appends
    /// to its file instead of overwriting what the earlier pass recorded.
    pub(super) csv_files: HashSet<PathBuf>,
    pub(super) report: RunReport,
    pub(super) failed_checks: bool,
    pub(super) last_fault_check: Duration,
    /// Clock time the run started; series times count from here.
    pub(super) run_start: Duration,
    /// `on_fault`, `finally` and the verification run: only a second stop request counts.
    pub(super) in_safe_stop: bool,
    /// The run's `watch:` limits and where each stands.
    pub(super) watches: Vec<(super::Watch, super::watch::WatchState)>,
    /// What the running sample step read last, for the watches of the same objects.
    pub(super) sampled: super::watch::SampledValues,
    /// The steps around the current one, for iteration-aware step ids and stages.
    pub(super) path: StepPath,
    /// `csv:` files of sample steps with one column per object instead of the long layout.
    pub(super) csv_wide: bool,
    pub(super) run: RunInfo,
    /// Where the answers to operator steps come from.
    pub(super) operator: Box<dyn Operator + 'a>,
    /// The speed setpoints written, for the report's whole-run timeline (bounded buckets).
    pub(super) setpoints: Option<(super::ObjectRef, super::BucketSeries)>,
    /// Where the unit's past runs are read (a results store), the checks that compare
    /// with its last pass, and what was found.
    pub(super) history: Option<std::sync::Arc<dyn super::History>>,
    /// (name, key) of each check that compares, for what the lookup says.
    pub(super) history_checks: Vec<(String, String)>,
    pub(super) past: super::history_lookup::Past,
    /// Faults the drives reported on their own while the run ended, said after the stop.
    pub(super) reported_in_stop: Vec<String>,
}

impl<'a> Session<'a> {
    pub fn new(
        drive: &'a mut Drive,
        observer: &'a mut dyn RunObserver,
        stop: &'a StopRequests,
        run: RunInfo,
    ) -> Self {
        Self::with_drives(vec![(String::new(), drive)], observer, stop, run)
    }

    /// A run over several named drives (a recipe's `drives:`), which must share one clock.
    /// Objects are then named `left.speed_actual`; the first drive names the report's port
    /// line together with the others.
    pub fn with_drives(
        drives: Vec<(String, &'a mut Drive)>,
        observer: &'a mut dyn RunObserver,
        stop: &'a StopRequests,
        run: RunInfo,
    ) -> Self {
        let drives: Vec<SessionDrive<'a>> = drives
            .into_iter()
            .map(|(name, drive)| SessionDrive::new(name, drive))
            .collect();
        let clock = drives[0].drive.clock().clone();
        let port = if drives.len() == 1 && drives[0].name.is_empty() {
            drives[0].drive.port()
        } else {
            drives
                .iter()
                .map(|d| format!("{}: {}", d.name, d.drive.port()))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let clock_now = clock.now();
        let mut report = RunReport::started(
            run.name.clone(),
            run.path.clone(),
            port,
            run.params.clone(),
            clock.wall_time(),
        );
        report.unit = run.unit.clone();
        report.recipe_sha256 = run.text_sha256.clone();
        Session {
            drives,
            current: 0,
            enable_count: 0,
            observer,
            stop,
            settings: SafeStopSettings::default(),
            clock,
            output_dir: PathBuf::from("."),
            windows: HashMap::new(),
            window_steps: HashMap::new(),
            csv_files: HashSet::new(),
            report,
            failed_checks: false,
            last_fault_check: Duration::ZERO,
            run_start: clock_now,
            in_safe_stop: false,
            watches: Vec::new(),
            sampled: Default::default(),
            path: StepPath::default(),
            csv_wide: false,
            run,
            operator: Box::new(Nobody),
            setpoints: None,
            history: None,
            history_checks: Vec::new(),
            past: Default::default(),
            reported_in_stop: Vec::new(),
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

    /// The unit under test as the command line gives it (`--unit`), before the run starts.
    pub fn with_unit(mut self, unit: UnitIdentity) -> Self {
        self.report.unit = unit.clone();
        self.run.unit = unit;
        self
    }

    /// Where the answers to operator steps come from (default: nobody, so every prompt
    /// fails).
    pub fn with_operator(mut self, operator: Box<dyn Operator + 'a>) -> Self {
        self.operator = operator;
        self
    }

    /// `csv:` files of sample steps with one column per object (`--csv-wide`).
    pub fn with_csv_wide(mut self, wide: bool) -> Self {
        self.csv_wide = wide;
        self
    }

    /// Where the unit's past runs are read, for the checks (name, key) that compare with
    /// its last passed run; looked up once the serial is known.
    pub fn with_history(
        mut self,
        history: Option<std::sync::Arc<dyn super::History>>,
        checks: Vec<(String, String)>,
    ) -> Self {
        self.history = history;
        self.history_checks = checks;
        self
    }

    /// Announces the run and looks at the drive (identity, a fault at the start). Call
    /// once, before the first operation.
    pub fn begin(&mut self) {
        self.run_start = self.clock.now();
        let run = self.run.clone();
        self.observer.run_started(&run, &self.report.drive);
        let _ = self.guarded(|s| {
            s.look_at_the_drive();
            Ok(())
        });
        // Before anything moves; a stop request during it is seen by the first step.
        let _ = self.guarded(|s| s.look_up_last_pass(false));
    }

    pub fn clock(&self) -> &SharedClock {
        &self.clock
    }

    /// The current drive (see [`Session::select`]).
    pub(super) fn drive(&mut self) -> &mut Drive {
        &mut *self.drives[self.current].drive
    }

    pub(super) fn drive_ref(&self) -> &Drive {
        &*self.drives[self.current].drive
    }

    pub(super) fn cur(&mut self) -> &mut SessionDrive<'a> {
        &mut self.drives[self.current]
    }

    /// Whether the run's drives are named (a recipe's `drives:`, even with one entry):
    /// objects then carry the drive's name (`left.speed_actual`).
    pub fn several_drives(&self) -> bool {
        self.drives.len() > 1 || self.drives.iter().any(|d| !d.name.is_empty())
    }

    /// Makes the drive called `name` the current one.
    pub fn select(&mut self, name: &str) -> Result<(), Stop> {
        match self.drives.iter().position(|d| d.name == name) {
            Some(i) => {
                self.current = i;
                Ok(())
            }
            None => Err(Stop::Error(format!(
                "no drive called `{name}` in this run (drives: {})",
                self.drive_names().join(", ")
            ))),
        }
    }

    pub(super) fn drive_names(&self) -> Vec<String> {
        self.drives.iter().map(|d| d.name.clone()).collect()
    }

    /// Makes the drive an object reference names (`left.speed_actual`) the current one and
    /// returns the object's name in that drive's dictionary. A name without a drive is the
    /// current drive's (the only drive's in a single-drive run).
    pub(super) fn select_object<'n>(&mut self, name: &'n str) -> Result<&'n str, Stop> {
        match name.split_once('.') {
            Some((drive, object)) if self.several_drives() => {
                self.select(drive)?;
                Ok(object)
            }
            _ => Ok(name),
        }
    }

    /// The indexes of the drives in the order the safe stop takes them: the last enabled
    /// first, then the ones never enabled in declaration order.
    pub(super) fn stop_order(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.drives.len()).collect();
        // Stable: drives never enabled (0) keep their declared order, after the others.
        order.sort_by_key(|&i| std::cmp::Reverse(self.drives[i].enabled_order));
        order
    }

    /// Runs `f`, turning a panic inside it into [`Stop::Panicked`].
    pub fn guarded(&mut self, f: impl FnOnce(&mut Self) -> Result<(), Stop>) -> Result<(), Stop> {
        match catch_unwind(AssertUnwindSafe(|| f(self))) {
            Ok(result) => result,
            Err(payload) => Err(Stop::Panicked(panic_message(payload.as_ref()))),
        }
    }

    /// Runs one step or operation: announces it, runs `op` (a panic inside is caught, so
    /// the step it happened in is recorded), records what came of it. A result whose text
    /// starts with `FAILED` is recorded as failed but lets the run go on (a failed check).
    pub fn perform(
        &mut self,
        info: &StepInfo,
        op: impl FnOnce(&mut Self) -> Result<String, Stop>,
    ) -> Result<String, Stop> {
        self.observer.step_started(info);
        self.path.enter(info);
        let id = self.path.id();
        self.observer.step_placed(&id);
        let started = self.clock.now();
        let result = match catch_unwind(AssertUnwindSafe(|| op(self))) {
            Ok(r) => r,
            Err(payload) => Err(Stop::Panicked(panic_message(payload.as_ref()))),
        };
        // A sample step lends its values to the watches only while it runs, however it ended.
        self.sampled.values.clear();
        // Only a failed check or wait is tried again by an `attempts` block; every other
        // stop ends the run, and its lines must not promise another attempt.
        if matches!(&result, Err(stop) if !matches!(stop, Stop::Failed(_))) {
            self.observer.attempts_given_up();
        }
        let (ok, detail) = outcome(&result);
        let ok = ok && !detail.starts_with("FAILED");
        self.record_step(info, id, ok, detail, started);
        self.path.leave();
        result
    }

    /// The current step (a repeat) begins its `n`th iteration (from 1): the ids of the
    /// steps inside it carry `[n]`.
    pub fn iteration(&mut self, n: u32) {
        self.path.iteration(n);
    }

    /// The current step's iteration-aware id and the stage that holds it, for checks.
    pub(super) fn place(&self) -> (String, String) {
        (self.path.id(), self.path.stage())
    }

    fn record_step(&mut self, info: &StepInfo, id: String, ok: bool, detail: String, started: Duration) {
        let record = StepRecord {
            number: info.number.clone(),
            id,
            label: info.label.clone(),
            origin: info.origin.clone(),
            ok,
            detail,
            started,
            duration: self.clock.now().saturating_sub(started),
            phase: info.phase,
        };
        self.observer.step_finished(&record);
        let nested = record.phase == "steps" && record.number.contains('.');
        if record.ok && nested && self.report.steps.len() >= MAX_RECORDS {
            self.report.omitted_steps += 1;
        } else {
            self.report.steps.push(record);
        }
    }

    /// Records a check result (see [`MAX_RECORDS`] for what is kept).
    pub(super) fn record_check_result(&mut self, mut result: CheckResult) {
        if result.decimals.is_none() {
            result.decimals = result
                .object
                .as_deref()
                .and_then(|o| self.scale_of(o))
                .map(super::object_scale::decimals_of_scale);
        }
        self.observer.check(&result);
        if result.passed && self.report.checks.len() >= MAX_RECORDS {
            self.report.omitted_checks += 1;
        } else {
            self.report.checks.push(result);
        }
    }

    /// A line under the current step (a value read, a message).
    pub fn message(&mut self, text: &str) {
        self.observer.message(text);
    }

    /// `run -x`: every failed check ends the run.
    pub fn stops_on_failure(&self) -> bool {
        self.settings.stop_on_failure
    }

    /// Whether anything shows progress; nothing is built for a screen that is not there.
    pub fn wants_progress(&self) -> bool {
        self.observer.wants_progress()
    }

    /// Progress of a long step: elapsed, total (when known) and live values.
    pub fn progress(&mut self, number: &str, elapsed: Duration, total: Option<Duration>, values: &str) {
        self.observer.step_progress(number, elapsed, total, values);
    }

    /// Identity and fault state at the start, both best effort.
    fn look_at_the_drive(&mut self) {
        for i in 0..self.drives.len() {
            self.current = i;
            let ident = self.ident_value();
            self.cur().identity = ident.as_ref().map(|v| v.to_string());
            if i == 0 {
                self.report.identity = self.drive_identity(ident.as_ref());
            }
            let faulted = matches!(
                self.drive().state(),
                Ok(DeviceState::Fault | DeviceState::FaultReactionActive)
            );
            self.cur().known_fault = faulted;
            if faulted {
                let code = self.drive().drive_error().unwrap_or(0);
                let code = self.drive().drive_error_note(code);
                let called = self.drives[i].called();
                self.observer
                    .message(&format!("{called} is in fault at the start{code}"));
            }
            // What the drive reported before the run began is told, not a stop: the
            // recipe decides (a fault_reset first), as for a fault at the start.
            if let Some(what) = self.drive().reported_fault() {
                let called = self.drives[i].called();
                self.observer
                    .message(&format!("{called} reported {what} before the run began"));
            }
        }
        self.current = 0;
    }

    /// A stop request that nobody answers yet. During the safe stop only a second request
    /// counts: the first one, arriving while `finally` already runs, asks for what is
    /// being done anyway.
    pub fn interrupted(&self) -> bool {
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
    /// [`Session::interrupted`]) ends the wait at once.
    pub fn wait(&mut self, deadline: Duration) -> Result<(), Stop> {
        // Whatever the reporters hold back goes out before the run goes quiet.
        self.observer.idle();
        loop {
            // A channel the drive expects telegrams on is served in between (the cyclic
            // telegram); the wait is cut into its periods.
            let mut until = deadline;
            for i in 0..self.drives.len() {
                if self.drives[i].link_given_up {
                    continue;
                }
                match self.drives[i].drive.keep_alive() {
                    Ok(Some(next)) => until = until.min(self.clock.now().saturating_add(next)),
                    Ok(None) => {}
                    // In the safe stop one drive's lost channel must not end the waits that
                    // stop the others; its own steps report the loss.
                    Err(_) if self.in_safe_stop => {}
                    Err(e) => return Err(e.into()),
                }
            }
            while self.clock.wait_until(until, self.stop) {
                if self.interrupted() {
                    return Err(Stop::Interrupted);
                }
            }
            if until >= deadline {
                return Ok(());
            }
        }
    }

    /// The object playing `role` in the profile, as a step names it.
    pub(super) fn role_ref(&self, role: crate::dictionary::Role) -> Option<ObjectRef> {
        let name = self.drive_ref().profile().ok()?.object(role)?.to_string();
        let def = self.drive_ref().object(&name).ok()?;
        Some(ObjectRef {
            name: def.name.clone(),
            unit: def.unit.map(|u| u.symbol().to_string()),
        })
    }

    /// Reads the state of every drive now and then (at most every `settings.fault_poll`,
    /// or at once when `now`); a fault on any of them stops the run.
    pub fn watch_fault(&mut self, now: bool) -> Result<(), Stop> {
        self.say_link_notices();
        self.check_watches()?;
        let t = self.clock.now();
        if !now && t < self.last_fault_check.saturating_add(self.settings.fault_poll) {
            return Ok(());
        }
        self.last_fault_check = t;
        let current = self.current;
        for i in 0..self.drives.len() {
            self.current = i;
            // On a fault the faulted drive stays the current one.
            self.watch_fault_of_current()?;
        }
        self.current = current;
        Ok(())
    }

    /// Says on the console what the drives' links did on their own (a node's NMT start).
    pub(super) fn say_link_notices(&mut self) {
        for i in 0..self.drives.len() {
            for text in self.drives[i].drive.notices() {
                self.observer.message(&text);
            }
        }
    }

    fn watch_fault_of_current(&mut self) -> Result<(), Stop> {
        // Without a device-control profile there is no state to watch, but a fault the
        // drive reports on its own (a CANopen node's EMCY) is one all the same.
        let fresh = self.settings.fault_poll / 4;
        let state = match self.drive().profile() {
            Ok(_) => Some(self.drive().state_within(fresh)?),
            Err(_) => None,
        };
        let faulted = matches!(state, Some(DeviceState::Fault | DeviceState::FaultReactionActive));
        let entered = faulted && !self.cur().known_fault;
        self.cur().known_fault = faulted;
        // Taken at every look, so that a fault the state shows as well is told once; once
        // the run is ending (on_fault, the safe stop) it stops nothing more and is said
        // after the stop.
        let reported = self.drive().reported_fault();
        let called = self.cur().called();
        if let (true, Some(state)) = (entered, state) {
            let code = self.drive().drive_error().unwrap_or(0);
            let code = self.drive().drive_error_note(code);
            // The drive's own report (a CANopen EMCY with its CiA 301 text) belongs in the
            // run's error line, not only in the `-v` lines.
            let told = reported
                .map(|what| format!("; it reported {what}"))
                .unwrap_or_default();
            return Err(Stop::Fault(format!(
                "drive fault: {called} went to {state}{code}{told}"
            )));
        }
        let Some(what) = reported else {
            return Ok(());
        };
        let reported = match state {
            Some(state) => format!("{called} reported {what} while in {state}"),
            None => format!("{called} reported {what}"),
        };
        if self.in_safe_stop {
            self.keep_reported_in_stop(reported);
            return Ok(());
        }
        Err(Stop::Fault(format!("drive fault: {reported}")))
    }

    pub(super) fn read_condition(
        &mut self,
        condition: &Condition,
    ) -> Result<(bool, String, Option<f64>), Stop> {
        match condition {
            // Every drive of the run in the state (the one drive of a single-drive run).
            Condition::State(target) => {
                let mut all = true;
                let mut seen = Vec::new();
                for i in 0..self.drives.len() {
                    let state = self.drives[i].drive.state()?;
                    all &= state == *target;
                    seen.push(match self.several_drives() {
                        true => format!("{}: {state}", self.drives[i].name),
                        false => state.to_string(),
                    });
                }
                Ok((all, seen.join(", "), None))
            }
            Condition::Value { object, predicate } => {
                let name = self.select_object(&object.name)?;
                if let Predicate::EqualsText(_) = predicate {
                    let v = self.drive().read(name)?.to_string();
                    let text = v.trim_matches('"').to_string();
                    return Ok((predicate.holds_text(&text), v, None));
                }
                let q = self.drive().read_quantity(name)?;
                let seen = match q.whole() {
                    Some(_) => exact_with_unit(&q, object.unit.as_deref()),
                    None => value_of(q.value, object),
                };
                // Beyond a float's precision the text (`seen`) is the measured value reports show.
                let measured = (!q.beyond_float()).then_some(q.value);
                Ok((predicate.holds_quantity(&q), seen, measured))
            }
            // One reading has no slope; `wait_until_stable` keeps the history.
            Condition::Stable { object, .. } => {
                let name = self.select_object(&object.name)?;
                let v = self.drive().read_number(name)?;
                Ok((false, value_of(v, object), Some(v)))
            }
        }
    }
}

/// A measured value of `o`, rounded, with its unit.
pub(super) fn value_of(v: f64, o: &ObjectRef) -> String {
    with_unit(round(v), o.unit.as_deref())
}

/// Three decimals is finer than any scale an engineer reads.
pub(super) fn round(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// A duration as recipes write it: `2h`, `1m 30s`, `100ms`.
pub fn show_duration(d: Duration) -> String {
    humantime::format_duration(d).to_string()
}

pub(super) fn secs(d: Duration) -> String {
    format!("{:.2} s", d.as_secs_f64())
}
