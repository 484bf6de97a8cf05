//! The data field: a decimal number as text, at most 12 characters with sign and decimal
//! point. Kept exact as digits and decimal places (`-47.6` is −476 × 10⁻¹), never through a
//! float. Replies of the Unidrive SP always carry a sign; older drives print leading zeros
//! (`-0047.6`) or a space for `+`, and writes may have leading spaces: all are read.
//!
//! Hexadecimal: the notes say older drives also accept `X` followed by hex digits in a
//! write. Such a field is read here in either direction (`decode` of another master's
//! capture, or a drive that answers that way: a reply in hex is not in the notes, reading
//! it is only tolerance). It is a whole number without sign or decimal point; the notes
//! say nothing of negative numbers in hex, so the digits are read as an unsigned value and
//! a sign before `X` is refused. Lower-case hex digits are read too [I]. drivescript itself
//! always writes decimal: every drive takes it, and hex only older ones. Pure.

use super::decode_error::DecodeError;
use crate::dictionary::WireValueError;
use std::fmt;

/// Longest data field, sign and decimal point included.
pub const MAX_DATA_LEN: usize = 12;

/// `digits` × 10^−`places`, exactly.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DataValue {
    pub digits: i64,
    pub places: u8,
}

impl DataValue {
    pub fn new(digits: i64, places: u8) -> DataValue {
        DataValue { digits, places }
    }

    /// Reads a data field that starts at byte `offset` of its message.
    pub fn parse(field: &[u8], offset: usize) -> Result<DataValue, DecodeError> {
        let text = String::from_utf8_lossy(field).into_owned();
        if field.len() > MAX_DATA_LEN {
            return Err(DecodeError::DataTooLong {
                len: field.len(),
                offset,
            });
        }
        let bad = |why| DecodeError::BadData {
            text: text.clone(),
            offset,
            why,
        };
        let body = match field.iter().position(|b| *b != b' ') {
            Some(start) => &field[start..],
            None => return Err(bad("no digits")),
        };
        let start = field.len() - body.len();
        if body.first() == Some(&b'X') {
            return parse_hex(&body[1..], offset + start + 1, bad);
        }
        let (negative, body) = match body.first() {
            Some(b'-') => (true, &body[1..]),
            Some(b'+') => (false, &body[1..]),
            _ => (false, body),
        };
        match body.first() {
            Some(b'X') => {
                return Err(bad(
                    "a sign before X: hexadecimal data is `X` and hex digits only",
                ))
            }
            Some(b'x') => return Err(bad("hexadecimal data starts with an upper-case `X`")),
            _ => {}
        }
        if body.is_empty() {
            return Err(bad("no digits"));
        }
        let point = body.iter().position(|b| *b == b'.');
        if let Some(p) = point {
            if p == 0 || p == body.len() - 1 {
                return Err(bad("the decimal point is never first or last"));
            }
            if body[p + 1..].contains(&b'.') {
                return Err(bad("more than one decimal point"));
            }
        }
        let mut digits: i64 = 0;
        for b in body.iter().filter(|b| **b != b'.') {
            if !b.is_ascii_digit() {
                return Err(bad(
                    "only digits, one sign first and one decimal point are allowed",
                ));
            }
            // At most 11 digits fit in 12 characters, far inside i64.
            digits = digits * 10 + i64::from(b - b'0');
        }
        let places = point.map_or(0, |p| body.len() - p - 1);
        Ok(DataValue {
            digits: if negative { -digits } else { digits },
            places: u8::try_from(places).map_err(|_| bad("too many decimal places"))?,
        })
    }

    /// The field as a write sends it (always decimal, never `X` + hex): `1500.5`, `-34.5` (no `+`: the sign is optional).
    pub fn write_field(self) -> Result<Vec<u8>, WireValueError> {
        self.field(false)
    }

    /// The field as a Unidrive SP reply carries it: always with a sign, `+1500.5`.
    pub fn reply_field(self) -> Result<Vec<u8>, WireValueError> {
        self.field(true)
    }

    fn field(self, plus: bool) -> Result<Vec<u8>, WireValueError> {
        let mut text = self.to_string();
        if plus && self.digits >= 0 {
            text.insert(0, '+');
        }
        if text.len() > MAX_DATA_LEN {
            return Err(WireValueError::Unfit(format!(
                "{self} needs {} characters; the data field holds at most {MAX_DATA_LEN}",
                text.len()
            )));
        }
        Ok(text.into_bytes())
    }

    /// The value scaled to `places` decimal places, when that is exact and fits.
    pub fn with_places(self, places: u8) -> Option<DataValue> {
        if places >= self.places {
            let factor = 10i64.checked_pow(u32::from(places - self.places))?;
            Some(DataValue::new(self.digits.checked_mul(factor)?, places))
        } else {
            let factor = 10i64.checked_pow(u32::from(self.places - places))?;
            (self.digits % factor == 0).then(|| DataValue::new(self.digits / factor, places))
        }
    }
}

