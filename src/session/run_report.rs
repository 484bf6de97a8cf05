//! What a recipe run did: every step with its result and duration, every check with its
//! measured value and limits, every sampled series, and how the run ended. Plain data for
//! the console, JUnit, CSV and HTML reports; no formatting and no I/O here.

use super::condition::Stats;
use super::step_origin::StepOrigin;
use super::UnitIdentity;
use super::{EndState, Limits};
use crate::stop_request::StopSignal;
use std::time::{Duration, SystemTime};

/// How a run ended, in the order of severity of DESIGN.md's exit codes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    Passed,
    /// An expectation failed (an `expect` check, or a `wait_until` that timed out).
    Failed,
    /// Communication failure or drive fault.
    Error(String),
    /// A stop signal (the first one), after the safe stop.
    Interrupted(StopSignal),
    /// A bug: a panic inside the run (its message), after the safe stop.
    Panicked(String),
}

/// The exit code of a panic, as Rust's own runtime uses.
pub const PANIC_EXIT: i32 = 101;
/// Communication failure, drive fault, or a safe stop that could not be confirmed.
pub const ERROR_EXIT: i32 = 3;

impl Verdict {
    pub fn exit_code(&self) -> i32 {
        match self {
            Verdict::Passed => 0,
            Verdict::Failed => 1,
            Verdict::Error(_) => ERROR_EXIT,
            Verdict::Interrupted(signal) => signal.exit_code(),
            Verdict::Panicked(_) => PANIC_EXIT,
        }
    }

    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Passed => "PASSED",
            Verdict::Failed => "FAILED",
            Verdict::Error(_) => "ERROR",
            Verdict::Interrupted(_) => "INTERRUPTED",
            Verdict::Panicked(_) => "PANIC",
        }
    }

    /// One sentence on why the run ended this way, for reports; `None` when it passed or
    /// failed a check (the checks say why).
    pub fn reason(&self) -> Option<String> {
        match self {
            Verdict::Passed | Verdict::Failed => None,
            Verdict::Error(m) => Some(m.clone()),
            Verdict::Interrupted(s) => Some(format!("interrupted by {}", s.describe())),
            Verdict::Panicked(m) => Some(format!("internal error (panic): {m}")),
        }
    }
}

/// One step as it ran.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// `3`, or `7.2.1` inside repeat/include (iteration-independent position).
    pub number: String,
    /// The number with the iteration of every repeat around it: `4[2].1`.
    pub id: String,
    pub label: String,
    pub origin: StepOrigin,
    pub ok: bool,
    /// What came of it: `ready to switch on`, `6001.2 rpm after 3.1 s`, an error text.
    pub detail: String,
    pub started: Duration,
    pub duration: Duration,
    /// `steps`, `finally` or `on_fault`.
    pub phase: &'static str,
}

/// One named check (`expect`, or a `wait_until` condition).
#[derive(Debug, Clone, PartialEq)]
pub struct CheckResult {
    pub name: String,
    /// The name without its limits (`speed_actual mean near`), or the name the recipe
    /// gave: the same check in every run, whatever its limits ([`super::check_key`]).
    pub key: String,
    pub passed: bool,
    /// The measured value in the object's unit (or text for string objects).
    pub measured: Option<f64>,
    pub measured_text: Option<String>,
    pub unit: Option<String>,
    pub limits: Limits,
    /// The object and statistic checked, for plots: (`speed_actual`, `mean`).
    pub object: Option<String>,
    pub statistic: Option<String>,
    pub message: String,
    pub origin: StepOrigin,
    /// The iteration-aware id of the step that made the check: `4[2].3`.
    pub step: String,
    /// For a statistic: the id of the sample step whose window it was computed over (the
    /// [`Series::step`] it belongs to).
    pub window: Option<String>,
    /// The steps that hold it (`Stage 2, 12000 rpm`, `repeat 3 times #2`); empty at the
    /// top level.
    pub stage: String,
    pub at: Duration,
    pub duration: Duration,
    /// Passed, but outside the check's narrower warning band (`warn:`): a unit that drifts
    /// toward a limit. Amber in HTML, `MARGINAL` in the console and JUnit.
    pub marginal: bool,
    /// Made in an `attempts` pass that failed and was tried again: kept in every report,
    /// never the verdict (the last attempt's checks are).
    pub retried: bool,
    /// The value may equal `low` and `high` (`at_least`, `at_most` of a typed value): the
    /// limits read `≥`/`≤`; otherwise a one-sided limit is strict (`above`, `below`).
    pub inclusive: bool,
    /// The decimal places one count of the measured object resolves (the dictionary's
    /// scale): every report shows the value so, never finer (`0.999 A`, not `0.998962 A`);
    /// `None` when no object's resolution applies (a time, a question).
    pub decimals: Option<usize>,
    /// A comparison with the unit's last passed run: the check it compared with.
    pub reference: Option<CheckReference>,
}

