//! Choosing the dictionary (built-in family plus the user's own files, capped by the
//! bench limits file) and opening a [`Drive`] on a connection: the common start of every
//! command that talks to a drive.

use super::connection_args::{Connection, ConnectionArgs};
use super::render_diagnostic;
use crate::dictionary::{BenchLimits, Dictionary, LIMITS_ENV};
use crate::drive::Drive;
use crate::family::sd2::Sd2Access;
use crate::family::sd2::Sd2Simulator;
use crate::link::TelegramObserver;
use crate::stop_request::StopRequests;
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

#[derive(Debug, Clone, Args)]
pub struct DictionaryArgs {
    /// The drive family, i.e. the built-in dictionary to start from.
    #[arg(long = "drive", value_name = "FAMILY", default_value = "sd2")]
    pub family: String,
    /// A dictionary file that adds objects to the built-in one (or replaces objects of the
    /// same name). May be given several times.
    #[arg(long = "dictionary", value_name = "PATH")]
    pub extra: Vec<PathBuf>,
    /// Bench limits file capping speed and current (`max_speed: 12000 rpm`). Without it:
    /// the file named by $DRIVESCRIPT_LIMITS, else drivescript-limits.yaml next to the
    /// recipe. Nothing (recipe, --set, --dictionary) can raise its limits.
    #[arg(long = "limits", value_name = "FILE")]
    pub limits: Option<PathBuf>,
}

impl DictionaryArgs {
    /// The built-in dictionary of `family` (or of `--drive`) with the user's files merged
    /// in. On failure, the rendered diagnostic to print.
    pub fn load(&self, family: Option<&str>) -> Result<Arc<Dictionary>, String> {
        self.load_for(family, None)
    }

    /// [`load`](Self::load) for running or checking `recipe`: a `drivescript-limits.yaml`
    /// next to it caps the dictionary when neither --limits nor $DRIVESCRIPT_LIMITS names
    /// a limits file.
    pub fn load_for(&self, family: Option<&str>, recipe: Option<&Path>) -> Result<Arc<Dictionary>, String> {
        let family = family.unwrap_or(&self.family);
        let mut dictionary = Dictionary::builtin(family).map_err(|e| render_diagnostic(&e))?;
        for path in &self.extra {
            dictionary.extend_from(path).map_err(|e| render_diagnostic(&e))?;
        }
        // Last, so that no dictionary above can raise the bench's limits.
        let env = std::env::var_os(LIMITS_ENV);
        if let Some((path, route)) = BenchLimits::find(self.limits.as_deref(), env.as_deref(), recipe) {
            let limits = BenchLimits::load(&path, route).map_err(|e| render_diagnostic(&e))?;
            dictionary.apply_bench_limits(limits);
        }
        Ok(Arc::new(dictionary))
    }

    /// The built-in SD2 dictionary and no extra files.
    pub fn builtin_sd2() -> Self {
        DictionaryArgs {
            family: "sd2".into(),
            extra: Vec::new(),
            limits: None,
        }
    }
}

/// A drive ready for use, and the simulated drive behind it when there is one.
pub struct OpenDrive {
    pub drive: Drive,
    pub simulator: Option<Arc<Mutex<Sd2Simulator>>>,
    pub description: String,
}

/// Opens the connection and wraps it in the drive API. On failure, the message to print
/// (exit code 3).
pub fn open_drive(
    connection: &ConnectionArgs,
    dictionary: Arc<Dictionary>,
    virtual_time: bool,
) -> Result<OpenDrive, String> {
    open_drive_observed(connection, dictionary, virtual_time, None, None)
}

/// [`open_drive`] with an observer of every telegram (trace file, `-v`).
pub fn open_drive_observed(
    connection: &ConnectionArgs,
    dictionary: Arc<Dictionary>,
    virtual_time: bool,
    observer: Option<Box<dyn TelegramObserver>>,
    stop: Option<Arc<StopRequests>>,
) -> Result<OpenDrive, String> {
    let Connection {
        mut link,
        dest,
        simulator,
        description,
    } = connection.open(virtual_time).map_err(|e| format!("error: {e}"))?;
    if let Some(o) = observer {
        link.set_observer(o);
    }
    if let Some(s) = stop {
        link.set_stop_requests(s);
    }
    let drive = Drive::new(Box::new(Sd2Access::new(link, dest)), dictionary);
    Ok(OpenDrive {
        drive,
        simulator,
        description,
    })
}
