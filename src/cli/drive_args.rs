//! Choosing the dictionary (built-in family plus the user's own files) and opening a
//! [`Drive`] on a connection: the common start of every command that talks to a drive.

use super::connection_args::{Connection, ConnectionArgs};
use super::render_diagnostic;
use crate::dictionary::Dictionary;
use crate::drive::{Drive, Sd2Access};
use crate::link::TelegramObserver;
use crate::sim::Sd2Simulator;
use crate::stop_request::StopRequests;
use clap::Args;
use std::path::PathBuf;
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
}

impl DictionaryArgs {
    /// The built-in dictionary of `family` (or of `--drive`) with the user's files merged
    /// in. On failure, the rendered diagnostic to print.
    pub fn load(&self, family: Option<&str>) -> Result<Arc<Dictionary>, String> {
        let family = family.unwrap_or(&self.family);
        let mut dictionary = Dictionary::builtin(family).map_err(|e| render_diagnostic(&e))?;
        for path in &self.extra {
            dictionary.extend_from(path).map_err(|e| render_diagnostic(&e))?;
        }
        Ok(Arc::new(dictionary))
    }

    /// The built-in SD2 dictionary and no extra files.
    pub fn builtin_sd2() -> Self {
        DictionaryArgs {
            family: "sd2".into(),
            extra: Vec::new(),
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
