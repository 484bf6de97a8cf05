//! Limits learnt from the drive itself, for families whose drives report them (Lenze 931:
//! `ON`/`OX`): `check --port` and `run` compare every number a recipe (or a script, as a
//! literal) writes with them before anything moves, and `objects --from-drive` shows
//! them. Only reads are sent; a family whose drives report no limits is asked nothing.

use super::connection_args::ConnectionArgs;
use super::drive_args::{open_drive, OpenDrive};
use super::RunError;
use crate::dictionary::{Dictionary, Value};
use crate::drive::{Drive, DriveError};
use crate::family::Registry;
use crate::recipe::WrittenValue;
use crate::stop_request::StopRequests;
use std::collections::BTreeMap;
use std::io::Write;
use std::sync::Arc;

/// What comparing the written values with the drive's limits came to.
#[derive(Debug, Default)]
pub struct DriveCheck {
    /// The limits read, one line per object.
    pub read: Vec<String>,
    /// Objects whose limits the family's drives do not report.
    pub not_reported: Vec<String>,
    /// Values outside (or objects whose limits the drive refused to give): one line each.
    pub problems: Vec<String>,
}

use crate::drive::ValueLimits as Limits;

/// Reads the drive's limits of every object `values` write (each object once) and
/// compares each value with them; `Err` when the drive could not be reached. Sends
/// nothing at all for a family whose drives report no limits.
pub fn compare(values: &[WrittenValue], drive: &mut Drive) -> Result<DriveCheck, RunError> {
    let port = drive.port();
    let mut limits: BTreeMap<String, Result<Option<Limits>, DriveError>> = BTreeMap::new();
    for w in values {
        if !limits.contains_key(&w.object.name) {
            // `left.speed_setpoint` in a recipe with `drives:`: the drive's own name.
            let own = w
                .object
                .name
                .split_once('.')
                .map_or(w.object.name.as_str(), |(_, o)| o);
            let l = read_limits(drive, own);
            if let Err(e) = &l {
                if e.is_communication() {
                    return Err(RunError::Unreachable(e.to_string()));
                }
            }
            limits.insert(w.object.name.clone(), l);
        }
    }
    let mut check = DriveCheck::default();
    for (name, l) in &limits {
        match l {
            Ok(Some(l)) => check
                .read
                .push(format!("drive limits of {name}: {} (read from {port})", show(l))),
            Ok(None) => check.not_reported.push(format!(
                "drive limits of {name}: the {} family's drives do not report limits; the dictionary's were checked",
                drive.dictionary().family()
            )),
            Err(e) => check
                .problems
                .push(format!("cannot read the drive's limits of {name}: {e}")),
        }
    }
    for w in values {
        let Some(Ok(Some((min, max)))) = limits.get(&w.object.name) else {
            continue;
        };
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
            check.problems.push(format!(
                "{} is above the maximum the drive reports, {limit}",
                w.described()
            ));
        }
        if let Some(limit) = outside(min, false) {
            check.problems.push(format!(
                "{} is below the minimum the drive reports, {limit}",
                w.described()
            ));
        }
    }
    Ok(check)
}

