//! What `write` says a number left in the drive: the value its raw count stands for, after
//! the wire's quantisation. Formatting only; it must not talk to a drive.

use crate::dictionary::{ObjectDef, Quantity, RawValue};

/// What a written number leaves in the drive (the wire holds whole counts: `3003 rpm` at
/// 6 rpm a count is `3006 rpm`) and its raw count, with the value given where they differ.
pub(super) fn held(def: &ObjectDef, given: &Quantity, raw: &RawValue) -> (String, String) {
    let Ok(value) = def.value_of(raw.clone()) else {
        return (given.to_string(), format!(" (raw {raw})"));
    };
    let asked = given
        .unit
        .zip(def.unit)
        .map_or(Some(given.value), |(g, own)| g.convert(given.value, own));
    let changed = value
        .quantity
        .zip(asked)
        .is_some_and(|(q, a)| (q.value - a).abs() > 1e-9 * a.abs().max(1.0));
    let note = if changed {
        format!("; {given} given, the nearest the object's resolution holds")
    } else {
        String::new()
    };
    (value.to_string(), format!(" (raw {raw}{note})"))
}