/// The hex digits after `X`, the first at byte `offset` of the message: a whole number.
fn parse_hex(
    digits: &[u8],
    offset: usize,
    bad: impl Fn(&'static str) -> DecodeError,
) -> Result<DataValue, DecodeError> {
    if digits.is_empty() {
        return Err(bad("no hex digits after X"));
    }
    let mut value: i64 = 0;
    for (i, &b) in digits.iter().enumerate() {
        let Some(d) = char::from(b).to_digit(16) else {
            return Err(DecodeError::Unexpected {
                offset: offset + i,
                expected: "a hex digit (0-9, A-F) after X",
                actual: b,
            });
        };
        // At most 11 hex digits fit in 12 characters: 44 bits, far inside i64.
        value = value * 16 + i64::from(d);
    }
    Ok(DataValue::new(value, 0))
}

impl fmt::Display for DataValue {
    /// `-47.6`, `1500.5`, `0.05`, `131`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = usize::from(self.places);
        let sign = if self.digits < 0 { "-" } else { "" };
        let abs = self.digits.unsigned_abs().to_string();
        if p == 0 {
            return write!(f, "{sign}{abs}");
        }
        let padded = format!("{abs:0>width$}", width = p + 1);
        let (whole, frac) = padded.split_at(padded.len() - p);
        write!(f, "{sign}{whole}.{frac}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<DataValue, DecodeError> {
        DataValue::parse(s.as_bytes(), 0)
    }

    #[test]
    fn replies_and_writes_of_every_form() {
        assert_eq!(parse("-47.6"), Ok(DataValue::new(-476, 1)));
        assert_eq!(parse("-0047.6"), Ok(DataValue::new(-476, 1)));
        assert_eq!(parse("+076.4"), Ok(DataValue::new(764, 1)));
        assert_eq!(parse(" 76.4"), Ok(DataValue::new(764, 1)), "a space for +");
        assert_eq!(parse("   131"), Ok(DataValue::new(131, 0)));
        assert_eq!(parse("+1500.5"), Ok(DataValue::new(15005, 1)));
        assert_eq!(parse("+0"), Ok(DataValue::new(0, 0)));
        assert_eq!(parse("+99999999999"), Ok(DataValue::new(99_999_999_999, 0)));
        assert_eq!(parse("+0.05").unwrap().to_string(), "0.05");
    }

    #[test]
    fn malformed_fields_say_why() {
        for (text, why) in [
            ("", "no digits"),
            ("-", "no digits"),
            ("+.5", "never first or last"),
            ("5.", "never first or last"),
            ("1.2.3", "more than one"),
            ("1 2", "only digits"),
            ("-X1F", "a sign before X"),
            ("x1F", "upper-case `X`"),
            ("X", "no hex digits"),
            ("+-1", "only digits"),
        ] {
            let e = parse(text).unwrap_err().to_string();
            assert!(e.contains(why), "{text}: {e}");
        }
        assert!(matches!(
            parse("+1234567890.1"),
            Err(DecodeError::DataTooLong { len: 13, .. })
        ));
    }

    #[test]
    fn hexadecimal_fields_are_whole_numbers() {
        assert_eq!(parse("X1F"), Ok(DataValue::new(31, 0)));
        assert_eq!(parse("X00ff"), Ok(DataValue::new(255, 0)));
        assert_eq!(parse("  X83"), Ok(DataValue::new(131, 0)), "leading spaces");
        assert_eq!(parse("XFFFFFFFFFFF"), Ok(DataValue::new(0xFFF_FFFF_FFFF, 0)));
        assert!(matches!(
            parse("X123456789ABC"),
            Err(DecodeError::DataTooLong { len: 13, .. })
        ));
    }

    #[test]
    fn a_bad_hex_digit_is_named_with_its_byte_offset() {
        // The field starts at byte 5 of `STX 0121 X1G ETX`: X at 5, `1` at 6, `G` at 7.
        let e = DataValue::parse(b"X1G", 5).unwrap_err();
        assert_eq!(
            e,
            DecodeError::Unexpected {
                offset: 7,
                expected: "a hex digit (0-9, A-F) after X",
                actual: b'G'
            }
        );
        assert_eq!(
            e.to_string(),
            "byte 7: expected a hex digit (0-9, A-F) after X, got 'G'"
        );
        let e = DataValue::parse(b" X1.5", 5).unwrap_err();
        assert!(
            matches!(
                e,
                DecodeError::Unexpected {
                    offset: 8,
                    actual: b'.',
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn exact_text_for_writes_and_replies() {
        let v = DataValue::new(15005, 1);
        assert_eq!(v.write_field().unwrap(), b"1500.5");
        assert_eq!(v.reply_field().unwrap(), b"+1500.5");
        assert_eq!(DataValue::new(-345, 1).write_field().unwrap(), b"-34.5");
        assert_eq!(DataValue::new(-5, 2).to_string(), "-0.05");
        assert!(DataValue::new(123_456_789_012, 1).write_field().is_err());
        assert_eq!(DataValue::new(15, 0).with_places(1), Some(DataValue::new(150, 1)));
        assert_eq!(DataValue::new(150, 1).with_places(0), Some(DataValue::new(15, 0)));
        assert_eq!(DataValue::new(155, 1).with_places(0), None);
    }
}
