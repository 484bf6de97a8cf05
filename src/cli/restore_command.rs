//! `restore`: a backup's parameters written back after a printed plan, refused while
//! the drive is in operation enabled. Prints and decides the exit code; must not plan,
//! write or verify itself (that is `crate::parameters`').

use super::parameter_commands::{dictionary_for, load, open, read_live};
use super::stop_signals;
use crate::drive::Drive;
use crate::family::Registry;
use crate::parameters::{self, Outcome, ParameterFile};
use crate::run::{ConnectionArgs, DictionaryArgs, COMMUNICATION, FAILED, INVALID, PASSED};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
/// Write a backup's parameters back (a plan first; --apply writes)
///
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
    let mut backup = match load(&args.file) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let dictionary = match dictionary_for(registry, &args.dictionary, &backup) {
        Ok(d) => d,
        Err(code) => return code,
    };
    backup.named_by(&dictionary);
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
