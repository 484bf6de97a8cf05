//! Raw values as SDO carries them: integers little-endian, strings as their characters
//! (VISIBLE_STRING, no length byte; trailing NULs a node pads with are dropped). Pure.
//!
//! The rule for reading with the size the node indicates: a value of exactly the type's
//! width is read as the type; a narrower one (a 2-byte code read as `i32`, the type a raw
//! `read C…` without `--type` assumes) is widened with the type's signedness, so give
//! `--type u16` to read a 16-bit unsigned code above 32767 right; a wider one is refused
//! (length mismatch). Without a size indication the type's width is taken from the 4 bytes.

use super::codec::Uploaded;
use crate::dictionary::{DataType, RawValue, WireValueError};

/// Decodes an uploaded value as `data_type`; the error says expected vs. actual.
pub fn decode(value: &Uploaded, data_type: DataType) -> Result<RawValue, WireValueError> {
    let bytes = value.data.as_slice();
    if let DataType::String { max } = data_type {
        let text: &[u8] = match bytes.iter().rposition(|&b| b != 0) {
            Some(end) => &bytes[..=end],
            None => &[],
        };
        if text.len() > usize::from(max) {
            return Err(WireValueError::Malformed(format!(
                "{data_type} holds at most {max} characters, the node sent {}",
                text.len()
            )));
        }
        return Ok(RawValue::Text(String::from_utf8_lossy(text).into_owned()));
    }
    let size = data_type.size();
    // A 64-bit value does not fit an expedited transfer: it comes in segments, whole.
    let whole_in_segments = size > 4 && bytes.len() == size;
    if value.segmented && !whole_in_segments {
        return Err(WireValueError::Malformed(format!(
            "the node sent {} bytes in segments (a string or a block parameter), not a {data_type}; read it with --type string(N)",
            bytes.len()
        )));
    }
    let used = if value.size_indicated {
        bytes.len()
    } else {
        size.min(bytes.len())
    };
    if used > size || used == 0 {
        return Err(WireValueError::Malformed(format!(
            "{data_type} takes {size} byte(s), the node indicated {used} (length mismatch)"
        )));
    }
    let count = data_type.from_le_bytes(&bytes[..used]);
    if data_type == DataType::U64 && count < 0 {
        return Err(WireValueError::Malformed(format!(
            "the node sent {}, beyond the 2^63 − 1 drivescript carries for u64",
            u64::from_le_bytes(bytes[..8].try_into().unwrap_or([0; 8]))
        )));
    }
    Ok(RawValue::Int(count))
}

/// The bytes to write for `raw`: an integer in the type's width, text as its characters.
/// What does not fit the type is refused instead of being sent wrapped.
pub fn encode(raw: &RawValue, data_type: DataType) -> Result<Vec<u8>, WireValueError> {
    match (data_type, raw) {
        (DataType::String { max }, RawValue::Text(text)) => {
            if text.is_empty() || text.len() > usize::from(max) || !text.is_ascii() {
                return Err(WireValueError::Unfit(format!(
                    "{text:?} does not fit {data_type} (1..={max} ASCII characters)"
                )));
            }
            Ok(text.as_bytes().to_vec())
        }
        (data_type, raw) => crate::family::le_integer::encode(raw, data_type),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn expedited(data: &[u8], size_indicated: bool) -> Uploaded {
        Uploaded {
            data: data.to_vec(),
            size_indicated,
            segmented: false,
        }
    }

    #[test]
    fn sixty_four_bit_values_come_whole_in_segments() {
        let segmented = |data: &[u8]| Uploaded {
            data: data.to_vec(),
            size_indicated: true,
            segmented: true,
        };
        let minus_two = (-2i64).to_le_bytes();
        assert_eq!(
            decode(&segmented(&minus_two), DataType::I64),
            Ok(RawValue::Int(-2))
        );
        let big = (1u64 << 40).to_le_bytes();
        assert_eq!(
            decode(&segmented(&big), DataType::U64),
            Ok(RawValue::Int(1 << 40))
        );
        assert!(decode(&segmented(&u64::MAX.to_le_bytes()), DataType::U64)
            .unwrap_err()
            .to_string()
            .contains("2^63 − 1"));
        assert!(decode(&segmented(&[1, 2, 3, 4, 5]), DataType::I64).is_err());
        assert_eq!(encode(&RawValue::Int(-2), DataType::I64), Ok(minus_two.to_vec()));
        assert!(encode(&RawValue::Int(-1), DataType::U64).is_err());
    }

    #[test]
    fn the_size_rule() {
        assert_eq!(
            decode(&expedited(&[0x2b, 0, 0, 0], true), DataType::I32),
            Ok(RawValue::Int(43))
        );
        assert_eq!(
            decode(&expedited(&[0xff, 0xff], true), DataType::I32),
            Ok(RawValue::Int(-1))
        );
        assert_eq!(
            decode(&expedited(&[0xff, 0xff], true), DataType::U32),
            Ok(RawValue::Int(65535))
        );
        assert_eq!(
            decode(&expedited(&[0x34, 0x12, 0xaa, 0xbb], false), DataType::U16),
            Ok(RawValue::Int(0x1234))
        );
        assert!(decode(&expedited(&[1, 0, 0, 0], true), DataType::U16)
            .unwrap_err()
            .to_string()
            .contains("length mismatch"));
        let text = Uploaded {
            data: b"05.00.12.07".to_vec(),
            size_indicated: true,
            segmented: true,
        };
        assert_eq!(
            decode(&text, DataType::String { max: 11 }),
            Ok(RawValue::Text("05.00.12.07".into()))
        );
        assert!(decode(&text, DataType::String { max: 8 }).is_err());
        assert!(decode(&text, DataType::I32)
            .unwrap_err()
            .to_string()
            .contains("--type string"));
    }

    #[test]
    fn encoding_refuses_what_does_not_fit() {
        assert_eq!(
            encode(&RawValue::Int(102), DataType::I32),
            Ok(vec![0x66, 0, 0, 0])
        );
        assert_eq!(
            encode(&RawValue::Int(3000), DataType::I32),
            Ok(vec![0xb8, 0x0b, 0, 0])
        );
        assert!(encode(&RawValue::Int(70000), DataType::U16).is_err());
        assert!(encode(&RawValue::Text("ab".into()), DataType::U16).is_err());
        assert_eq!(
            encode(&RawValue::Text("ab".into()), DataType::String { max: 4 }),
            Ok(b"ab".to_vec())
        );
    }

    proptest! {
        #[test]
        fn integers_round_trip(v in any::<i32>()) {
            let bytes = encode(&RawValue::Int(v.into()), DataType::I32).unwrap();
            prop_assert_eq!(decode(&expedited(&bytes, true), DataType::I32), Ok(RawValue::Int(v.into())));
        }
    }
}
