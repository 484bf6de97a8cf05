//! A value an operation writes: a number in the object's unit, or text for string
//! objects. Plain data.

use crate::dictionary::Quantity;

/// A value to write: a number in the object's unit (a bare quantity, which keeps a whole
/// number exactly), or text for string objects.
#[derive(Debug, Clone, PartialEq)]
pub enum SetValue {
    Number(Quantity),
    Text(String),
}

impl SetValue {
    /// A number in the object's unit.
    pub fn number(value: f64) -> SetValue {
        SetValue::Number(Quantity::new(value, None))
    }
}
