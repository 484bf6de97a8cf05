//! A value an operation writes: a number in the object's unit, or text for string
//! objects. Plain data.

/// A value to write: a number in the object's unit, or text for string objects.
#[derive(Debug, Clone, PartialEq)]
pub enum SetValue {
    Number(f64),
    Text(String),
}
