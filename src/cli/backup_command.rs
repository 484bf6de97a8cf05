//! `backup`: every parameter the dictionary marks saved from the drive to a YAML file.
//! Prints and decides the exit code; must not read parameters itself (that is
//! `crate::parameters`').

use super::parameter_commands::{open, read_live};
use super::stop_signals;
use crate::family::Registry;
use crate::report::write_atomically;
use crate::run::{ConnectionArgs, DictionaryArgs, INVALID, PASSED};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
/// Save a drive's parameters to a YAML file
///
/// Save every parameter the dictionary marks (`parameter: true`) to a YAML file: family,
/// address, identity, date, and per object its value with unit and raw value. An object
/// that cannot be read is recorded with its error.
pub struct BackupArgs {
    /// Where to write the backup [default: standard output].
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Also every object the drive itself lists beyond the dictionary, named in the
    /// family's notation (Control Techniques: every #menu.parameter the drive answers;
    /// they are compared by `diff` but not written by `restore`, whose access and limits
    /// are unknown).
    #[arg(long)]
    all: bool,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

pub fn backup(args: &BackupArgs, registry: &Registry) -> i32 {
    let dictionary = match args.dictionary.load_for(registry, None) {
        Ok(d) => d,
        Err(text) => {
            eprint!("{text}");
            return INVALID;
        }
    };
    if !dictionary.objects().any(|o| o.parameter) {
        eprintln!(
            "error: the {} dictionary marks no object as a parameter; add `parameter: true` to the objects to save (--dictionary FILE)",
            dictionary.name()
        );
        return INVALID;
    }
    let stop = stop_signals::install(false);
    let mut open = match open(registry, &args.connection, dictionary, &stop) {
        Ok(o) => o,
        Err(code) => return code,
    };
    let file = match read_live(&mut open, &args.connection, &stop, args.all) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let unreadable = file.objects.iter().filter(|o| o.raw().is_none()).count();
    let text = file.to_yaml();
    match &args.output {
        Some(path) => {
            if let Err(e) = write_atomically(path, &text) {
                eprintln!("error: {e}");
                return INVALID;
            }
            eprintln!("{} parameter(s) saved to {}", file.objects.len(), path.display());
        }
        None => print!("{text}"),
    }
    if unreadable > 0 {
        eprintln!("warning: {unreadable} parameter(s) could not be read; the file records why");
    }
    PASSED
}
