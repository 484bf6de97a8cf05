//! `backup`, `diff` and `restore`: a drive's parameters saved to a YAML file, compared with
//! the live drive or another file, and written back after a printed plan. Prints and
//! decides exit codes; the reading, comparing and writing are `crate::parameters`'.

use super::stop_signals;
use crate::dictionary::Dictionary;
use crate::drive::Drive;
use crate::family::Registry;
use crate::parameters::{self, Difference, Origin, Outcome, ParameterFile, Reading, SavedObject};
use crate::report::write_atomically;
use crate::run::ConnectionArgs;
use crate::run::{open_drive, DictionaryArgs, OpenDrive};
use crate::run::{COMMUNICATION, FAILED, INVALID, PASSED};
use crate::stop_request::StopRequests;
use clap::Args;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::SystemTime;

#[derive(Debug, Args)]
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

#[derive(Debug, Args)]
/// Compare a backup with the live drive (one file) or with another backup (two files).
/// Exit code 0 when equal, 1 when different.
pub struct DiffArgs {
    #[arg(value_name = "BACKUP", required = true, num_args = 1..=2)]
    files: Vec<PathBuf>,
    /// Numbers this close (in the object's unit) count as equal.
    #[arg(long, value_name = "AMOUNT", default_value_t = 0.0)]
    tolerance: f64,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

#[derive(Debug, Args)]
/// Write a backup's parameters back: prints the plan (only writable parameters that
/// differ, in dictionary order), writes only with --apply, reads every written object back.
/// Refused while the drive is in operation enabled.
pub struct RestoreArgs {
    #[arg(value_name = "BACKUP")]
    file: PathBuf,
    /// Carry out the plan (without it nothing is written).
    #[arg(long)]
    apply: bool,
    /// Restore although the backup was taken from a drive with another identity
    /// (type, firmware, ident string), or the drive's state cannot be read.
    #[arg(long)]
    force: bool,
    /// Then store the parameters in the drive's non-volatile memory, where the family has
    /// a documented command for it.
    #[arg(long)]
    store: bool,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

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
fn open(
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
fn read_live(
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
fn dictionary_for(
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

fn load(path: &std::path::Path) -> Result<ParameterFile, i32> {
    ParameterFile::load(path).map_err(|text| {
        eprintln!("{}", text.trim_end());
        INVALID
    })
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

fn print_differences(differences: &[Difference], left: &str, right: &str) {
    let width = differences.iter().map(|d| d.name().len()).max().unwrap_or(0);
    for d in differences {
        match d {
            Difference::Changed {
                name,
                left: a,
                right: b,
            } => {
                println!("{name:<width$}  changed   {left}: {a}   {right}: {b}")
            }
            Difference::Missing { name, left: a } => {
                println!("{name:<width$}  missing   {left}: {a}   not in {right}")
            }
            Difference::Extra { name, right: b } => {
                println!("{name:<width$}  extra     {right}: {b}   not in {left}")
            }
        }
    }
}

pub fn diff(args: &DiffArgs, registry: &Registry) -> i32 {
    let Some(first) = args.files.first() else {
        return INVALID;
    };
    if !(args.tolerance.is_finite() && args.tolerance >= 0.0) {
        eprintln!("error: --tolerance must be a number of 0 or more");
        return INVALID;
    }
    let left = match load(first) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let left_name = first.display().to_string();
    let (right, right_name) = match args.files.get(1) {
        Some(second) => match load(second) {
            Ok(f) => (f, second.display().to_string()),
            Err(code) => return code,
        },
        None => {
            let dictionary = match dictionary_for(registry, &args.dictionary, &left) {
                Ok(d) => d,
                Err(code) => return code,
            };
            let stop = stop_signals::install(false);
            let mut open = match open(registry, &args.connection, dictionary, &stop) {
                Ok(o) => o,
                Err(code) => return code,
            };
            // A backup taken with --all holds objects beyond the dictionary: scan again.
            let all = left
                .objects
                .iter()
                .any(|o| open.drive.dictionary().get(&o.name).is_none());
            let mut live = match read_live(&mut open, &args.connection, &stop, all) {
                Ok(f) => f,
                Err(code) => return code,
            };
            // Only what the backup holds is compared with the drive; a dictionary that has
            // grown since is not a difference of the drive.
            live.objects
                .retain(|o| left.objects.iter().any(|l| l.name == o.name) || left.objects.is_empty());
            (live, "drive".to_string())
        }
    };
    if left.family != right.family {
        eprintln!(
            "warning: {left_name} is of family {}, {right_name} of {}",
            left.family, right.family
        );
    }
    let differences = parameters::compare(&left, &right, args.tolerance);
    print_differences(&differences, &left_name, &right_name);
    if differences.is_empty() {
        println!("no differences: {} parameter(s) equal", left.objects.len());
        PASSED
    } else {
        println!(
            "{} difference(s) between {left_name} and {right_name}",
            differences.len()
        );
        FAILED
    }
}

/// The identity differences between the backup and the drive, as lines to print.
fn identity_mismatches(backup: &ParameterFile, drive: &mut Drive) -> Vec<String> {
    backup
        .identity
        .iter()
        .filter_map(|(name, saved)| {
            let live = drive
                .read(name)
                .map(|v| v.text().map_or_else(|| v.to_string(), str::to_string))
                .unwrap_or_else(|e| format!("unreadable ({e})"));
            (live != *saved).then(|| format!("{name}: backup {saved:?}, drive {live:?}"))
        })
        .collect()
}

/// The library's restore interlock, said: the exit code of a refusal, or a warning where
/// `--force` let a state that cannot be read through.
fn refuse_while_powered(drive: &mut Drive, force: bool) -> Result<(), i32> {
    match parameters::clear_for_restore(drive, force) {
        Ok(None) => Ok(()),
        Ok(Some(e)) => {
            eprintln!("warning: cannot tell whether the drive is enabled ({e}); going on because of --force");
            Ok(())
        }
        Err(refused) => {
            eprintln!("error: {refused}");
            Err(INVALID)
        }
    }
}

/// The planned writes outside the limits the drive itself reports, as lines to print.
fn beyond_drive_limits(drive: &mut Drive, plan: &[parameters::PlannedWrite]) -> Vec<String> {
    let mut out = Vec::new();
    for w in plan {
        let (Some(value), Some(Ok((min, max)))) = (w.number(), drive.limits(&w.name)) else {
            continue;
        };
        let low = min.as_ref().and_then(|v| v.number()).is_some_and(|m| value < m);
        let high = max.as_ref().and_then(|v| v.number()).is_some_and(|m| value > m);
        if low || high {
            let shown = |v: &Option<crate::dictionary::Value>| {
                v.as_ref().map_or("none".to_string(), ToString::to_string)
            };
            out.push(format!(
                "{}: {} is outside the drive's limits {} .. {}",
                w.name,
                w.to,
                shown(&min),
                shown(&max)
            ));
        }
    }
    out
}

pub fn restore(args: &RestoreArgs, registry: &Registry) -> i32 {
    let backup = match load(&args.file) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let dictionary = match dictionary_for(registry, &args.dictionary, &backup) {
        Ok(d) => d,
        Err(code) => return code,
    };
    if backup.family != dictionary.family() {
        eprintln!(
            "error: {} holds parameters of a {} drive; the dictionary in use is for {}",
            args.file.display(),
            backup.family,
            dictionary.family()
        );
        return INVALID;
    }
    let stop = stop_signals::install(false);
    let mut open = match open(registry, &args.connection, dictionary.clone(), &stop) {
        Ok(o) => o,
        Err(code) => return code,
    };
    if let Err(code) = refuse_while_powered(&mut open.drive, args.force) {
        return code;
    }
    let mismatches = identity_mismatches(&backup, &mut open.drive);
    if !mismatches.is_empty() {
        for m in &mismatches {
            eprintln!("warning: identity differs: {m}");
        }
        if !args.force {
            eprintln!("error: the backup was taken from another drive type or firmware; give --force to restore it anyway; nothing was written");
            return INVALID;
        }
    }
    let live = match read_live(&mut open, &args.connection, &stop, false) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let skipped = parameters::skipped(&dictionary, &backup);
    if !skipped.is_empty() {
        println!(
            "not restored, being beyond the {} dictionary (access and limits unknown): {}",
            dictionary.name(),
            skipped.join(", ")
        );
    }
    let plan = match parameters::plan(&dictionary, &backup, &live) {
        Ok(p) => p,
        Err(refusals) => {
            for r in &refusals {
                eprintln!("error: {}: {}", r.name, r.reason);
            }
            eprintln!(
                "{} parameter(s) cannot be restored; nothing was written",
                refusals.len()
            );
            return INVALID;
        }
    };
    if plan.is_empty() {
        println!(
            "the drive already holds every parameter of {}; nothing to write",
            args.file.display()
        );
        return PASSED;
    }
    // The drive's own limits (Lenze 931 `ON`/`OX`), where the family can ask, before the
    // first write.
    let beyond = beyond_drive_limits(&mut open.drive, &plan);
    if !beyond.is_empty() {
        for line in &beyond {
            eprintln!("error: {line}");
        }
        eprintln!(
            "{} value(s) outside the drive's own limits; nothing was written",
            beyond.len()
        );
        return INVALID;
    }
    println!("plan: {} write(s), in this order", plan.len());
    for (i, w) in plan.iter().enumerate() {
        println!("  {}. {}: {} → {}", i + 1, w.name, w.now, w.to);
    }
    if !args.apply {
        println!("nothing written; give --apply to carry out the plan");
        return PASSED;
    }
    // `apply` asks the interlock again just before the first write: reading the live set
    // took a while.
    let done = parameters::apply(
        &mut open.drive,
        &plan,
        args.force,
        &|| stop.first().is_none(),
        &mut |w, outcome| match outcome {
            Outcome::Written => println!("  wrote {} = {}", w.name, w.to),
            Outcome::Limited { stored } => {
                println!(
                    "  wrote {} = {} but the drive limited it: it holds {stored}",
                    w.name, w.to
                )
            }
            Outcome::Mismatch { read_back } => {
                println!("  wrote {} = {} but reads back {read_back}", w.name, w.to)
            }
            Outcome::Failed(e) => println!("  FAILED {}: {e}", w.name),
        },
    );
    let done = match done {
        Ok(done) => done,
        Err(refused) => {
            eprintln!("error: {refused}");
            return INVALID;
        }
    };
    let failed = done.iter().any(|(_, o)| matches!(o, Outcome::Failed(_)));
    let short = done
        .iter()
        .filter(|(_, o)| !matches!(o, Outcome::Written))
        .count();
    let written: Vec<&str> = done
        .iter()
        .filter(|(_, o)| !matches!(o, Outcome::Failed(_)))
        .map(|(n, _)| n.as_str())
        .collect();
    if done.len() < plan.len() {
        let not: Vec<&str> = plan[done.len()..].iter().map(|w| w.name.as_str()).collect();
        let why = match stop.first() {
            Some(signal) => format!("interrupted by {}", signal.describe()),
            None => "stopped at the failed write".to_string(),
        };
        println!(
            "{why}: written {} of {}: {}; not written: {}",
            written.len(),
            plan.len(),
            if written.is_empty() {
                "none".to_string()
            } else {
                written.join(", ")
            },
            not.join(", ")
        );
        return stop.first().map_or(COMMUNICATION, |s| s.exit_code());
    }
    if failed {
        return COMMUNICATION;
    }
    // A stop during the last write: everything is written, but nothing is stored.
    if let Some(signal) = stop.first() {
        println!(
            "interrupted by {} after the last write: all {} written, nothing stored",
            signal.describe(),
            plan.len()
        );
        return signal.exit_code();
    }
    if args.store {
        match open.drive.store_parameters() {
            None => eprintln!(
                "warning: the {} family has no documented command to store parameters in non-volatile memory; they are written but not stored",
                dictionary.family()
            ),
            Some(Ok(())) => println!("parameters stored in the drive's non-volatile memory"),
            Some(Err(e)) => {
                eprintln!("error: the parameters are written but storing them failed: {e}");
                return COMMUNICATION;
            }
        }
    }
    if short > 0 {
        println!(
            "{} of {} written as planned; {short} differ on the drive (see above)",
            plan.len() - short,
            plan.len()
        );
        return FAILED;
    }
    println!(
        "restored {} parameter(s) from {}",
        plan.len(),
        args.file.display()
    );
    PASSED
}
