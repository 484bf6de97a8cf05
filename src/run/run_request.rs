//! What one run is asked to do and what it produced: the command line fills a
//! [`RunRequest`] from its options, the tests directly. Only data.

use crate::clock::SharedClock;
use crate::family::Registry;
use crate::report::JunitSuite;
use crate::run::{ConnectionArgs, DictionaryArgs, OperatorArgs, OutputArgs, SafeStopArgs, TerminalInput};
use crate::session::{RunObserver, RunReport};
use crate::sim::SimulatedDrive;
use crate::stop_request::StopRequests;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// A hook that gets the simulated drive and the run's clock before the run starts.
pub type PrepareSimulator = dyn Fn(&Arc<Mutex<dyn SimulatedDrive>>, &SharedClock);

/// Everything a run needs; the command line fills it from its options, the tests directly.
pub struct RunRequest<'a> {
    /// The drive families to pick from (the built-in ones; tests add their own).
    pub registry: &'a Registry,
    /// The recipe, or the script (`.rhai`).
    pub file: &'a Path,
    pub set: &'a [(String, String)],
    /// Virtual time (simulated drive only).
    pub fast: bool,
    pub output_dir: PathBuf,
    pub dictionary: &'a DictionaryArgs,
    pub connection: &'a ConnectionArgs,
    pub outputs: &'a OutputArgs,
    /// Called with the simulated drive and the run's clock before the run (tests inject
    /// faults here); with `drives:`, once for each simulated drive in the order declared.
    pub prepare_simulator: Option<&'a PrepareSimulator>,
    /// Stop requests (signals, or scheduled by tests).
    pub stop: Arc<StopRequests>,
    /// The command line's choices for the safe stop (over the recipe's and the defaults).
    pub safe_stop: SafeStopArgs,
    /// Whether standard output is a terminal (live progress).
    pub terminal: bool,
    /// The unit under test (`--unit`) and the answers given to operator steps.
    pub operator: &'a OperatorArgs,
    /// The terminal a person answers operator steps at (standard input when it is one);
    /// without one, every operator step needs an answer given beforehand.
    pub input: Option<Arc<TerminalInput>>,
    /// Further observers of the run, told every event after the console and the CSV
    /// recorder: where features that follow a run plug in (operator prompts, run
    /// identity, a results store, replay). Shared, so the caller reads them afterwards.
    pub observers: Vec<SharedObserver>,
    /// Where the unit's past runs are read (the results store), for checks that compare
    /// with its last passed run; `None`: nowhere (those checks cannot be judged).
    pub history: Option<Arc<dyn crate::session::History>>,
}

/// An observer the caller keeps a handle on.
pub type SharedObserver = Arc<Mutex<dyn RunObserver>>;

/// What a run produced.
pub struct RunResult {
    pub exit_code: i32,
    /// `None` when the run never started (invalid recipe, port not available).
    pub report: Option<RunReport>,
    /// The simulated drive (the first declared one of a recipe with `drives:`).
    pub simulator: Option<Arc<Mutex<dyn SimulatedDrive>>>,
    /// Every simulated drive by the recipe's name for it (empty name: the one drive).
    pub simulators: Vec<(String, Arc<Mutex<dyn SimulatedDrive>>)>,
    /// The test suite of the run's JUnit report (with several files, one suite of the
    /// command's one file); `None` when the run could not write its output files.
    pub junit: Option<JunitSuite>,
}

impl RunResult {
    /// A run that never started.
    pub fn refused(exit_code: i32) -> Self {
        RunResult {
            exit_code,
            report: None,
            simulator: None,
            simulators: Vec::new(),
            junit: None,
        }
    }
}
