//! The recipe interpreter: walks a validated recipe's steps and hands each to the
//! [`Session`]'s operations, numbering and recording them; `repeat` and `include` nest.
//! The session ends every run with the safe stop (the recipe's `finally`, or the default)
//! whatever ended the steps. Knows steps, never bytes or families.

use super::recipe::{OnFailure, Recipe};
use super::step::{Step, StepKind};
use crate::drive::Drive;
use crate::session::{
    show_duration, Operator, RunInfo, RunObserver, RunReport, SafeStopSettings, Session, StepInfo, Stop,
    UnitIdentity,
};
use crate::stop_request::StopRequests;
use std::path::PathBuf;
use std::time::Duration;

pub struct Runner<'a> {
    session: Session<'a>,
}

impl<'a> Runner<'a> {
    /// A runner for a recipe with `drives:`: each drive under the name the recipe gives it
    /// (all on one clock); a recipe without `drives:` has its one drive unnamed.
    pub fn with_drives(
        drives: Vec<(String, &'a mut Drive)>,
        observer: &'a mut dyn RunObserver,
        stop: &'a StopRequests,
        recipe: &Recipe,
    ) -> Self {
        let run = RunInfo {
            kind: "recipe",
            name: recipe.name.clone(),
            path: recipe.path.clone(),
            params: recipe
                .params
                .iter()
                .map(|p| (p.name.clone(), p.value.clone()))
                .collect(),
            unit: UnitIdentity::default(),
            text_sha256: Some(recipe.text_sha256.clone()),
        };
        Runner {
            session: Session::with_drives(drives, observer, stop, run),
        }
    }

    /// How the safe stop waits for standstill and how long it tries to reopen a lost port.
    pub fn with_settings(mut self, settings: SafeStopSettings) -> Self {
        self.session = self.session.with_settings(settings);
        self
    }

    /// The unit under test as known at the start, and where the operator steps' answers
    /// come from.
    pub fn with_operator(mut self, unit: UnitIdentity, operator: Box<dyn Operator + 'a>) -> Self {
        self.session = self.session.with_unit(unit).with_operator(operator);
        self
    }

    /// Where the unit's past runs are read, for the checks that compare with its last pass.
    pub fn with_history(
        mut self,
        history: Option<std::sync::Arc<dyn crate::session::History>>,
        recipe: &Recipe,
    ) -> Self {
        self.session = self
            .session
            .with_history(history, super::last_pass_checks(recipe).0);
        self
    }

    /// Where `csv:` files of sample steps go (relative paths).
    pub fn with_output_dir(mut self, dir: PathBuf) -> Self {
        self.session = self.session.with_output_dir(dir);
        self
    }

    /// `csv:` files of sample steps with one column per object (`--csv-wide`).
    pub fn with_csv_wide(mut self, wide: bool) -> Self {
        self.session = self.session.with_csv_wide(wide);
        self
    }

    /// Runs the recipe to the end, whatever happens, and returns what happened. A panic in
    /// the steps is caught so that the safe stop still runs; the caller exits 101.
    pub fn run(self, recipe: &Recipe) -> RunReport {
        let mut session = self.session.with_watches(recipe.watches.clone());
        session.begin();
        let policy = Policy::of(&session, recipe);
        let ended = session
            .guarded(|s| steps(s, &recipe.steps, "", "steps", &policy))
            .err();
        let mut on_fault = |s: &mut Session| best_effort(s, &recipe.on_fault, "on_fault");
        let mut finally = |s: &mut Session| {
            if let Some(steps) = &recipe.finally {
                best_effort(s, steps, "finally");
            }
        };
        let on_fault: Option<&mut dyn FnMut(&mut Session)> =
            (!recipe.on_fault.is_empty()).then_some(&mut on_fault);
        let finally: Option<&mut dyn FnMut(&mut Session)> = recipe.finally.is_some().then_some(&mut finally);
        session.end(ended, recipe.leave_enabled, on_fault, finally)
    }
}

fn info(step: &Step, number: String, phase: &'static str) -> StepInfo {
    StepInfo {
        number,
        label: step.label.clone(),
        origin: step.origin.clone(),
        phase,
        container: matches!(
            step.kind,
            StepKind::Repeat { .. } | StepKind::Include { .. } | StepKind::Attempts { .. }
        ),
    }
}

/// What a failed check does where steps run: whether it ends the run (and who says so),
/// and whether an `attempts` block around them may still try again, when it does not yet.
#[derive(Debug, Clone, Default)]
struct Policy {
    /// `Some(why)`: the first failed check ends the run (`on_failure: stop`, `run -x`).
    stop: Option<String>,
    /// Inside an `attempts` block: a failed attempt is no failure until the attempts are
    /// used up, so the block's own step is judged instead.
    trying: bool,
    /// The command line's `-x`: no block's `on_failure: continue` turns it off.
    forced: bool,
}

impl Policy {
    /// The recipe's own policy, or the command line's `-x` over it.
    fn of(s: &Session, recipe: &Recipe) -> Policy {
        let stop = if s.stops_on_failure() {
            Some("run --stop-on-failure".to_string())
        } else {
            (recipe.on_failure == OnFailure::Stop).then(|| "on_failure: stop of the recipe".to_string())
        };
        Policy {
            stop,
            trying: false,
            forced: s.stops_on_failure(),
        }
    }