/// The check of an earlier run a comparison with the last pass was made against.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckReference {
    /// The earlier run's id in the results store.
    pub run: String,
    /// When it started (UTC, RFC 3339).
    pub started_at: String,
    /// What it measured, in the check's unit.
    pub value: f64,
}

impl CheckResult {
    /// A check named `name` that passed or not, with nothing else said yet: nothing
    /// measured, no limits, no message, no place or time (`..CheckResult::named(…)` under
    /// the fields a caller knows). Its key is its name (a name without limits is its own
    /// key); a caller whose name holds limits gives the key.
    pub fn named(name: impl Into<String>, passed: bool) -> CheckResult {
        let name = name.into();
        CheckResult {
            key: name.clone(),
            name,
            passed,
            measured: None,
            measured_text: None,
            unit: None,
            limits: Limits::default(),
            object: None,
            statistic: None,
            message: String::new(),
            origin: StepOrigin {
                path: String::new(),
                line: 0,
                column: 0,
            },
            step: String::new(),
            window: None,
            stage: String::new(),
            at: Duration::ZERO,
            duration: Duration::ZERO,
            marginal: false,
            retried: false,
            inclusive: false,
            decimals: None,
            reference: None,
        }
    }

    /// The limits as the recipe wrote them, for every report: `5970 .. 6030 rpm`, `= 1`,
    /// `> 5 A`, `< 60 °C`, `≤ 2.8 mm/s`; `None` without limits.
    pub fn limits_text(&self) -> Option<String> {
        self.limits.text(self.unit.as_deref(), self.inclusive)
    }
}

/// A check a recipe holds, known before the run: reports show the ones no result answers
/// as not reached.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedCheck {
    /// As [`CheckResult::name`] will say it.
    pub name: String,
    /// As [`CheckResult::key`] will say it.
    pub key: String,
    pub object: Option<String>,
    pub statistic: Option<String>,
    /// The steps that hold it, as [`CheckResult::stage`] will say it (`repeat 2 times #2`).
    pub stage: String,
    /// The number of the step that holds it, without iterations: `4.1.3`.
    pub step: String,
    pub origin: StepOrigin,
}

/// A sampled series: (time since start in s, value).
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub object: String,
    pub unit: Option<String>,
    /// The iteration-aware id of the step that sampled it (`8[2].3`).
    pub step: String,
    /// What the plot draws; after more samples than the run keeps per series, the lowest
    /// and highest of each interval only.
    pub points: Vec<(f64, f64)>,
    /// The count and statistics of every sample the step took, as its checks saw them;
    /// `None` when `points` are all the samples.
    pub samples: Option<Stats>,
    /// Where the step response of a window with a declared step was measured.
    pub marks: Option<super::ResponseMarks>,
}

/// A bounded series of one object over the whole run: the speed setpoints written, for the
/// timeline.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Track {
    pub object: String,
    pub unit: Option<String>,
    pub points: Vec<(f64, f64)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RunReport {
    pub recipe: String,
    pub recipe_path: String,
    pub drive: String,
    /// The drive's identity (ident string), when it could be read.
    pub identity: Option<String>,
    /// SHA-256 (hex) of the text the run ran with, when the front end knows it.
    pub recipe_sha256: Option<String>,
    /// The unit under test and the run's operator and station, as known at the end.
    pub unit: UnitIdentity,
    pub params: Vec<(String, String)>,
    pub started_at: SystemTime,
    pub duration: Duration,
    pub verdict: Verdict,
    pub steps: Vec<StepRecord>,
    pub checks: Vec<CheckResult>,
    pub series: Vec<Series>,
    /// The speed setpoints the run wrote, over the whole run.
    pub setpoints: Option<Track>,
    /// How the drive was left; for a run with several drives, all of them together (each
    /// one's own in `drive_ends`).
    pub end: EndState,
    /// The drive did not obey the stop commands and the stop was escalated.
    pub disobeyed: bool,
    /// The drives were left enabled on purpose (a `leave_enabled` run that passed): the
    /// end is the state its steps left, not a stop.
    pub kept_enabled: bool,
    /// Notes on the safe stop: what ran, what failed, the escalation.
    pub safe_stop: Vec<String>,
    /// Why the run ended at its first failed check (`on_failure: stop`, `run -x`), said as
    /// the reason its remaining checks were not reached; `None`: it did not.
    pub stopped_on_failure: Option<String>,
    /// Passed steps and checks inside repeats that were not kept once the report held
    /// [`MAX_RECORDS`] of each (they were printed as they ran); failures are always kept.
    pub omitted_steps: u64,
    pub omitted_checks: u64,
    /// The `csv:` files of sample steps this run wrote, by path.
    pub csv_files: Vec<String>,
    /// The resolution (one count, in its unit) of every object checked or sampled, from
    /// the dictionary, so reports show values as finely as the drive gives them.
    pub resolutions: Vec<(String, f64)>,
    /// One entry per drive, in the order they were stopped, for a run with several drives
    /// (empty for one drive: the fields above say it).
    pub drive_ends: Vec<DriveEnd>,
}

