//! Restoring a backup: the plan (writable parameters whose live value differs, in the
//! order the dictionary declares them, each value checked against the dictionary's and the
//! bench's limits before the first write), and carrying it out with every written object
//! read back. Writes only what the plan lists, and never while the drive's power stage may
//! be on (the interlock [`clear_for_restore`], which [`apply`] asks itself before the first
//! write); the caller decides whether to apply the plan.

use super::backup::raw_text;
use super::comparison::same;
use super::parameter_file::{ParameterFile, Reading, SavedObject};
use crate::dictionary::{ObjectDef, Quantity, RawValue, ValueError};
use crate::drive::{DeviceState, Drive, DriveError, WriteOutcome};

/// One write of the plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedWrite {
    pub name: String,
    /// The live value now and the backup's, as shown.
    pub now: String,
    pub to: String,
    /// The backup's raw value, which the read-back must match.
    pub raw: String,
    value: WriteValue,
}

impl PlannedWrite {
    /// The number to write in the object's unit; `None` for text.
    pub fn number(&self) -> Option<f64> {
        match &self.value {
            WriteValue::Number(q) => Some(q.value),
            WriteValue::Text(_) => None,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
enum WriteValue {
    Number(Quantity),
    Text(String),
}

/// Why a backup's object cannot be restored; any of these stops the restore before the
/// first write.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    pub name: String,
    pub reason: RefusalReason,
}

/// What keeps one backup value from being written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RefusalReason {
    #[error("differs from the backup but is read-only")]
    ReadOnly,
    #[error("raw value `{raw}` is not a number")]
    NotANumber { raw: String },
    #[error("raw value `{raw}` has no number")]
    NoNumber { raw: String },
    /// The object's type, or its limits (the dictionary's or the bench's, which it names).
    #[error(transparent)]
    Value(#[from] ValueError),
}

/// The writes that make the live set equal the backup, or every reason it cannot.
pub fn plan(
    dictionary: &crate::dictionary::Dictionary,
    backup: &ParameterFile,
    live: &ParameterFile,
) -> Result<Vec<PlannedWrite>, Vec<Refusal>> {
    let mut writes = Vec::new();
    let mut refusals = Vec::new();
    // Objects beyond the dictionary (a `backup --all` scan) have no known access or limits:
    // `diff` compares them, `restore` leaves them alone (see `skipped`).
    // Dictionary order: a selection object (the parameter set) comes before what it selects.
    for def in dictionary.objects().filter(|o| o.parameter) {
        let Some(saved) = backup.objects.iter().find(|o| o.name == def.name) else {
            continue;
        };
        let Some(raw) = saved.raw() else {
            continue; // Unreadable when the backup was taken: nothing to restore.
        };
        let current = live.objects.iter().find(|o| o.name == def.name);
        if current.is_some_and(|c| same(saved, c, 0.0)) {
            continue;
        }
        if !def.writable() {
            refusals.push(Refusal {
                name: def.name.clone(),
                reason: RefusalReason::ReadOnly,
            });
            continue;
        }
        match value_to_write(def, raw) {
            Ok(value) => writes.push(PlannedWrite {
                name: def.name.clone(),
                now: current.map_or_else(|| "not read".to_string(), shown),
                to: saved.shown().unwrap_or(raw).to_string(),
                raw: raw.to_string(),
                value,
            }),
            Err(reason) => refusals.push(Refusal {
                name: def.name.clone(),
                reason,
            }),
        }
    }
    if refusals.is_empty() {
        Ok(writes)
    } else {
        Err(refusals)
    }
}

fn shown(o: &SavedObject) -> String {
    match &o.reading {
        Reading::Value { shown, .. } => shown.clone(),
        Reading::Error(e) => format!("unreadable ({e})"),
    }
}

/// The backup's raw text as a value to write, checked against the object's type and its
/// (bench-tightened) limits.
fn value_to_write(def: &ObjectDef, raw: &str) -> Result<WriteValue, RefusalReason> {
    if !def.data_type.is_number() {
        def.text_to_raw(raw)?;
        return Ok(WriteValue::Text(raw.to_string()));
    }
    // A float as the shortest text of its bits, which reads back to them exactly.
    let parsed = match def.data_type.float_single() {
        Some(single) => crate::dictionary::Real::parse(raw, single).map(RawValue::Real),
        None => parse_raw(raw),
    }
    .ok_or_else(|| RefusalReason::NotANumber { raw: raw.to_string() })?;
    let value = def.value_of(parsed)?;
    let quantity = value
        .quantity
        .ok_or_else(|| RefusalReason::NoNumber { raw: raw.to_string() })?;
    // to_raw refuses what is outside the limits, saying which (the dictionary's or the bench's).
    def.to_raw(&quantity)?;
    Ok(WriteValue::Number(quantity))
}

/// The backup's objects the dictionary does not know, which a restore does not write.
pub fn skipped<'a>(dictionary: &crate::dictionary::Dictionary, backup: &'a ParameterFile) -> Vec<&'a str> {
    backup
        .objects
        .iter()
        .filter(|o| dictionary.get(&o.name).is_none())
        .map(|o| o.name.as_str())
        .collect()
}

