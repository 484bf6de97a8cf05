//! Where `run` records its result (`--results`, `--no-results`, `DRIVESCRIPT_RESULTS`), and
//! the recorder that writes a run into the results store as it goes. Chooses and builds;
//! must not write a record itself (the recorder's thread does) or print.

use super::{outputs_for, ConnectionArgs, DictionaryArgs, OutputArgs};
use crate::family::Registry;
use crate::results::{FileFacts, Locator, Notes, RecorderSettings, ResultsRecorder, StoreHistory};
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Where `run` records its result.
#[derive(Debug, Clone, Default, Args)]
#[command(next_help_heading = "Results")]
pub struct RecordArgs {
    /// The results store: a SQLite file, or postgres://USER@HOST/DB for a store a fleet of
    /// benches shares [default: $DRIVESCRIPT_RESULTS, else results.sqlite in
    /// $XDG_DATA_HOME/drivescript or ~/.local/share/drivescript, on Windows
    /// %LOCALAPPDATA%\drivescript; runs on the built-in simulated drive are recorded only in
    /// a store named here or in DRIVESCRIPT_RESULTS].
    #[arg(long, value_name = "PATH|postgres://…")]
    pub results: Option<String>,
    /// Record nothing.
    #[arg(long, conflicts_with = "results")]
    pub no_results: bool,
}

impl RecordArgs {
    /// Where a run reads the unit's past runs (checks that compare with its last pass): the
    /// store it records in (also with `--no-results`, which records nothing but may
    /// compare), among runs as simulated as this one. `None` when nothing names a store
    /// and there is no data directory.
    pub fn history(&self, connection: &ConnectionArgs) -> Option<Arc<dyn crate::session::History>> {
        let (locator, _) = Locator::resolve(self.results.as_deref())?;
        // Simulated exactly as the recorder marks the run (a replay is).
        Some(Arc::new(StoreHistory::new(locator, connection.is_simulated())))
    }

    /// The recorder for a run of `files`, or `None` when nothing is to be recorded.
    pub fn recorder(
        &self,
        files: &[PathBuf],
        connection: &ConnectionArgs,
        dictionary: &DictionaryArgs,
        registry: &Registry,
        outputs: &OutputArgs,
        output_dir: &Path,
    ) -> Option<ResultsRecorder> {
        if self.no_results {
            return None;
        }
        let (locator, named) = Locator::resolve(self.results.as_deref())?;
        let simulated = connection.is_simulated();
        // The tour's simulated runs stay out of a bench's history unless a store is named.
        if simulated && !named {
            return None;
        }
        let several = files.len() > 1;
        let files = files
            .iter()
            .enumerate()
            .map(|(i, file)| {
                // As the run will load it; a file that cannot be loaded never starts a run.
                let loaded = dictionary.load_for(registry, Some(file)).ok();
                let own = outputs_for(outputs, output_dir, several.then_some((i + 1, file.as_path())));
                let shared = outputs_for(outputs, output_dir, None);
                let mut paths: Vec<String> = [&own.trace, &own.csv, &own.report, &shared.junit]
                    .into_iter()
                    .flatten()
                    .map(|p| p.display().to_string())
                    .collect();
                paths.dedup();
                FileFacts {
                    path: file.display().to_string(),
                    dictionary: loaded.as_ref().map(|d| d.name().to_string()),
                    family: loaded.as_ref().map(|d| d.family().to_string()),
                    report_files: paths,
                }
            })
            .collect();
        // A replay is marked simulated (no drive moved) and names its capture.
        let replay = connection
            .replay
            .as_ref()
            .map(|c| format!("replay:{}", c.display()));
        let port = replay
            .or_else(|| connection.port.clone())
            .or_else(|| connection.tcp.clone().map(|t| format!("tcp:{t}")))
            .or_else(|| connection.can.as_ref().map(|c| format!("{c:?}")));
        let settings = RecorderSettings {
            simulated,
            port,
            address: connection
                .address
                .clone()
                .or_else(|| connection.dnc_address.clone().map(|a| format!("dnc:{a}"))),
            files,
            quiet: outputs.quiet,
        };
        let notes: Notes = Arc::new(Mutex::new(std::io::stderr()));
        Some(ResultsRecorder::start(locator, settings, notes))
    }
}