/// Says what `check` came to, as `check --port` and `run` both say it: the limits read
/// (and, with `not_reported`, the objects whose limits the family's drives do not
/// report) on `out`, each value outside with its place and the drive's limit on `err`.
/// The exit code: 0 within, 2 for values outside, 3 for a drive that could not be
/// reached; with it, the error line (also written to `err`) for the not-run reports.
pub fn report(
    check: &Result<DriveCheck, RunError>,
    path: &str,
    not_reported: bool,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> (i32, String) {
    match check {
        Ok(check) => {
            let lines = check
                .read
                .iter()
                .chain(check.not_reported.iter().filter(|_| not_reported));
            for l in lines {
                let _ = writeln!(out, "    {l}");
            }
            if check.problems.is_empty() {
                return (super::PASSED, String::new());
            }
            let _ = writeln!(
                out,
                "    refused: {} value(s) outside the limits the drive reports",
                check.problems.len()
            );
            for p in &check.problems {
                let _ = writeln!(err, "  × {p}");
            }
            let text = format!(
                "error: {} value(s) of {path} lie outside the limits the drive reports; nothing was sent to move the drive. Lower the value, or change the drive's limit first",
                check.problems.len()
            );
            let _ = writeln!(err, "{text}");
            let mut why = check.problems.iter().fold(String::new(), |mut s, p| {
                s.push_str(&format!("× {p}\n"));
                s
            });
            why.push_str(&text);
            (super::INVALID, why)
        }
        Err(e) => {
            let _ = writeln!(err, "{e}");
            let text = format!(
                "error: the drive's limits could not be read; {path} was checked against the dictionary only"
            );
            let _ = writeln!(err, "{text}");
            (super::COMMUNICATION, format!("{e}\n{text}"))
        }
    }
}

/// Before the first telegram that moves anything: the values `values` write compared with
/// the limits the drive itself reports, as `check --port` compares them (families whose
/// drives report none are asked nothing and nothing is said). `Err` holds the exit code
/// and the reason for the not-run reports, already said on `err`.
pub fn within_drive_limits(
    values: &[WrittenValue],
    drive: &mut Drive,
    path: &str,
    stop: &StopRequests,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<(), (i32, String)> {
    let check = compare(values, drive);
    // A stop signal while the limits were read ends the run with that signal's code; the
    // unanswered read is no communication failure.
    if let (Err(_), Some(signal)) = (&check, stop.first()) {
        let why = format!(
            "stopped by {} while the drive's limits were read; nothing was sent to move the drive",
            signal.describe()
        );
        let _ = writeln!(err, "{why}");
        return Err((signal.exit_code(), why));
    }
    match report(&check, path, false, out, err) {
        (super::PASSED, _) => Ok(()),
        (code, why) => Err((code, why)),
    }
}

/// `check --port`: opens the drive and compares `values` (a recipe's, or a script's
/// literal ones) with its limits; `Err` when the drive could not be reached. Only reads
/// are sent.
pub fn against_drive(
    registry: &Registry,
    values: &[WrittenValue],
    dictionary: Arc<Dictionary>,
    connection: &ConnectionArgs,
    err: &mut dyn Write,
) -> Result<DriveCheck, RunError> {
    open(registry, connection, dictionary, err).and_then(|mut open| compare(values, &mut open.drive))
}

/// Each object's limits as text for a listing, by the object's name.
pub type LimitsByName = BTreeMap<String, String>;

/// The drive's limits of each of `names`, as text for a listing (`-6000 rpm .. 6000 rpm`,
/// `not reported`, or why they could not be read), and what was asked.
pub fn read_all(
    registry: &Registry,
    names: &[String],
    dictionary: Arc<Dictionary>,
    connection: &ConnectionArgs,
    err: &mut dyn Write,
) -> Result<(String, LimitsByName), RunError> {
    let mut open = open(registry, connection, dictionary, err)?;
    let mut out = BTreeMap::new();
    for name in names {
        let text = match read_limits(&mut open.drive, name) {
            Ok(Some(l)) => show(&l),
            Ok(None) => "not reported".to_string(),
            Err(e) if e.is_communication() => return Err(RunError::Unreachable(e.to_string())),
            Err(e) => format!("error: {e}"),
        };
        out.insert(name.clone(), text);
    }
    Ok((open.drive.port(), out))
}

fn open(
    registry: &Registry,
    connection: &ConnectionArgs,
    dictionary: Arc<Dictionary>,
    err: &mut dyn Write,
) -> Result<OpenDrive, RunError> {
    let open = open_drive(registry, connection, dictionary, true, None, None)?;
    if open.simulator.is_some() {
        let _ = writeln!(err, "using {}: its limits, not a real drive's", open.description);
    }
    Ok(open)
}

/// One object's limits; `None` where the family's drives report none.
fn read_limits(drive: &mut Drive, name: &str) -> Result<Option<Limits>, DriveError> {
    drive.limits(name).transpose()
}

fn show((min, max): &Limits) -> String {
    let side = |v: &Option<Value>, open: &str| v.as_ref().map_or(open.to_string(), |v| v.to_string());
    format!("{} .. {}", side(min, "no minimum"), side(max, "no maximum"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::{ObjectRef, StepOrigin};

    /// The simulated 931 with one object at the simulator's speed-setpoint number.
    fn simulated_931() -> Drive {
        let registry = Registry::builtin();
        let family = registry.family("lenze-931").unwrap();
        let text = "family: lenze-931\nobjects:\n  - name: speed_setpoint\n    address: \"0x0010\"\n    type: i32\n    unit: rpm\n    access: rw\n";
        let dictionary = Dictionary::from_yaml_for("t.yaml", text, family.address_parser()).unwrap();
        open_drive(
            &registry,
            &ConnectionArgs::simulated(),
            Arc::new(dictionary),
            true,
            None,
            None,
        )
        .unwrap()
        .drive
    }

    fn written(name: &str, value: f64) -> WrittenValue {
        WrittenValue {
            object: ObjectRef {
                name: name.into(),
                unit: Some("rpm".into()),
            },
            value,
            origin: StepOrigin {
                path: "r.yaml".into(),
                line: 7,
                column: 5,
            },
            step: "set",
        }
    }

    #[test]
    fn a_drives_own_name_is_looked_up_and_the_recipes_name_shown() {
        let mut drive = simulated_931();
        let check = compare(
            &[
                written("axis.speed_setpoint", 100.0),
                written("axis.speed_setpoint", 7000.0),
            ],
            &mut drive,
        )
        .unwrap();
        assert_eq!(check.read.len(), 1, "each object once: {:?}", check.read);
        assert_eq!(
            check.problems,
            ["r.yaml:7:5: set axis.speed_setpoint = 7000 rpm is above the maximum the drive reports, 6000 rpm"]
        );
    }
}