/// A backup's raw number: whole counts (`6000000`) or an exact decimal as the drive sent
/// it (`1500.5`, Control Techniques).
fn parse_raw(text: &str) -> Option<RawValue> {
    let t = text.trim();
    match t.split_once('.') {
        None => t.parse().ok().map(RawValue::Int),
        Some((whole, frac)) => {
            if frac.is_empty() || !frac.chars().all(|c| c.is_ascii_digit()) {
                return None;
            }
            let places = u8::try_from(frac.len()).ok()?;
            let digits: i64 = format!("{whole}{frac}").parse().ok()?;
            // `-0.5`: the sign belongs to the whole value.
            let digits = if whole.starts_with('-') && digits > 0 {
                -digits
            } else {
                digits
            };
            Some(RawValue::Decimal { digits, places })
        }
    }
}

/// Why a restore was refused before anything was written.
#[derive(Debug, thiserror::Error)]
pub enum RestoreRefused {
    /// The power stage may be on or the motor braking: some parameters change the
    /// motor's behaviour at once.
    #[error("the drive is in {state}; disable it first with `drivescript stop` and the same connection options (or the drive's own controls); nothing was written")]
    Powered { state: DeviceState },
    /// The state cannot be read, and `force` was not given.
    #[error("cannot tell whether the drive is enabled ({cause}); make sure it is disabled and give --force; nothing was written")]
    StateUnknown { cause: DriveError },
}

/// The restore's interlock, asked now: refused while the drive is powered, whatever
/// `force` says; where the state cannot be read, only `force` clears it, and the answer
/// is then why it was not checked (for a warning).
pub fn clear_for_restore(drive: &mut Drive, force: bool) -> Result<Option<DriveError>, RestoreRefused> {
    match drive.state() {
        Ok(state) if state.is_powered() => Err(RestoreRefused::Powered { state }),
        Ok(_) => Ok(None),
        Err(cause) if force => Ok(Some(cause)),
        Err(cause) => Err(RestoreRefused::StateUnknown { cause }),
    }
}

/// What happened to one planned write.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Written and read back equal.
    Written,
    /// The drive stored another value than the one sent (Lenze 931 "written, but limited").
    Limited { stored: String },
    /// Written, but the read-back differs.
    Mismatch { read_back: String },
    /// The write failed; nothing after it was written.
    Failed(String),
}

/// Carries out `plan` in order, after the interlock [`clear_for_restore`] is asked again
/// just before the first write (with `force` for a state that cannot be read).
/// `keep_going()` is asked before each write: a stop request ends the restore there, and
/// the result lists exactly what was written.
pub fn apply(
    drive: &mut Drive,
    plan: &[PlannedWrite],
    force: bool,
    keep_going: &dyn Fn() -> bool,
    progress: &mut dyn FnMut(&PlannedWrite, &Outcome),
) -> Result<Vec<(String, Outcome)>, RestoreRefused> {
    clear_for_restore(drive, force)?;
    let mut done = Vec::new();
    for w in plan {
        if !keep_going() {
            break;
        }
        let written = match &w.value {
            WriteValue::Number(q) => drive.write(&w.name, q),
            WriteValue::Text(t) => drive.write_text(&w.name, t),
        };
        let outcome = match written {
            Err(e) => Outcome::Failed(e.to_string()),
            Ok(result) => match drive.read(&w.name) {
                Err(e) => Outcome::Failed(format!("written, but reading it back failed: {e}")),
                Ok(v) => {
                    let back = raw_text(&v.raw);
                    match result {
                        WriteOutcome::Limited(_) => Outcome::Limited {
                            stored: v.to_string(),
                        },
                        WriteOutcome::Stored if back == w.raw => Outcome::Written,
                        WriteOutcome::Stored => Outcome::Mismatch {
                            read_back: v.to_string(),
                        },
                    }
                }
            },
        };
        progress(w, &outcome);
        let failed = matches!(outcome, Outcome::Failed(_));
        done.push((w.name.clone(), outcome));
        if failed {
            break;
        }
    }
    Ok(done)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_numbers_read_back_exactly() {
        assert_eq!(parse_raw("6000000"), Some(RawValue::Int(6_000_000)));
        assert_eq!(parse_raw("-12"), Some(RawValue::Int(-12)));
        assert_eq!(
            parse_raw("1500.5"),
            Some(RawValue::Decimal {
                digits: 15005,
                places: 1
            })
        );
        assert_eq!(
            parse_raw("-0.50"),
            Some(RawValue::Decimal {
                digits: -50,
                places: 2
            })
        );
        assert_eq!(
            parse_raw("60000.0"),
            Some(RawValue::Decimal {
                digits: 600000,
                places: 1
            })
        );
        for bad in ["", "1.", ".5x", "abc", "1.2.3"] {
            assert_eq!(parse_raw(bad), None, "{bad}");
        }
    }
}
