//! Values the link cannot carry, refused before anything opens: a family may narrow what
//! an object can be written with under the link's settings (the family's `link_range`),
//! and those settings are known before anything is sent. `check` and `run` compare every
//! number a recipe or script writes (`set`, `ramp` points, with `--set` applied) with
//! that range; and note the values the wire's whole counts change (`3003 rpm` sent as
//! 501 counts of 6 rpm is `3006 rpm`). Sends nothing.

use super::{ConnectionArgs, LoadedPlan, RunError};
use crate::dictionary::Dictionary;
use crate::family::Registry;
use crate::recipe::WrittenValue;
use crate::session::number;

/// `Ok` when every value of `values` is within what the link of `connection` carries for
/// its object on the drive it goes to (with `drives:`, `left.speed_setpoint` goes to
/// `left`, checked with `left`'s dictionary and family); otherwise each value beyond, with
/// its place (exit code 2).
pub fn within_link_range(
    values: &[WrittenValue],
    loaded: &LoadedPlan,
    registry: &Registry,
    connection: &ConnectionArgs,
) -> Result<(), RunError> {
    let options = connection.link_options().extra;
    let mut problems = Vec::new();
    for w in values {
        let Some((dictionary, own)) = drive_of(loaded, &w.object.name) else {
            continue;
        };
        let Ok(family) = registry.family(dictionary.family()) else {
            continue;
        };
        let Ok(def) = dictionary.lookup(own) else {
            continue;
        };
        let Some(range) = family.link_range(def, &options) else {
            continue;
        };
        let tolerance = 1e-9 * range.max.abs().max(range.min.abs()).max(1.0);
        if w.value > range.max + tolerance || w.value < range.min - tolerance {
            problems.push(format!(
                "  × {} is beyond {} .. {}{}: {}",
                w.described(),
                number(range.min),
                number(range.max),
                w.unit_text(),
                range.why
            ));
        }
    }
    match problems.is_empty() {
        true => Ok(()),
        false => Err(RunError::Invalid(format!(
            "error: {} value(s) the link cannot carry; nothing was sent\n{}",
            problems.len(),
            problems.join("\n")
        ))),
    }
}

/// Notes on the written values the wire's whole counts change: `recipe.yaml:6:5 set
/// speed_setpoint = 3003 rpm: the drive holds whole counts of 6 rpm, so it gets 3006 rpm`.
/// What `check` says beside its verdict (a note, not a problem: the run sends the nearest
/// count, as `write` does).
pub fn quantised_values(values: &[WrittenValue], loaded: &LoadedPlan) -> Vec<String> {
    let mut notes = Vec::new();
    for w in values {
        let Some((dictionary, own)) = drive_of(loaded, &w.object.name) else {
            continue;
        };
        let Ok(def) = dictionary.lookup(own) else {
            continue;
        };
        let given = crate::dictionary::Quantity::new(w.value, None);
        let Some(held) = def
            .to_raw(&given)
            .ok()
            .and_then(|raw| def.value_of(raw).ok())
            .and_then(|v| v.quantity)
        else {
            continue;
        };
        if (held.value - w.value).abs() > 1e-9 * w.value.abs().max(1.0) {
            notes.push(format!(
                "{}: the drive holds whole counts of {}{}, so it gets {}{}",
                w.described(),
                number(def.scale),
                w.unit_text(),
                number(held.value),
                w.unit_text()
            ));
        }
    }
    notes
}

/// The dictionary of the drive `name` is written to, and the object's name in it: the
/// plan's one dictionary, or the named drive's (`left.speed_setpoint`).
fn drive_of<'a>(loaded: &'a LoadedPlan, name: &'a str) -> Option<(&'a Dictionary, &'a str)> {
    if loaded.drive_dictionaries.is_empty() {
        return Some((&loaded.dictionary, name));
    }
    let (drive, own) = name.split_once('.')?;
    let (_, dictionary) = loaded.drive_dictionaries.iter().find(|(n, _)| n == drive)?;
    Some((dictionary, own))
}
