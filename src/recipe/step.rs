//! A validated recipe step: every object resolved, every value converted to the object's
//! engineering unit and checked against its limits, every duration parsed. What the
//! interpreter runs; it never sees YAML.

use crate::drive::device_control::{DeviceCommand, DeviceState};
use crate::session::{Check, Condition};
use crate::session::{ObjectRef, Prompt, SetValue, StepOrigin};
use std::time::Duration;

#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub kind: StepKind,
    pub origin: StepOrigin,
    /// One line saying what the step does: `set speed_setpoint = 6000 rpm`.
    pub label: String,
    /// A block's own `on_failure:` (repeat, attempts, include); `None`: the enclosing one's.
    pub on_failure: Option<super::recipe::OnFailure>,
    /// A block's own `watch:` limits (repeat, attempts), read while its steps run.
    pub watches: Vec<crate::session::Watch>,
}

/// The longest a list of steps can take (see [`Step::longest_time`]).
pub fn longest_time_of(steps: &[Step]) -> Duration {
    steps
        .iter()
        .fold(Duration::ZERO, |sum, s| sum.saturating_add(s.longest_time()))
}

#[derive(Debug, Clone, PartialEq)]
pub enum StepKind {
    /// Write one device-control command to the control word of the named drive (`None`:
    /// every drive of the recipe).
    Command(DeviceCommand, Option<String>),
    /// Walk the state machine of the named drive (`None`: every drive, one after the
    /// other) to a state, each transition within `timeout`.
    GoTo {
        state: DeviceState,
        timeout: Duration,
        drive: Option<String>,
    },
    /// Write objects, in the order written.
    Set(Vec<(ObjectRef, SetValue)>),
    /// Read objects and show their values.
    Read(Vec<ObjectRef>),
    /// Show a message.
    Print(String),
    /// Poll until the condition holds; failing after `timeout`.
    WaitUntil {
        condition: Condition,
        timeout: Duration,
        every: Duration,
    },
    /// Wait, watching the drive for faults.
    Dwell(Duration),
    /// Read objects every `every` for `duration`, keeping statistics; optionally to CSV.
    Sample {
        sampling: crate::session::Sampling,
        /// The setpoint step an object's response is measured against.
        steps: Vec<(String, crate::session::StepSpec)>,
    },
    /// Named pass/fail checks.
    Expect(Vec<Check>),
    /// The drive holds the parameters of a backup: one check per object.
    ExpectParameters {
        file: String,
        parameters: Box<crate::parameters::ParameterFile>,
    },
    /// Write an object in steps from one value to another.
    Ramp {
        object: ObjectRef,
        points: Vec<f64>,
        every: Duration,
    },
    /// Run nested steps a number of times or for a duration.
    Repeat {
        times: Option<u32>,
        duration: Option<Duration>,
        steps: Vec<Step>,
    },
    /// Steps of another recipe file, with its parameters already applied.
    Include { path: String, steps: Vec<Step> },
    /// An operator step: a question or instruction, answered at the terminal or
    /// beforehand.
    Ask(Prompt),
    /// Nested steps tried up to `times` times until their checks pass; every attempt is
    /// kept in the reports, the verdict is the last one's.
    Attempts { times: u32, steps: Vec<Step> },
    /// Power stage off at speed, the spindle coasting by design; the time from one speed
    /// down past another is checked.
    CoastDown(crate::session::CoastDown),
}

impl Step {
    /// The steps this one holds (repeat, include, attempts); none for any other step.
    /// Walks that must see every step of a recipe go through here, so a new kind of
    /// container cannot be missed by one of them.
    pub fn nested(&self) -> &[Step] {
        match &self.kind {
            StepKind::Repeat { steps, .. }
            | StepKind::Include { steps, .. }
            | StepKind::Attempts { steps, .. } => steps,
            _ => &[],
        }
    }

    /// The longest this step can take: every timeout in full, a repeat's steps multiplied
    /// out, telegram times left aside; saturating. The loader bounds it so that no sum of
    /// times in a run can overflow.
    pub fn longest_time(&self) -> Duration {
        match &self.kind {
            StepKind::Command(..)
            | StepKind::Set(_)
            | StepKind::Read(_)
            | StepKind::Print(_)
            | StepKind::Expect(_)
            | StepKind::ExpectParameters { .. } => Duration::ZERO,
            // A person's time is not planned; a timeout bounds it.
            StepKind::Ask(p) => p.timeout.unwrap_or_default(),
            // Each transition has its own timeout; no walk has more transitions than states.
            StepKind::GoTo { timeout, .. } => timeout.saturating_mul(DeviceState::ALL.len() as u32),
            StepKind::WaitUntil { timeout, every, .. } => timeout.saturating_add(*every),
            StepKind::Dwell(d) => *d,
            StepKind::CoastDown(c) => c.timeout.saturating_add(c.every),
            StepKind::Sample { sampling, .. } => sampling.duration.saturating_add(sampling.every),
            StepKind::Ramp { points, every, .. } => {
                every.saturating_mul(u32::try_from(points.len()).unwrap_or(u32::MAX))
            }
            StepKind::Repeat {
                times,
                duration,
                steps,
            } => {
                let once = longest_time_of(steps);
                match (times, duration) {
                    (Some(t), _) => once.saturating_mul(*t),
                    // The last pass starts just before the time is up and runs to its end.
                    (_, Some(d)) => d.saturating_add(once),
                    _ => Duration::ZERO,
                }
            }
            StepKind::Include { steps, .. } => longest_time_of(steps),
            StepKind::Attempts { times, steps } => longest_time_of(steps).saturating_mul(*times),
        }
    }

    /// True when time passes while the step runs (it waits or talks to the drive). A
    /// `repeat` with `for` needs one such step, or it would never end in virtual time.
    pub fn takes_time(&self) -> bool {
        match &self.kind {
            StepKind::Print(_) => false,
            StepKind::Expect(checks) => checks.iter().any(|c| c.statistic.is_none()),
            StepKind::Repeat { steps, .. }
            | StepKind::Include { steps, .. }
            | StepKind::Attempts { steps, .. } => steps.iter().any(Step::takes_time),
            _ => true,
        }
    }

    /// True for steps that take time and should show progress.
    pub fn is_long(&self) -> bool {
        matches!(
            self.kind,
            StepKind::WaitUntil { .. }
                | StepKind::Dwell(_)
                | StepKind::Sample { .. }
                | StepKind::Repeat { .. }
                | StepKind::Attempts { .. }
                | StepKind::Ramp { .. }
                | StepKind::CoastDown(_)
        )
    }
}
