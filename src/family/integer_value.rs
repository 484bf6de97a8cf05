//! The integer a number-holding place of a byte family (a Lenze 931 object, a Modbus
//! register) takes from a value to write: within its type's range, or refused with why.
//! Pure; how the integer goes on the wire is each family's own.

use crate::dictionary::{DataType, RawValue, WireValueError};

/// `value` as an integer of `data_type`'s range; `holds` names the place for the refusal of
/// a value that is no integer (`a Modbus register holds a number`).
pub(crate) fn integer_in_range(
    value: &RawValue,
    data_type: DataType,
    holds: &str,
) -> Result<i64, WireValueError> {
    let RawValue::Int(n) = value else {
        return Err(WireValueError::Unfit(format!(
            "{holds}; {value} cannot be written to it"
        )));
    };
    let fits = data_type.range().is_some_and(|(lo, hi)| (lo..=hi).contains(n));
    if !fits {
        return Err(WireValueError::Unfit(format!(
            "{n} is outside the range of the type {data_type}"
        )));
    }
    Ok(*n)
}
