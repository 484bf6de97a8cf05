//! Reads a quantity of one dimension from a file: a bench limits cap (`max_speed: 12000
//! rpm`), a recipe's standstill speed. It must carry a unit of that dimension and be finite
//! and 0 or more; each problem is recorded at its place with what to write. No I/O; the
//! caller has already read the text (a recipe substitutes its parameters first).

use super::quantity::Quantity;
use super::unit::{Dimension, Unit};
use crate::diag::{Reader, Span};

/// `text`, written at `span` as the value of `key`, as a quantity of `dimension` and its
/// value in the dimension's base unit (rpm, A). `example` is a whole line to write
/// (`max_speed: 12000 rpm`). `None` after recording a problem.
pub(crate) fn read_dimensioned(
    r: &mut Reader,
    span: &Span,
    key: &str,
    text: &str,
    dimension: Dimension,
    example: &str,
) -> Option<(Quantity, f64)> {
    let units = Unit::ALL
        .into_iter()
        .filter(|u| u.dimension() == dimension)
        .map(Unit::symbol)
        .collect::<Vec<_>>()
        .join(" or ");
    let mut refuse = |message: String, label: &str, help: String| {
        r.problem(span, message, label, Some(help));
        None
    };
    let quantity = match Quantity::parse(text) {
        Ok(q) => q,
        Err(e) => {
            return refuse(
                format!("`{key}`: {e}"),
                "not a value",
                format!("write e.g. `{example}`"),
            )
        }
    };
    let Some(unit) = quantity.unit else {
        return refuse(
            format!("`{key}` {text} has no unit"),
            "which unit?",
            format!("write the unit, {units}, e.g. `{example}`"),
        );
    };
    let Some(value) = unit.convert(quantity.value, dimension.base()) else {
        return refuse(
            format!(
                "`{key}` is a {}, but {unit} measures {}",
                dimension.name(),
                unit.dimension().name()
            ),
            "wrong unit",
            format!("write it in {units}, e.g. `{example}`"),
        );
    };
    if !value.is_finite() || value < 0.0 {
        return refuse(
            format!("`{key}` {text} must be a finite number, 0 or more"),
            "not 0 or more",
            format!("write e.g. `{example}`"),
        );
    }
    Some((quantity, value))
}