/// How one drive of a run with several drives was left.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveEnd {
    /// The name the recipe gives the drive.
    pub name: String,
    pub end: EndState,
}

/// Most step records, and most check results, one report keeps: a repeat that runs for
/// days would otherwise record every nested step once per iteration.
pub const MAX_RECORDS: usize = 10_000;

impl RunReport {
    /// The report of a run that has just started: passed so far, nothing recorded, the
    /// drive's state not read and the safe stop not (yet) confirmed. Every other field a
    /// run fills in as it goes.
    pub fn started(
        recipe: String,
        recipe_path: String,
        drive: String,
        params: Vec<(String, String)>,
        started_at: SystemTime,
    ) -> RunReport {
        RunReport {
            recipe,
            recipe_path,
            drive,
            identity: None,
            recipe_sha256: None,
            unit: UnitIdentity::default(),
            params,
            started_at,
            duration: Duration::ZERO,
            verdict: Verdict::Passed,
            steps: Vec::new(),
            checks: Vec::new(),
            series: Vec::new(),
            setpoints: None,
            end: EndState::default(),
            disobeyed: false,
            kept_enabled: false,
            safe_stop: Vec::new(),
            stopped_on_failure: None,
            omitted_steps: 0,
            omitted_checks: 0,
            csv_files: Vec::new(),
            resolutions: Vec::new(),
            drive_ends: Vec::new(),
        }
    }

    /// The process exit code: the verdict's own. The run layer's verdict rule
    /// (`run::verdict_rule`) settles the verdict from the checks and the drive's end before
    /// any report reads it, so the code and the words never disagree.
    pub fn exit_code(&self) -> i32 {
        self.verdict.exit_code()
    }

    /// The truth about the drives after the safe stop, in one line ([`EndState::drive_left`]
    /// of each).
    pub fn drive_left(&self) -> String {
        self.drive_left_lines().join("; ")
    }

    /// [`RunReport::drive_left`] as one line per drive (`right: drive left in …`) for a
    /// run with several drives, in the order they were stopped.
    pub fn drive_left_lines(&self) -> Vec<String> {
        if self.drive_ends.is_empty() {
            return vec![self.end.drive_left()];
        }
        self.drive_ends
            .iter()
            .map(|e| format!("{}: {}", e.name, e.end.drive_left()))
            .collect()
    }

    /// True when the last word must be CHECK THE DRIVE BY HAND.
    pub fn check_by_hand(&self) -> bool {
        !self.end.stop_confirmed
    }

    pub fn checks_passed(&self) -> usize {
        self.checks.iter().filter(|c| c.passed).count()
    }

    pub fn checks_failed(&self) -> usize {
        self.checks.iter().filter(|c| !c.passed && !c.retried).count()
    }

    /// Failed checks of attempts that were tried again (kept, not the verdict's).
    pub fn checks_retried(&self) -> usize {
        self.checks.iter().filter(|c| !c.passed && c.retried).count()
    }

    /// Whether the run was on the built-in simulated drive (every drive of it, or one of
    /// several): the reports say so beside the verdict.
    pub fn simulated(&self) -> bool {
        self.drive.contains(crate::drive::SIMULATED_PORT)
    }

    /// The dictionary's resolution of `object`, when known.
    pub fn resolution(&self, object: &str) -> Option<f64> {
        self.resolutions
            .iter()
            .find(|(o, _)| o == object)
            .map(|(_, r)| *r)
    }
}
