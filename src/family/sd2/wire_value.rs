//! Raw values as SD2 puts them in a block's data field: integers little-endian in the
//! type's size; strings as `data[0]` = maximum length, then the characters, NUL-terminated
//! when shorter (the read layout; the sources show no string write). Pure.

use crate::dictionary::{DataType, RawValue, WireValueError};

/// Decodes a data field; a wrong byte count is refused with expected vs. actual.
pub fn decode(bytes: &[u8], data_type: DataType) -> Result<RawValue, WireValueError> {
    let size = data_type.size();
    let wrong_count = |expected: String| {
        WireValueError::Malformed(format!("{data_type} takes {expected} bytes, got {}", bytes.len()))
    };
    if let DataType::String { .. } = data_type {
        let Some((_, chars)) = bytes.split_first() else {
            return Err(wrong_count(format!("1 to {size}")));
        };
        if bytes.len() > size {
            return Err(wrong_count(format!("1 to {size}")));
        }
        let text: Vec<u8> = chars.iter().copied().take_while(|&b| b != 0).collect();
        return Ok(RawValue::Text(String::from_utf8_lossy(&text).into_owned()));
    }
    if bytes.len() != size {
        return Err(wrong_count(size.to_string()));
    }
    Ok(RawValue::Int(data_type.from_le_bytes(bytes)))
}

/// The data field for `raw`. A value that does not fit the type (text for an integer, a
/// count outside the type's range, text too long or not ASCII) is refused instead of
/// being written wrapped.
pub fn encode(raw: &RawValue, data_type: DataType) -> Result<Vec<u8>, WireValueError> {
    match (data_type, raw) {
        (DataType::String { max }, RawValue::Text(text)) => {
            if text.len() > usize::from(max) || !text.is_ascii() {
                return Err(WireValueError::Unfit(format!(
                    "{text:?} does not fit {data_type}"
                )));
            }
            let mut bytes = Vec::with_capacity(text.len() + 2);
            bytes.push(max);
            bytes.extend_from_slice(text.as_bytes());
            if text.len() < usize::from(max) {
                bytes.push(0);
            }
            Ok(bytes)
        }
        (data_type, raw) => crate::family::le_integer::encode(raw, data_type),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn every_integer_type_both_ways() {
        let cases: [(DataType, &[u8], i64); 6] = [
            (DataType::U8, &[0xff], 255),
            (DataType::I8, &[0xff], -1),
            (DataType::U16, &[0x37, 0x02], 0x237),
            (DataType::I16, &[0x00, 0x80], -32768),
            (DataType::U32, &[0xff, 0xff, 0xff, 0xff], 4_294_967_295),
            (DataType::I32, &[0x7f, 0x50, 0x0f, 0x00], 1_003_647),
        ];
        for (t, bytes, expected) in cases {
            let v = decode(bytes, t).unwrap();
            assert_eq!(v, RawValue::Int(expected), "{t}");
            assert_eq!(encode(&v, t).unwrap(), bytes, "{t}");
        }
    }

    #[test]
    fn strings_both_ways() {
        let ident = DataType::String { max: 32 };
        let bytes = [
            0x20, 0x54, 0x65, 0x73, 0x74, 0x20, 0x4d, 0x6f, 0x74, 0x6f, 0x72, 0x00,
        ];
        assert_eq!(decode(&bytes, ident), Ok(RawValue::Text("Test Motor".into())));
        assert_eq!(decode(&[0x20], ident), Ok(RawValue::Text(String::new())));
        assert_eq!(
            encode(&RawValue::Text("Test Motor".into()), ident).unwrap(),
            bytes.to_vec()
        );
    }

    #[test]
    fn wrong_byte_counts_are_refused() {
        assert_eq!(
            decode(&[1, 2], DataType::I32).unwrap_err(),
            WireValueError::Malformed("i32 takes 4 bytes, got 2".into())
        );
        let ident = DataType::String { max: 32 };
        assert_eq!(
            decode(&[], ident).unwrap_err(),
            WireValueError::Malformed("string(32) takes 1 to 33 bytes, got 0".into())
        );
        assert!(decode(&[0x20; 34], ident).is_err());
    }

    #[test]
    fn values_that_do_not_fit_are_refused() {
        assert!(encode(&RawValue::Int(70000), DataType::U16).is_err());
        assert!(encode(&RawValue::Text("6".into()), DataType::U16).is_err());
        let ident = DataType::String { max: 32 };
        assert!(encode(&RawValue::Int(6), ident).is_err());
        assert!(encode(&RawValue::Text("x".repeat(40)), ident).is_err());
        assert_eq!(encode(&RawValue::Int(15), DataType::U16).unwrap(), vec![15, 0]);
    }

    proptest! {
        #[test]
        fn round_trip_every_integer_type(t in 0usize..6, count in any::<i64>()) {
            let data_type = DataType::INTEGERS[t];
            let (lo, hi) = data_type.range().unwrap();
            let count = lo + (count.rem_euclid(hi - lo + 1));
            let bytes = encode(&RawValue::Int(count), data_type).unwrap();
            prop_assert_eq!(decode(&bytes, data_type).unwrap(), RawValue::Int(count));
        }

        #[test]
        fn decode_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..40), t in 0usize..7) {
            let data_type = if t == 6 { DataType::String { max: 32 } } else { DataType::INTEGERS[t] };
            let _ = decode(&bytes, data_type);
        }
    }
}
