//! What the script thread and the session thread say to each other. The script runs on a
//! thread of its own (Rhai calls back into `'static` functions, the session borrows the
//! drive), so every drive operation is a [`Request`] the session thread performs and
//! answers. Plain data; it must not perform anything.

use crate::diag::Diagnostic;
use crate::drive::{DeviceCommand, DeviceState};
use crate::session::{CheckResult, ObjectRef, SetValue, Stop};
use std::time::Duration;

/// One drive operation, resolved and checked on the script side.
#[derive(Debug)]
pub enum Call {
    /// To the named drive (`None`: every drive of the run).
    Command(DeviceCommand, Option<String>),
    /// The named drive (`None`: every drive, one after the other).
    GoTo(DeviceState, Duration, Option<String>),
    Set(ObjectRef, SetValue),
    /// A query: not a step of its own.
    Read(ObjectRef),
    /// A query: not a step of its own. The named drive's (`None`: the one drive's).
    State(Option<String>),
    WaitUntil {
        object: ObjectRef,
        timeout: Duration,
        every: Duration,
    },
    Dwell(Duration),
    Sample(crate::session::Sampling),
    Expect(Box<CheckResult>),
    /// A check (by name, with its value) compared with the unit's last passed run.
    CompareLastPass(Box<(String, f64, crate::session::LastPass)>),
    /// `wait_until_stable`: a [`Condition::Stable`](crate::session::Condition) to wait for.
    WaitStable {
        condition: crate::session::Condition,
        timeout: Duration,
        every: Duration,
    },
    CoastDown(Box<crate::session::CoastDown>),
    Fail(String),
    Message(String),
    /// `d.watch(...)`: a limit held from here until the script's steps end. Not a step of
    /// its own.
    Watch(Box<crate::session::Watch>),
    /// An operator step.
    Ask(Box<crate::session::Prompt>),
}

/// A call and where the script made it.
#[derive(Debug)]
pub struct Request {
    pub call: Call,
    /// One line saying what it does: `set speed_setpoint = 6000 rpm`.
    pub label: String,
    pub line: usize,
    pub column: usize,
}

/// What came of a request.
#[derive(Debug)]
pub enum Answer {
    Done,
    Number(f64),
    State(DeviceState),
    Sampled(Vec<Window>),
    /// What the operator answered.
    Asked(crate::session::Accepted),
}

/// One object's sample window, for a script's statistics.
#[derive(Debug, Clone)]
pub struct Window {
    pub object: ObjectRef,
    pub stats: crate::session::Stats,
    /// `None` when the window held more samples than a script may keep.
    pub values: Option<Vec<f64>>,
}

/// From the script thread.
pub enum ToSession {
    Request(Request),
    /// The script's condition of a `wait_until` on a value the session read.
    Holds(Result<bool, Stop>),
    /// The script (or its `finally`) has ended.
    Ended(Ending),
}

/// From the session thread.
pub enum ToScript {
    Answer(Result<Answer, Stop>),
    /// Does the `wait_until` condition hold for this value?
    Ask(f64),
    /// Run the script's `fn finally(d)`.
    RunFinally,
    /// The run is over; the script thread returns.
    Finish,
}

/// How the script (or its `finally`) ended.
pub enum Ending {
    Completed,
    /// Why, and the script's own diagnostic of it (a place in the script) when it has one.
    Stopped(Stop, Option<Box<Diagnostic>>),
}
