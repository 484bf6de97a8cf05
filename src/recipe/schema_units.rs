//! The units a recipe's value may be written in, as the JSON Schema's regex alternatives
//! (any case, as the loader reads them) and the `$defs` key of each kind of value. Pure
//! text; it must not read a dictionary beyond the unit and pole pairs it is given.

use crate::dictionary::{Dimension, Unit};

/// `rpm` → `[rR][pP][mM]`: units are read regardless of case, and JSON Schema patterns
/// have no flags.
pub(super) fn any_case(symbol: &str) -> String {
    symbol
        .chars()
        .map(|c| {
            if c.is_ascii_alphabetic() {
                format!("[{}{}]", c.to_ascii_lowercase(), c.to_ascii_uppercase())
            } else {
                regex_escape(c)
            }
        })
        .collect()
}

fn regex_escape(c: char) -> String {
    if r"\^$.|?*+()[]{}/".contains(c) {
        format!("\\{c}")
    } else {
        c.to_string()
    }
}

/// The units of `dimension`, as a regex alternative.
pub(super) fn units_of(dimension: Dimension) -> String {
    Unit::ALL
        .iter()
        .filter(|u| u.dimension() == dimension)
        .map(|u| any_case(u.symbol()))
        .collect::<Vec<_>>()
        .join("|")
}

/// The `$defs` key of the values of objects in `unit` (`value_speed`, `value_plain`);
/// `value_speed_or_frequency` for an inverter's speed, which the motor's pole pairs let
/// be written in Hz too.
pub(super) fn value_key(unit: Option<Unit>, pole_pairs: bool) -> String {
    match unit {
        Some(u) if pole_pairs && u.dimension() == Dimension::Speed => "value_speed_or_frequency".into(),
        Some(u) => format!("value_{}", u.dimension().name()),
        None => "value_plain".into(),
    }
}
