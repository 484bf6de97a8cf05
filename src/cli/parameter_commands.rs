//! What `backup`, `diff` and `restore` share: opening the drive, reading its live
//! parameters (with `--all`, the objects beyond the dictionary), loading a backup and the
//! dictionary its names come from. Prints its own errors and hands back exit codes; must
//! not decide what is saved, compared or written (that is `crate::parameters`').

use crate::dictionary::Dictionary;
use crate::family::Registry;
use crate::parameters::{self, Origin, ParameterFile, Reading, SavedObject};
use crate::run::ConnectionArgs;
use crate::run::{open_drive, DictionaryArgs, OpenDrive};
use crate::run::{COMMUNICATION, INVALID};
use crate::stop_request::StopRequests;
use std::io::IsTerminal;
use std::sync::Arc;
use std::time::SystemTime;

fn origin(connection: &ConnectionArgs, open: &OpenDrive) -> Origin {
    Origin {
        address: connection
            .address_recorded()
            .map_or_else(|| open.drive.port(), |a| format!("{a} ({})", open.drive.port())),
        date: parameters::utc_timestamp(SystemTime::now()),
        tool: format!("drivescript {}", env!("CARGO_PKG_VERSION")),
    }
}

/// Opens the drive for a parameter command, saying so when it is the simulated one.
pub(super) fn open(
    registry: &Registry,
    connection: &ConnectionArgs,
    dictionary: Arc<Dictionary>,
    stop: &Arc<StopRequests>,
) -> Result<OpenDrive, i32> {
    let open =
        open_drive(registry, connection, dictionary, true, None, Some(stop.clone())).map_err(|text| {
            eprintln!("{text}");
            COMMUNICATION
        })?;
    if open.simulator.is_some() {
        eprintln!("using {}", open.description);
    }
    Ok(open)
}

/// The live parameters, read with progress on standard error.
/// With `all`, the objects the drive lists beyond the dictionary are added, named in the
/// family's notation (`#5.04`).
pub(super) fn read_live(
    open: &mut OpenDrive,
    connection: &ConnectionArgs,
    stop: &StopRequests,
    all: bool,
) -> Result<ParameterFile, i32> {
    let origin = origin(connection, open);
    let (mut file, mut complete) = parameters::take(
        &mut open.drive,
        origin,
        &mut |i, n, name| eprintln!("reading {}/{n}: {name}", i + 1),
        &|| stop.first().is_none(),
    );
    // Addresses as the family writes them (`#1.06`, `C00088`).
    let dictionary = open.drive.dictionary().clone();
    for o in &mut file.objects {
        if let Some(def) = dictionary.get(&o.name) {
            o.address = open.family.show_address(&def.address);
        }
    }
    if all && complete {
        match scan_beyond_dictionary(open, stop) {
            Ok(extra) => file.objects.extend(extra),
            Err(code) => return Err(code),
        }
        complete = stop.first().is_none();
    }
    match stop.first() {
        Some(signal) if !complete => {
            eprintln!(
                "interrupted by {}: {} of the parameters read",
                signal.describe(),
                file.objects.len()
            );
            Err(signal.exit_code())
        }
        _ => Ok(file),
    }
}

/// The objects the drive lists (`--all`) at addresses the dictionary does not know; those
/// it knows are saved by name already, or are live values and commands, each said with
/// why it is left out.
fn scan_beyond_dictionary(open: &mut OpenDrive, stop: &StopRequests) -> Result<Vec<SavedObject>, i32> {
    let dictionary = open.drive.dictionary().clone();
    let family = open.family.clone();
    // A scan asks every address it can; one line per try would bury the log, so only a
    // terminal sees where it is, on one line that is rewritten.
    let terminal = std::io::stderr().is_terminal();
    eprintln!("scanning the drive for objects beyond the dictionary (this takes a while)");
    let listed = open.drive.list_objects(&|| stop.first().is_none(), &mut |text| {
        if terminal {
            eprint!("\r\x1b[Kscanning {text}");
        }
    });
    if terminal {
        eprintln!();
    }
    let listed = match listed {
        None => {
            eprintln!(
                "error: --all: the {} family's drives cannot list their objects; only the dictionary's parameters can be saved",
                dictionary.family()
            );
            return Err(INVALID);
        }
        Some(Err(e)) => {
            eprintln!("error: scanning the drive's objects failed: {e}");
            return Err(COMMUNICATION);
        }
        Some(Ok(list)) => list,
    };
    eprintln!("the drive lists {} object(s)", listed.len());
    for (address, _) in &listed {
        let Some(def) = dictionary.objects().find(|o| o.address == *address) else {
            continue;
        };
        let why = if def.parameter && def.readable() {
            continue;
        } else if !def.readable() {
            "write-only in the dictionary"
        } else if def.access == crate::dictionary::Access::ReadOnly {
            "read-only: a live value the drive reports, not a setting"
        } else {
            "a command or live value (the dictionary does not mark it `parameter: true`)"
        };
        eprintln!("  left out {} {}: {why}", family.show_address(address), def.name);
    }
    Ok(listed
        .into_iter()
        .filter(|(address, _)| !dictionary.objects().any(|o| o.address == *address))
        .map(|(address, raw)| SavedObject {
            name: family.show_address(&address),
            address: family.show_address(&address),
            reading: Reading::Value {
                shown: raw.to_string(),
                raw: parameters::raw_text(&raw),
            },
        })
        .collect())
}

/// The dictionary a backup's names come from: the one it names, with the user's files and
/// bench limits.
pub(super) fn dictionary_for(
    registry: &Registry,
    args: &DictionaryArgs,
    backup: &ParameterFile,
) -> Result<Arc<Dictionary>, i32> {
    let mut args = args.clone();
    if !backup.dictionary.is_empty() {
        args.name = backup.dictionary.clone();
    }
    args.load_for(registry, None).map_err(|text| {
        eprint!("{text}");
        INVALID
    })
}

pub(super) fn load(path: &std::path::Path) -> Result<ParameterFile, i32> {
    ParameterFile::load(path).map_err(|e| {
        eprintln!("{}", e.to_string().trim_end());
        INVALID
    })
}
