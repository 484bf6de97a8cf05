//! `diff`: a backup compared with the live drive or with another backup. Prints the
//! differences and decides the exit code; must not compare values itself (that is
//! `crate::parameters::compare`).

use super::parameter_commands::{dictionary_for, load, open, read_live};
use super::stop_signals;
use crate::family::Registry;
use crate::parameters::{self, Difference};
use crate::run::{ConnectionArgs, DictionaryArgs, FAILED, INVALID, PASSED};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
/// Compare a backup with the live drive or with another backup
///
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

fn print_differences(differences: &[Difference], left: &str, right: &str) {
    // Names line up to a width a terminal shows; a longer one (an EDS name can be of any
    // length) pushes its own row only, and never past what `format!` can pad.
    let width = differences
        .iter()
        .map(|d| d.name().chars().count())
        .max()
        .unwrap_or(0)
        .min(super::MAX_ALIGNED_WIDTH);
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
    let mut left = match load(first) {
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
            left.named_by(&dictionary);
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
