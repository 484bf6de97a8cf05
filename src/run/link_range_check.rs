//! Values the link cannot carry, refused before anything opens: a family may narrow what
//! an object can be written with under the link's settings (the family's `link_range`),
//! and those settings are known before anything is sent. `check` and `run` compare every
//! number a recipe or script writes (`set`, `ramp` points, with `--set` applied) with
//! that range. Sends nothing.

use super::{ConnectionArgs, RunError};
use crate::dictionary::Dictionary;
use crate::family::Registry;
use crate::recipe::WrittenValue;
use crate::session::number;

/// `Ok` when every value of `values` is within what the link of `connection` carries for
/// its object; otherwise each value beyond, with its place (exit code 2).
pub fn within_link_range(
    values: &[WrittenValue],
    dictionary: &Dictionary,
    registry: &Registry,
    connection: &ConnectionArgs,
) -> Result<(), RunError> {
    let Ok(family) = registry.family(dictionary.family()) else {
        return Ok(());
    };
    let options = connection.link_options().extra;
    let mut problems = Vec::new();
    for w in values {
        let Ok(def) = dictionary.lookup(&w.object.name) else {
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
