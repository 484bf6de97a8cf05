//! Values between the drive layer's typed raw values and Modbus registers: 16-bit types in
//! one register, 32-bit types in two (high word first unless the object says low word
//! first), signed types in two's complement. Strings are not carried: no register map seen
//! gives one the same way. Pure.

use crate::dictionary::{DataType, RawValue, WireValueError};
use crate::family::integer_value::integer_in_range;

/// How many registers an object of `data_type` takes; `None` for types Modbus objects
/// cannot have here.
pub fn count(data_type: DataType) -> Option<u16> {
    match data_type {
        DataType::U8 | DataType::I8 | DataType::U16 | DataType::I16 => Some(1),
        DataType::U32 | DataType::I32 => Some(2),
        _ => None,
    }
}

fn unsupported(data_type: DataType) -> WireValueError {
    WireValueError::Unfit(format!(
        "a Modbus object is a 16-bit or 32-bit integer (u16 i16 u32 i32, or u8 i8 in one register), not {data_type}"
    ))
}

pub fn decode(words: &[u16], data_type: DataType, low_word_first: bool) -> Result<RawValue, WireValueError> {
    let n = count(data_type).ok_or_else(|| unsupported(data_type))?;
    if words.len() != usize::from(n) {
        return Err(WireValueError::Malformed(format!(
            "{} register(s) came for an object of {n}",
            words.len()
        )));
    }
    let bits: u32 = match (words, low_word_first) {
        ([w], _) => u32::from(*w),
        ([lo, hi], true) | ([hi, lo], false) => (u32::from(*hi) << 16) | u32::from(*lo),
        _ => unreachable!("count is 1 or 2"),
    };
    let value = match data_type {
        DataType::I8 | DataType::I16 => i64::from(bits as u16 as i16),
        DataType::I32 => i64::from(bits as i32),
        _ => i64::from(bits),
    };
    let fits = data_type
        .range()
        .is_some_and(|(lo, hi)| (lo..=hi).contains(&value));
    if !fits {
        return Err(WireValueError::Malformed(format!(
            "0x{bits:04X} ({value}) does not fit the object's type {data_type}"
        )));
    }
    Ok(RawValue::Int(value))
}

pub fn encode(
    value: &RawValue,
    data_type: DataType,
    low_word_first: bool,
) -> Result<Vec<u16>, WireValueError> {
    let n = count(data_type).ok_or_else(|| unsupported(data_type))?;
    let bits = integer_in_range(value, data_type, "a Modbus register holds a number")? as u32;
    Ok(match (n, low_word_first) {
        (1, _) => vec![bits as u16],
        (_, false) => vec![(bits >> 16) as u16, bits as u16],
        (_, true) => vec![bits as u16, (bits >> 16) as u16],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_and_values_in_both_word_orders() {
        assert_eq!(decode(&[0xFFFF], DataType::I16, false), Ok(RawValue::Int(-1)));
        assert_eq!(decode(&[0xFFFF], DataType::U16, false), Ok(RawValue::Int(65535)));
        assert_eq!(
            decode(&[0x0001, 0x0002], DataType::U32, false),
            Ok(RawValue::Int(0x0001_0002))
        );
        assert_eq!(
            decode(&[0x0002, 0x0001], DataType::U32, true),
            Ok(RawValue::Int(0x0001_0002))
        );
        assert_eq!(
            decode(&[0xFFFF, 0xFFFE], DataType::I32, false),
            Ok(RawValue::Int(-2))
        );
        assert!(decode(&[0x0100], DataType::U8, false).is_err());
        assert_eq!(
            encode(&RawValue::Int(-2), DataType::I32, false),
            Ok(vec![0xFFFF, 0xFFFE])
        );
        assert_eq!(
            encode(&RawValue::Int(0x10002), DataType::U32, true),
            Ok(vec![2, 1])
        );
        assert_eq!(encode(&RawValue::Int(-1), DataType::I16, false), Ok(vec![0xFFFF]));
        assert!(encode(&RawValue::Int(70000), DataType::U16, false).is_err());
        assert!(encode(&RawValue::Text("x".into()), DataType::String { max: 4 }, false).is_err());
    }
}
