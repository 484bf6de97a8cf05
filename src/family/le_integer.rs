//! An integer raw value as the little-endian bytes of its type, the way SD2 and CANopen
//! both put it on the wire, refusing what does not fit. Pure; strings are each family's own.

use crate::dictionary::{DataType, RawValue, WireValueError};

/// The little-endian bytes of `raw` in `data_type`'s size; a count outside the type's
/// range or anything but an integer is refused instead of being sent wrapped.
pub fn encode(raw: &RawValue, data_type: DataType) -> Result<Vec<u8>, WireValueError> {
    match raw {
        RawValue::Int(count) => data_type
            .to_le_bytes(*count)
            .ok_or_else(|| WireValueError::Unfit(format!("{count} does not fit {data_type}"))),
        other => Err(WireValueError::Unfit(format!(
            "{other} cannot be sent as {data_type}"
        ))),
    }
}
