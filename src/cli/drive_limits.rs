//! Limits learnt from the drive itself, for families whose drives report them (Lenze 931:
//! `ON`/`OX`): `check --port` compares every number a recipe writes with them before
//! anything moves, and `objects --from-drive` shows them. Only reads are sent.

use super::connection_args::ConnectionArgs;
use super::drive_args::{open_drive, OpenDrive};
use crate::dictionary::{Dictionary, Value};
use crate::drive::Drive;
use crate::family::Registry;
use crate::recipe::{number, written_values, Recipe};
use std::collections::BTreeMap;
use std::sync::Arc;

/// What comparing a recipe with the drive's limits came to.
pub enum DriveCheck {
    /// Every value lies within; the lines say which limits were read.
    Within(Vec<String>),
    /// Values outside (or objects whose limits the drive refused to give): one line each.
    Outside(Vec<String>, Vec<String>),
    /// The drive could not be reached; nothing was checked.
    Unreachable(String),
}

use crate::drive::ValueLimits as Limits;

/// Opens the drive named by `connection` and checks `recipe`'s values against the limits
/// it reports.
pub fn check_recipe(recipe: &Recipe, dictionary: Arc<Dictionary>, connection: &ConnectionArgs) -> DriveCheck {
    let mut open = match open(connection, dictionary) {
        Ok(o) => o,
        Err(e) => return DriveCheck::Unreachable(e),
    };
    let port = open.drive.port();
    let values = written_values(recipe);
    let mut limits: BTreeMap<String, Result<Option<Limits>, String>> = BTreeMap::new();
    for w in &values {
        if !limits.contains_key(&w.object.name) {
            let l = read_limits(&mut open.drive, &w.object.name);
            if let Err(e) = &l {
                if e.starts_with("unreachable: ") {
                    return DriveCheck::Unreachable(e.trim_start_matches("unreachable: ").to_string());
                }
            }
            limits.insert(w.object.name.clone(), l);
        }
    }
    let mut lines = Vec::new();
    let mut problems = Vec::new();
    for (name, l) in &limits {
        match l {
            Ok(Some(l)) => lines.push(format!("drive limits of {name}: {} (read from {port})", show(l))),
            Ok(None) => lines.push(format!(
                "drive limits of {name}: the {} family's drives do not report limits; the dictionary's were checked",
                open.drive.dictionary().family()
            )),
            Err(e) => problems.push(format!("cannot read the drive's limits of {name}: {e}")),
        }
    }
    for w in &values {
        let Some(Ok(Some((min, max)))) = limits.get(&w.object.name) else {
            continue;
        };
        let unit = w
            .object
            .unit
            .as_deref()
            .map(|u| format!(" {u}"))
            .unwrap_or_default();
        let place = format!("{}:{}:{}", w.origin.path, w.origin.line, w.origin.column);
        let value = format!("{}{unit}", number(w.value));
        let outside = |limit: &Option<Value>, above: bool| {
            let l = limit.as_ref()?.number()?;
            let tolerance = 1e-9 * l.abs().max(1.0);
            let beyond = if above {
                w.value > l + tolerance
            } else {
                w.value < l - tolerance
            };
            beyond.then(|| limit.as_ref().map(|v| v.to_string()).unwrap_or_default())
        };
        if let Some(limit) = outside(max, true) {
            problems.push(format!(
                "{place}: {} {} = {value} is above the maximum the drive reports, {limit}",
                w.step, w.object.name
            ));
        }
        if let Some(limit) = outside(min, false) {
            problems.push(format!(
                "{place}: {} {} = {value} is below the minimum the drive reports, {limit}",
                w.step, w.object.name
            ));
        }
    }
    if problems.is_empty() {
        DriveCheck::Within(lines)
    } else {
        DriveCheck::Outside(lines, problems)
    }
}

/// [`check_recipe`] with its lines printed; the exit code (2 for values outside, 3 for
/// a drive that could not be reached).
pub fn check_and_print(recipe: &Recipe, dictionary: Arc<Dictionary>, connection: &ConnectionArgs) -> i32 {
    match check_recipe(recipe, dictionary, connection) {
        DriveCheck::Within(lines) => {
            for l in lines {
                println!("    {l}");
            }
            super::PASSED
        }
        DriveCheck::Outside(lines, problems) => {
            for l in lines {
                println!("    {l}");
            }
            println!(
                "    refused: {} value(s) outside the limits the drive reports",
                problems.len()
            );
            for p in &problems {
                eprintln!("  × {p}");
            }
            eprintln!(
                "error: {} value(s) of {} lie outside the limits the drive reports; nothing was sent to move the drive. Lower the value, or change the drive's limit first",
                problems.len(),
                recipe.path
            );
            super::INVALID
        }
        DriveCheck::Unreachable(e) => {
            eprintln!("{e}");
            eprintln!(
                "error: the drive's limits could not be read; {} was checked against the dictionary only",
                recipe.path
            );
            super::COMMUNICATION
        }
    }
}

/// The drive's limits of each of `names`, as text for a listing (`-6000 rpm .. 6000 rpm`,
/// `not reported`, or why they could not be read), and what was asked.
pub fn read_all(
    names: &[String],
    dictionary: Arc<Dictionary>,
    connection: &ConnectionArgs,
) -> Result<(String, BTreeMap<String, String>), String> {
    let mut open = open(connection, dictionary)?;
    let mut out = BTreeMap::new();
    for name in names {
        let text = match read_limits(&mut open.drive, name) {
            Ok(Some(l)) => show(&l),
            Ok(None) => "not reported".to_string(),
            Err(e) if e.starts_with("unreachable: ") => {
                return Err(e.trim_start_matches("unreachable: ").to_string())
            }
            Err(e) => format!("error: {e}"),
        };
        out.insert(name.clone(), text);
    }
    Ok((open.drive.port(), out))
}

fn open(connection: &ConnectionArgs, dictionary: Arc<Dictionary>) -> Result<OpenDrive, String> {
    let open = open_drive(&Registry::builtin(), connection, dictionary, true, None, None)?;
    if open.simulator.is_some() {
        eprintln!("using {}: its limits, not a real drive's", open.description);
    }
    Ok(open)
}

/// One object's limits; an error that means the drive cannot be reached at all is
/// prefixed `unreachable: `.
fn read_limits(drive: &mut Drive, name: &str) -> Result<Option<Limits>, String> {
    match drive.limits(name) {
        None => Ok(None),
        Some(Ok(l)) => Ok(Some(l)),
        Some(Err(e)) if e.is_communication() => Err(format!("unreachable: {e}")),
        Some(Err(e)) => Err(e.to_string()),
    }
}

fn show((min, max): &Limits) -> String {
    let side = |v: &Option<Value>, open: &str| v.as_ref().map_or(open.to_string(), |v| v.to_string());
    format!("{} .. {}", side(min, "no minimum"), side(max, "no maximum"))
}