    /// The policy for `step` itself: its own `on_failure` (where written) over this one's;
    /// `-x` is never turned off by a block's `continue`.
    fn for_step(&self, step: &Step, number: &str) -> Policy {
        let stop = match step.on_failure {
            Some(OnFailure::Stop) if self.stop.is_none() => {
                Some(format!("on_failure: stop of step {number}"))
            }
            Some(OnFailure::Continue) if !self.forced => None,
            _ => self.stop.clone(),
        };
        Policy { stop, ..*self }
    }

    /// The policy of the steps inside `step` (an attempts block tries them).
    fn inside(&self, step: &Step) -> Policy {
        Policy {
            stop: self.stop.clone(),
            trying: self.trying || matches!(step.kind, StepKind::Attempts { .. }),
            forced: self.forced,
        }
    }
}

fn steps(
    s: &mut Session,
    steps: &[Step],
    prefix: &str,
    phase: &'static str,
    policy: &Policy,
) -> Result<(), Stop> {
    for (i, step) in steps.iter().enumerate() {
        if s.interrupted() {
            return Err(Stop::Interrupted);
        }
        let number = if prefix.is_empty() {
            format!("{}", i + 1)
        } else {
            format!("{prefix}.{}", i + 1)
        };
        let info = info(step, number, phase);
        let own = policy.for_step(step, &info.number);
        let inside = own.inside(step);
        let mark = s.check_mark();
        let watching = s.begin_block_watches(&step.watches);
        let done = s.perform(&info, |s| exec(s, step, &info.number, phase, &inside));
        s.end_block_watches(watching);
        done?;
        if let (Some(why), false) = (&own.stop, own.trying) {
            if let Some(check) = s.failed_check_since(mark) {
                return Err(s.stop_on_failure(&check, &info.number, why));
            }
        }
        if phase == "steps" {
            s.watch_fault(false)?;
        }
    }
    Ok(())
}

fn exec(
    s: &mut Session,
    step: &Step,
    number: &str,
    phase: &'static str,
    policy: &Policy,
) -> Result<String, Stop> {
    match &step.kind {
        StepKind::Command(c, None) => s.command_all(*c),
        StepKind::Command(c, Some(drive)) => s.command_on(drive, *c),
        StepKind::GoTo {
            state,
            timeout,
            drive: None,
        } => s.go_to_all(*state, *timeout),
        StepKind::GoTo {
            state,
            timeout,
            drive: Some(drive),
        } => s.go_to_on(drive, *state, *timeout),
        StepKind::Set(writes) => s.set(writes),
        StepKind::Read(objects) => s.read(objects),
        StepKind::Print(text) => s.print(text),
        StepKind::WaitUntil {
            condition,
            timeout,
            every,
        } => s.wait_until(condition, *timeout, *every, &step.origin, number),
        StepKind::Dwell(d) => {
            s.dwell(*d, number)?;
            Ok(format!("{} dwelt", show_duration(*d)))
        }
        StepKind::Sample { sampling: x, steps } => s.sample(x, steps, number),
        StepKind::Expect(checks) => s.expect(checks, &step.origin),
        StepKind::CoastDown(c) => s.coast_down(c, &step.origin, number),
        StepKind::ExpectParameters { file, parameters } => {
            s.expect_parameters(file, parameters, &step.origin)
        }
        StepKind::Ramp {
            object,
            points,
            every,
        } => s.ramp(object, points, *every, number),
        StepKind::Repeat {
            times,
            duration,
            steps: nested,
        } => repeat(s, *times, *duration, nested, number, phase, policy),
        StepKind::Ask(prompt) => s.ask(prompt, &step.origin, number).map(|(detail, _)| detail),
        StepKind::Include { steps: nested, .. } => {
            steps(s, nested, number, phase, policy)?;
            Ok(format!("{} steps", nested.len()))
        }
        StepKind::Attempts { times, steps: nested } => attempts(s, *times, nested, number, phase, policy),
    }
}

fn repeat(
    s: &mut Session,
    times: Option<u32>,
    duration: Option<Duration>,
    nested: &[Step],
    number: &str,
    phase: &'static str,
    policy: &Policy,
) -> Result<String, Stop> {
    let start = s.clock().now();
    let mut n = 0u32;
    loop {
        let more = match (times, duration) {
            (Some(t), _) => n < t,
            (_, Some(d)) => s.clock().now().saturating_sub(start) < d,
            _ => false,
        };
        if !more {
            break;
        }
        n += 1;
        s.iteration(n);
        if s.wants_progress() {
            let elapsed = s.clock().now().saturating_sub(start);
            let what = match times {
                Some(t) => format!("iteration {n} of {t}"),
                None => format!("iteration {n}"),
            };
            s.progress(number, elapsed, duration, &what);
        }
        steps(s, nested, number, phase, policy)?;
    }
    let took = s.clock().now().saturating_sub(start);
    // `for`: an iteration begun before the duration ran out runs to its end (a run-in's
    // cycle left half done would leave its checks unmade), so the repeat may take up to one
    // iteration longer; said where it did.
    let over = duration.filter(|d| took > *d).map_or(String::new(), |d| {
        format!(
            " (whole iterations: the last began before the {} of `for` ran out)",
            humantime::format_duration(d)
        )
    });
    Ok(format!("{n} iteration(s) in {:.2} s{over}", took.as_secs_f64()))
}

/// Runs `nested` up to `times` times until an attempt ends with none of its checks failed;
/// a failed check (also a wait that timed out: the drive did not get there in time, which
/// another attempt may change) of an attempt with another to follow is kept as retried.
/// Errors, faults, stop requests, an operator step nobody answered in time and an answer
/// naming another unit end it at once: a person who does not answer is no failed
/// measurement, another attempt would move the drive again with nobody watching, and the
/// wrong unit on the bench stays the wrong one.
fn attempts(
    s: &mut Session,
    times: u32,
    nested: &[Step],
    number: &str,
    phase: &'static str,
    policy: &Policy,
) -> Result<String, Stop> {
    for k in 1..=times {
        let mark = s.begin_attempt(number, k, times);
        let ended = steps(s, nested, number, phase, policy);
        let failed = match &ended {
            Ok(()) => s.failed_since(mark),
            Err(Stop::Failed(_)) => true,
            Err(_) => return ended.map(|()| String::new()),
        };
        if !failed {
            return Ok(format!("passed at attempt {k} of {times}"));
        }
        if k == times {
            ended?;
            return Ok(format!("FAILED: every attempt ({times}) failed its checks"));
        }
        s.retry_attempt(mark);
        s.message(&format!("attempt {k} of {times} failed its checks; trying again"));
    }
    Ok(String::new())
}

/// Runs steps whatever fails (the safe stop's `finally` and `on_fault`); each failure is
/// noted and the next step tried; a lost port is reopened and the step tried once more. A
/// second stop request abandons the rest.
fn best_effort(s: &mut Session, list: &[Step], phase: &'static str) {
    for (i, step) in list.iter().enumerate() {
        if s.interrupted() {
            s.note(format!(
                "{phase} abandoned at step {} (a second stop request)",
                i + 1
            ));
            return;
        }
        let number = format!("{phase}.{}", i + 1);
        let info = info(step, number, phase);
        // A failed check here never ends anything: the stop must run to its end.
        s.perform_best_effort(&info, |s| exec(s, step, &info.number, phase, &Policy::default()));
    }
}
