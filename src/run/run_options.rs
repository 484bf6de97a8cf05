//! Every option of one run, as `run` and `station` both take them from the command line
//! (one clap struct both flatten, so the two never drift apart), and the request and the
//! results recorder built from them. Builds data; must not run anything or print.

use super::{
    BadValue, ConnectionArgs, DictionaryArgs, OperatorArgs, OutputArgs, RecordArgs, RunRequest, SafeStopArgs,
    SharedObserver,
};
use crate::clock::SharedClock;
use crate::family::Registry;
use crate::sim::SimulatedDrive;
use crate::stop_request::StopRequests;
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

#[derive(Debug, Clone, Args)]
pub struct RunOptions {
    /// Parameter override, NAME=VALUE (e.g. speed=8000rpm); may be repeated.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_set)]
    pub set: Vec<(String, String)>,
    /// Run in virtual time, simulated drive only: hours take seconds with identical
    /// results.
    #[arg(long, conflicts_with = "realtime")]
    pub fast: bool,
    /// Run in real time (the default; with a real drive always).
    #[arg(long, hide_short_help = true)]
    pub realtime: bool,
    /// Directory for every output given as a relative path: --junit, --report, --csv,
    /// --trace and the `csv:` files of sample steps (and of a script's `sample`) (default:
    /// the current directory).
    #[arg(long, value_name = "DIR", default_value = ".")]
    pub output_dir: PathBuf,
    #[command(flatten)]
    pub outputs: OutputArgs,
    #[command(flatten)]
    pub safe_stop: SafeStopArgs,
    // The unit's parts the command line gives (station, part) and answers given beforehand.
    #[command(flatten)]
    pub operator: OperatorArgs,
    #[command(flatten)]
    pub dictionary: DictionaryArgs,
    #[command(flatten)]
    pub connection: ConnectionArgs,
    #[command(flatten)]
    pub record: RecordArgs,
}

/// `--set NAME=VALUE`.
pub fn parse_set(text: &str) -> Result<(String, String), BadValue> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(BadValue(format!(
            "`{text}`: write NAME=VALUE, e.g. speed=8000rpm"
        ))),
    }
}

/// Nobody reads the simulated drive's request log from a command line, and it would grow
/// for as long as the run.
fn without_request_log(sim: &Arc<Mutex<dyn SimulatedDrive>>, _: &SharedClock) {
    sim.lock()
        .unwrap_or_else(PoisonError::into_inner)
        .set_logging(false);
}

impl RunOptions {
    /// The results recorder of a run of `files` with `outputs` (as named for its unit),
    /// taking `stop` requests, where these options record one.
    pub fn recorder(
        &self,
        files: &[PathBuf],
        registry: &Registry,
        outputs: &OutputArgs,
        stop: Arc<StopRequests>,
    ) -> Option<SharedObserver> {
        let recorder = self.record.recorder(
            files,
            &self.connection,
            &self.dictionary,
            registry,
            outputs,
            &self.output_dir,
        )?;
        Some(Arc::new(Mutex::new(recorder.with_stop(stop))))
    }

    /// The request of a run with these options: `outputs` as named for its unit and
    /// `operator` (the unit and the answers given). Nobody to ask, no further observers
    /// and no live progress: the caller says otherwise.
    pub fn request<'a>(
        &'a self,
        registry: &'a Registry,
        outputs: &'a OutputArgs,
        operator: &'a OperatorArgs,
        stop: Arc<StopRequests>,
    ) -> RunRequest<'a> {
        RunRequest {
            registry,
            file: Path::new(""),
            set: &self.set,
            fast: self.fast,
            output_dir: self.output_dir.clone(),
            dictionary: &self.dictionary,
            connection: &self.connection,
            outputs,
            prepare_simulator: Some(&without_request_log),
            stop,
            safe_stop: self.safe_stop.clone(),
            terminal: false,
            operator,
            input: None,
            observers: Vec::new(),
            history: self.record.history(&self.connection),
        }
    }
}
