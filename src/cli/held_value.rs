//! What `write` says a number left in the drive: the value its raw count stands for, after
//! the wire's quantisation. Formatting only; it must not talk to a drive.

use crate::dictionary::{ObjectDef, Quantity, RawValue};

/// What a written number leaves in the drive (the wire holds whole counts: `3003 rpm` at
/// 6 rpm a count is `3006 rpm`) and its raw count, with the value given where they differ.
pub(super) fn held(def: &ObjectDef, given: &Quantity, raw: &RawValue) -> (String, String) {
    let Ok(value) = def.value_of(raw.clone()) else {
        return (given.to_string(), format!(" (raw {raw})"));
    };
    // In the object's own unit (Hz given for an rpm object goes through its pole pairs).
    let asked = match (given.unit, def.unit) {
        (Some(g), Some(own)) if g != own => def.in_own_unit(given.value, g).ok(),
        _ => Some(given.value),
    };
    let changed = value
        .quantity
        .zip(asked)
        .is_some_and(|(q, a)| (q.value - a).abs() > 1e-9 * a.abs().max(1.0));
    let note = if changed {
        format!("; {given} given, the nearest the object's resolution holds")
    } else {
        String::new()
    };
    // A value given in another unit than the object's is said as given, then as held.
    let shown = match (given.unit, def.unit) {
        (Some(g), Some(own)) if g != own && !changed => format!("{given} ({value})"),
        _ => value.to_string(),
    };
    (shown, format!(" (raw {raw}{note})"))
}
