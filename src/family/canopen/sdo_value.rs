//! Raw values as SDO carries them: integers little-endian (3 to 7 byte ones too, sign
//! extended), floats as their little-endian IEEE bytes, strings as their characters
//! (VISIBLE_STRING, no length byte; trailing NULs a node pads with are dropped), UNICODE_STRING
//! as UTF-16LE, OCTET_STRING and DOMAIN as the bytes. Pure.
//!
//! The rule for reading with the size the node indicates: a value of exactly the type's
//! width is read as the type; a narrower one (a 2-byte code read as `i32`, the type a raw
//! `read C…` without `--type` assumes) is widened with the type's signedness, so give
//! `--type u16` to read a 16-bit unsigned code above 32767 right; a wider one is refused
//! (length mismatch). Without a size indication the type's width is taken from the 4 bytes.

use super::codec::Uploaded;
use crate::dictionary::{DataType, RawValue, Real, WireValueError};

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
    match data_type {
        // The transfer kept at most MAX_TRANSFER bytes, MAX_BLOCK_LEN.
        DataType::Octets | DataType::Domain => return Ok(RawValue::Bytes(bytes.to_vec())),
        DataType::Unicode => return unicode(bytes),
        _ => {}
    }
    if let Some(single) = data_type.float_single() {
        let size = data_type.size();
        let used = if value.size_indicated {
            bytes.len()
        } else {
            size.min(bytes.len())
        };
        return bytes
            .get(..used)
            .and_then(|b| Real::from_le_bytes(b, single))
            .map(RawValue::Real)
            .ok_or_else(|| {
                WireValueError::Malformed(format!(
                    "{data_type} takes {size} bytes, the node sent {used} (length mismatch)"
                ))
            });
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
        (DataType::Unicode, RawValue::Text(text)) if !text.is_empty() => {
            Ok(text.encode_utf16().flat_map(u16::to_le_bytes).collect())
        }
        (DataType::Octets, RawValue::Bytes(bytes)) if !bytes.is_empty() => Ok(bytes.clone()),
        (DataType::F32, RawValue::Real(r @ Real::Single(_)))
        | (DataType::F64, RawValue::Real(r @ Real::Double(_))) => Ok(r.to_le_bytes()),
        (DataType::Domain | DataType::Unicode | DataType::Octets | DataType::F32 | DataType::F64, raw) => {
            Err(WireValueError::Unfit(format!(
                "{raw} cannot be sent as {data_type}"
            )))
        }
        (data_type, raw) => crate::family::le_integer::encode(raw, data_type),
    }
}

/// UTF-16LE text; trailing NUL characters a node pads with are dropped.
fn unicode(bytes: &[u8]) -> Result<RawValue, WireValueError> {
    if !bytes.len().is_multiple_of(2) {
        return Err(WireValueError::Malformed(format!(
            "UTF-16 text comes in pairs of bytes, the node sent {}",
            bytes.len()
        )));
    }
    let mut units: Vec<u16> = bytes
        .chunks_exact(2)
        .map(|p| u16::from_le_bytes([p[0], p[1]]))
        .collect();
    while units.last() == Some(&0) {
        units.pop();
    }
    Ok(RawValue::Text(String::from_utf16_lossy(&units)))
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

    #[test]
    fn floats_bytes_and_utf16() {
        let whole = |data: &[u8]| Uploaded {
            data: data.to_vec(),
            size_indicated: true,
            segmented: data.len() > 4,
        };
        let one_and_a_half = decode(&whole(&[0, 0, 0xc0, 0x3f]), DataType::F32).unwrap();
        assert_eq!(one_and_a_half.to_string(), "1.5");
        assert_eq!(encode(&one_and_a_half, DataType::F32), Ok(vec![0, 0, 0xc0, 0x3f]));
        let nan = decode(&whole(&[0, 0, 0xc0, 0x7f]), DataType::F32).unwrap();
        assert_eq!(nan.to_string(), "NaN");
        let minus_inf = decode(&whole(&(-f64::INFINITY).to_le_bytes()), DataType::F64).unwrap();
        assert_eq!(minus_inf.to_string(), "-inf");
        assert!(decode(&whole(&[0, 0, 0xc0]), DataType::F32)
            .unwrap_err()
            .to_string()
            .contains("length mismatch"));
        assert!(
            encode(&one_and_a_half, DataType::F64).is_err(),
            "a single is not sent as a double"
        );
        assert!(encode(&RawValue::Int(1), DataType::F32).is_err());
        let i48 = DataType::Int {
            bytes: 6,
            signed: true,
        };
        assert_eq!(
            decode(&whole(&[0xfe, 0xff, 0xff, 0xff, 0xff, 0xff]), i48),
            Ok(RawValue::Int(-2))
        );
        assert_eq!(
            decode(
                &whole(&[0xfe, 0xff, 0xff]),
                DataType::Int {
                    bytes: 3,
                    signed: true
                }
            ),
            Ok(RawValue::Int(-2))
        );
        assert_eq!(
            decode(&whole(&[1, 2, 0xff, 0, 5]), DataType::Octets),
            Ok(RawValue::Bytes(vec![1, 2, 0xff, 0, 5]))
        );
        assert_eq!(
            decode(&whole(&[b'N', 0, 0xa9, 0, 0, 0]), DataType::Unicode),
            Ok(RawValue::Text("N\u{a9}".into()))
        );
        assert!(decode(&whole(&[b'N', 0, 1]), DataType::Unicode).is_err());
        assert_eq!(
            encode(&RawValue::Text("N\u{a9}".into()), DataType::Unicode),
            Ok(vec![b'N', 0, 0xa9, 0])
        );
        assert!(encode(&RawValue::Bytes(vec![1]), DataType::Domain).is_err());
    }

    proptest! {
        /// Whatever a node sends, every type decodes it or says why, and what decodes
        /// encodes back to the same bytes.
        #[test]
        fn any_bytes_decode_without_panic_and_round_trip(
            data in proptest::collection::vec(any::<u8>(), 0..300),
            size_indicated: bool,
            segmented: bool,
            t in 0usize..9,
        ) {
            let types = [
                DataType::F32,
                DataType::F64,
                DataType::Int { bytes: 3, signed: true },
                DataType::Int { bytes: 5, signed: false },
                DataType::Int { bytes: 7, signed: true },
                DataType::Octets,
                DataType::Unicode,
                DataType::Domain,
                DataType::String { max: 47 },
            ];
            let data_type = types[t];
            let value = Uploaded { data: data.clone(), size_indicated, segmented };
            if let Ok(raw) = decode(&value, data_type) {
                let exact = data_type.is_number() && size_indicated && data.len() == data_type.size();
                if exact || matches!(data_type, DataType::Octets) && !data.is_empty() {
                    prop_assert_eq!(encode(&raw, data_type), Ok(data));
                }
            }
        }

        #[test]
        fn integers_round_trip(v in any::<i32>()) {
            let bytes = encode(&RawValue::Int(v.into()), DataType::I32).unwrap();
            prop_assert_eq!(decode(&expedited(&bytes, true), DataType::I32), Ok(RawValue::Int(v.into())));
        }
    }
}
