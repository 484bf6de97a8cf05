//! Values between the drive layer's typed raw values and the 931's wire: the 32-bit
//! `DDDDDDDD` of the object commands (two's complement for signed types [I]) and the hex
//! bytes of the SDO simulation (read as CANopen's little-endian order [I]). Pure.

use crate::dictionary::{DataType, RawValue, WireValueError};
use crate::family::integer_value::integer_in_range;

/// The 32 bits of `DDDDDDDD` as a value of `data_type`; refused when they do not fit it.
pub fn decode(bits: u32, data_type: DataType) -> Result<RawValue, WireValueError> {
    let Some((lo, hi)) = data_type.range() else {
        return Err(WireValueError::Malformed(format!(
            "the drive sent the number 0x{bits:08X}, but the object's type is {data_type}; give it an integer type"
        )));
    };
    let value = if data_type.is_signed() {
        i64::from(bits as i32)
    } else {
        i64::from(bits)
    };
    if value < lo || value > hi {
        return Err(WireValueError::Malformed(format!(
            "0x{bits:08X} ({value}) does not fit the object's type {data_type} ({lo}..={hi})"
        )));
    }
    Ok(RawValue::Int(value))
}

/// A value for `OW:NNNN:DDDDDDDD`.
pub fn encode(value: &RawValue, data_type: DataType) -> Result<u32, WireValueError> {
    let n = integer_in_range(value, data_type, "a 931 object holds a 32-bit number")?;
    if data_type.is_signed() {
        i32::try_from(n)
            .map(|v| v as u32)
            .map_err(|_| WireValueError::Unfit(format!("{n} does not fit 32 bits")))
    } else {
        u32::try_from(n).map_err(|_| WireValueError::Unfit(format!("{n} does not fit 32 bits")))
    }
}

/// SDO data as a value of `data_type`: integers little-endian (at most 4 bytes), text as
/// ASCII up to the first NUL.
pub fn decode_bytes(data: &[u8], data_type: DataType) -> Result<RawValue, WireValueError> {
    if let DataType::String { .. } = data_type {
        let end = data.iter().position(|b| *b == 0).unwrap_or(data.len());
        let text = &data[..end];
        if !text.iter().all(|b| b.is_ascii_graphic() || *b == b' ') {
            return Err(WireValueError::Malformed(
                "the SDO data is not printable ASCII text".into(),
            ));
        }
        return Ok(RawValue::Text(String::from_utf8_lossy(text).into_owned()));
    }
    if data.is_empty() || data.len() > 4 {
        return Err(WireValueError::Malformed(format!(
            "{} data byte(s) cannot be a 32-bit number",
            data.len()
        )));
    }
    let mut bits = 0u32;
    for (i, b) in data.iter().enumerate() {
        bits |= u32::from(*b) << (8 * i);
    }
    if data_type.is_signed() && data.len() < 4 && data[data.len() - 1] & 0x80 != 0 {
        bits |= u32::MAX << (8 * data.len());
    }
    decode(bits, data_type)
}

/// A value as SDO data: the type's width, little-endian.
pub fn encode_bytes(value: &RawValue, data_type: DataType) -> Result<Vec<u8>, WireValueError> {
    let bits = encode(value, data_type)?;
    Ok(bits.to_le_bytes()[..data_type.size().min(4)].to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn signed_values_are_twos_complement() {
        assert_eq!(decode(0xFFFF_F448, DataType::I32), Ok(RawValue::Int(-3000)));
        assert_eq!(decode(0xFFFF_F448, DataType::U32), Ok(RawValue::Int(0xFFFF_F448)));
        assert_eq!(decode(0xFFFF_FFFF, DataType::I16), Ok(RawValue::Int(-1)));
        assert!(decode(0x0001_0000, DataType::U16)
            .unwrap_err()
            .to_string()
            .contains("does not fit"));
        assert!(decode(1, DataType::String { max: 8 }).is_err());
        assert_eq!(encode(&RawValue::Int(-3000), DataType::I32), Ok(0xFFFF_F448));
        assert_eq!(encode(&RawValue::Int(3000), DataType::U16), Ok(3000));
        assert!(encode(&RawValue::Int(-1), DataType::U32).is_err());
        assert!(encode(&RawValue::Text("x".into()), DataType::U32).is_err());
    }

    #[test]
    fn sdo_bytes_are_little_endian() {
        assert_eq!(
            decode_bytes(&[0x37, 0x02], DataType::U16),
            Ok(RawValue::Int(0x0237))
        );
        assert_eq!(decode_bytes(&[0xFF, 0xFF], DataType::I16), Ok(RawValue::Int(-1)));
        assert_eq!(
            encode_bytes(&RawValue::Int(0x0237), DataType::U16),
            Ok(vec![0x37, 0x02])
        );
        assert_eq!(
            decode_bytes(b"931E\0\0", DataType::String { max: 8 }),
            Ok(RawValue::Text("931E".into()))
        );
        assert!(decode_bytes(&[1, 2, 3, 4, 5], DataType::U32).is_err());
    }

    proptest! {
        #[test]
        fn every_integer_type_round_trips(t in 0usize..6, n in any::<i64>()) {
            let data_type = DataType::INTEGERS[t];
            let (lo, hi) = data_type.range().unwrap();
            let n = lo + n.rem_euclid(hi - lo + 1);
            let raw = RawValue::Int(n);
            prop_assert_eq!(decode(encode(&raw, data_type).unwrap(), data_type), Ok(raw.clone()));
            prop_assert_eq!(decode_bytes(&encode_bytes(&raw, data_type).unwrap(), data_type), Ok(raw));
        }
    }
}
