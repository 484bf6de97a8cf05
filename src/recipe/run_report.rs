//! What a recipe run did: every step with its result and duration, every check with its
//! measured value and limits, every sampled series, and how the run ended. Plain data for
//! the console, JUnit, CSV and HTML reports; no formatting and no I/O here.

use super::step::StepOrigin;
use crate::protocol::device_control::DeviceState;
use std::time::{Duration, SystemTime};

/// How a run ended, in the order of severity of DESIGN.md's exit codes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    Passed,
    /// An expectation failed (an `expect` check, or a `wait_until` that timed out).
    Failed,
    /// Communication failure or drive fault.
    Error(String),
    /// Ctrl-C, after the safe stop.
    Interrupted,
}

impl Verdict {
    pub fn exit_code(&self) -> i32 {
        match self {
            Verdict::Passed => 0,
            Verdict::Failed => 1,
            Verdict::Error(_) => 3,
            Verdict::Interrupted => 130,
        }
    }

    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Passed => "PASSED",
            Verdict::Failed => "FAILED",
            Verdict::Error(_) => "ERROR",
            Verdict::Interrupted => "INTERRUPTED",
        }
    }
}

/// One step as it ran.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// `3`, or `7.2.1` inside repeat/include (iteration-independent position).
    pub number: String,
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
    pub passed: bool,
    /// The measured value in the object's unit (or text for string objects).
    pub measured: Option<f64>,
    pub measured_text: Option<String>,
    pub unit: Option<String>,
    pub low: Option<f64>,
    pub high: Option<f64>,
    /// The object and statistic checked, for plots: (`speed_actual`, `mean`).
    pub object: Option<String>,
    pub statistic: Option<String>,
    pub message: String,
    pub origin: StepOrigin,
    pub at: Duration,
    pub duration: Duration,
}

/// A sampled series: (time since start in s, value).
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub object: String,
    pub unit: Option<String>,
    /// The step that sampled it.
    pub step: String,
    pub points: Vec<(f64, f64)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RunReport {
    pub recipe: String,
    pub recipe_path: String,
    pub drive: String,
    /// The drive's identity (ident string), when it could be read.
    pub identity: Option<String>,
    pub params: Vec<(String, String)>,
    pub started_at: SystemTime,
    pub duration: Duration,
    pub verdict: Verdict,
    pub steps: Vec<StepRecord>,
    pub checks: Vec<CheckResult>,
    pub series: Vec<Series>,
    /// The state the drive was left in, when it could be read.
    pub final_state: Option<DeviceState>,
    /// Notes on the safe stop: what ran, what failed, the safety net.
    pub safe_stop: Vec<String>,
}

impl RunReport {
    pub fn checks_passed(&self) -> usize {
        self.checks.iter().filter(|c| c.passed).count()
    }

    pub fn checks_failed(&self) -> usize {
        self.checks.iter().filter(|c| !c.passed).count()
    }
}
