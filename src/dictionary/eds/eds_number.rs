//! Integer values of an EDS/DCF entry (CiA 306): decimal, `0x` hexadecimal, octal with a
//! leading `0`, and `$NODEID` expressions such as `$NODEID+0x180` or `0x600+$NODEID`,
//! whose value depends on the node the file is used for. Pure: text in, value or an
//! [`EdsNumberError`] saying what was expected out.

/// A number from an EDS, possibly relative to the node id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct EdsNumber {
    /// The constant part.
    pub value: i128,
    /// True for a `$NODEID` expression: the node id is added to `value`.
    pub plus_node_id: bool,
}

impl EdsNumber {
    /// The value for node `node`; a `$NODEID` expression without a node is `None`.
    pub fn resolve(self, node: Option<u8>) -> Option<i128> {
        match (self.plus_node_id, node) {
            (false, _) => Some(self.value),
            (true, Some(n)) => Some(self.value + i128::from(n)),
            (true, None) => None,
        }
    }

    /// Reads `text`. The error says what was expected.
    pub fn parse(text: &str) -> Result<EdsNumber, EdsNumberError> {
        let t: String = text.chars().filter(|c| !c.is_whitespace()).collect();
        if t.is_empty() {
            return Err(EdsNumberError::Empty);
        }
        let upper = t.to_ascii_uppercase();
        if let Some(at) = upper.find("$NODEID") {
            let before = &t[..at];
            let after = &t[at + "$NODEID".len()..];
            let constant = match (before, after) {
                ("", "") => 0,
                ("", rest) => match rest.strip_prefix('+') {
                    Some(n) => integer(n)?,
                    None => match rest.strip_prefix('-') {
                        Some(n) => -integer(n)?,
                        None => return Err(expression_help(text)),
                    },
                },
                (first, "") => match first.strip_suffix('+') {
                    Some(n) => integer(n)?,
                    None => return Err(expression_help(text)),
                },
                _ => return Err(expression_help(text)),
            };
            return Ok(EdsNumber {
                value: constant,
                plus_node_id: true,
            });
        }
        Ok(EdsNumber {
            value: integer(&t)?,
            plus_node_id: false,
        })
    }
}

/// A `LowLimit` or `HighLimit`: a number as above, or for a REAL32/REAL64 object a float
/// (`1.5`, `-3.4E+38`; CiA 306 writes them in decimal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum EdsLimit {
    Number(EdsNumber),
    Real(f64),
}

impl EdsLimit {
    /// Reads `text`, as a float first when `real`. The error says what was expected.
    pub fn parse(text: &str, real: bool) -> Result<EdsLimit, EdsNumberError> {
        if real {
            let t = text.trim();
            if let Ok(v) = t.parse::<f64>() {
                return Ok(EdsLimit::Real(v));
            }
            return EdsNumber::parse(t)
                .map(EdsLimit::Number)
                .map_err(|_| EdsNumberError::NotReal { text: t.to_string() });
        }
        EdsNumber::parse(text).map(EdsLimit::Number)
    }

    /// For a signed integer object of `bits`: a limit written in hex (`0x80000000`,
    /// `0xFFFFFFFFFFFFFFF6`) as the two's complement number it is at that width, as the
    /// device reads its own bytes. Decimal text and `$NODEID` expressions stay as written.
    pub fn signed_at(self, text: &str, bits: u32) -> EdsLimit {
        let hex = {
            let t = text.trim();
            t.starts_with("0x") || t.starts_with("0X")
        };
        match self {
            EdsLimit::Number(mut n) if hex && !n.plus_node_id && (1..=64).contains(&bits) => {
                let width = 1i128 << bits;
                if n.value >= width / 2 && n.value < width {
                    n.value -= width;
                }
                EdsLimit::Number(n)
            }
            other => other,
        }
    }

    /// The value for node `node`; a `$NODEID` expression without a node is `None`.
    pub fn resolve(self, node: Option<u8>) -> Option<f64> {
        match self {
            EdsLimit::Number(n) => n.resolve(node).map(|v| v as f64),
            EdsLimit::Real(v) => Some(v),
        }
    }
}

/// Why an EDS entry's text is not the number it should be: the text, and what an EDS
/// writes there instead.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(crate) enum EdsNumberError {
    #[error("expected a number, found nothing")]
    Empty,
    #[error("`{text}` is not a $NODEID expression; expected `$NODEID`, `$NODEID+0x180` or `0x180+$NODEID`")]
    NotExpression { text: String },
    #[error("`{text}` is not a hexadecimal number")]
    NotHexadecimal { text: String },
    #[error("`{text}` starts with 0, which makes it octal in an EDS, but it has digits beyond 7")]
    NotOctal { text: String },
    #[error("`{text}` is not a number (decimal, 0x hexadecimal or 0 octal)")]
    NotNumber { text: String },
    #[error("`{text}` is beyond any 64-bit number an object can hold")]
    Beyond64Bits { text: String },
    #[error("`{text}` is not a number; a REAL object's limit is a decimal such as 1.5 or -3.4E+38")]
    NotReal { text: String },
}

fn expression_help(text: &str) -> EdsNumberError {
    EdsNumberError::NotExpression {
        text: text.to_string(),
    }
}

/// A signed integer: `-5`, `0x1A`, `017` (octal: CiA 306's leading zero).
fn integer(text: &str) -> Result<i128, EdsNumberError> {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let plain = |d: &str, radix: u32| !d.is_empty() && d.chars().all(|c| c.is_digit(radix));
    let parsed = if let Some(hex) = digits.strip_prefix("0x").or_else(|| digits.strip_prefix("0X")) {
        plain(hex, 16)
            .then(|| i128::from_str_radix(hex, 16).ok())
            .flatten()
            .ok_or_else(|| EdsNumberError::NotHexadecimal {
                text: text.to_string(),
            })
    } else if digits.len() > 1 && digits.starts_with('0') {
        plain(&digits[1..], 8)
            .then(|| i128::from_str_radix(&digits[1..], 8).ok())
            .flatten()
            .ok_or_else(|| EdsNumberError::NotOctal {
                text: text.to_string(),
            })
    } else {
        plain(digits, 10)
            .then(|| digits.parse::<i128>().ok())
            .flatten()
            .ok_or_else(|| EdsNumberError::NotNumber {
                text: text.to_string(),
            })
    };
    let value = if negative { -parsed? } else { parsed? };
    // No CiA 301 type is wider than 64 bits; bounding here also keeps `$NODEID+…` sums
    // from overflowing.
    if value > i128::from(u64::MAX) || value < i128::from(i64::MIN) {
        return Err(EdsNumberError::Beyond64Bits {
            text: text.to_string(),
        });
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n(text: &str) -> Result<(i128, bool), EdsNumberError> {
        EdsNumber::parse(text).map(|n| (n.value, n.plus_node_id))
    }

    /// Each text reads as its value, with `$NODEID` to add or not.
    fn reads_all(cases: &[(&str, i128, bool)]) {
        for &(text, value, plus_node_id) in cases {
            assert_eq!(n(text), Ok((value, plus_node_id)), "{text}");
        }
    }

    #[test]
    fn decimal_hex_octal_and_signs() {
        reads_all(&[
            ("1000", 1000, false),
            ("0x6041", 0x6041, false),
            ("0X7f", 127, false),
            ("017", 15, false),
            ("0", 0, false),
            ("-32768", -32768, false),
            ("0xFFFFFFFFFFFFFFFF", u64::MAX.into(), false),
        ]);
        assert!(n("09").unwrap_err().to_string().contains("octal"));
        assert!(n("0xZZ").unwrap_err().to_string().contains("hexadecimal"));
        assert!(n("").is_err());
        assert!(n("12abc").is_err());
    }

    #[test]
    fn limits_of_real_objects_are_floats() {
        let l = |t: &str, real| EdsLimit::parse(t, real).map(|l| l.resolve(Some(2)));
        assert_eq!(l("1.5", true), Ok(Some(1.5)));
        assert_eq!(l("-3.4E+38", true), Ok(Some(-3.4e38)));
        assert_eq!(l("0x10", true), Ok(Some(16.0)));
        assert_eq!(l("$NODEID+1", true), Ok(Some(3.0)));
        assert!(l("1,5", true).unwrap_err().to_string().contains("-3.4E+38"));
        assert!(
            l("1.5", false).is_err(),
            "an integer object's limit is an integer"
        );
        assert_eq!(l("$NODEID+1", false), Ok(Some(3.0)));
    }

    #[test]
    fn hex_limits_of_signed_types_are_twos_complement_at_their_width() {
        let l = |t: &str, bits| {
            EdsLimit::parse(t, false)
                .unwrap()
                .signed_at(t, bits)
                .resolve(None)
        };
        assert_eq!(l("0x80000000", 32), Some(-2_147_483_648.0));
        assert_eq!(l("0x7FFFFFFF", 32), Some(2_147_483_647.0));
        assert_eq!(l("0xFFFFFFFFFFFFFFF6", 64), Some(-10.0));
        assert_eq!(l("0xFF", 8), Some(-1.0));
        assert_eq!(l("0x8000", 16), Some(-32768.0));
        assert_eq!(l("0xEC78", 16), Some(-5000.0));
        // Decimal text is what it says; beyond the width it is left for the range check.
        assert_eq!(l("40000", 16), Some(40000.0));
        assert_eq!(l("0x10000", 16), Some(65536.0));
        assert_eq!(l("-5000", 16), Some(-5000.0));
    }

    #[test]
    fn node_id_expressions() {
        reads_all(&[
            ("$NODEID+0x180", 0x180, true),
            ("$NodeId + 0x600", 0x600, true),
            ("0x580+$NODEID", 0x580, true),
            ("$NODEID", 0, true),
            ("$NODEID-1", -1, true),
        ]);
        assert!(n("$NODEID*2").unwrap_err().to_string().contains("$NODEID+0x180"));
        assert!(n("1-$NODEID").is_err());
        // Beyond any 64-bit value: refused, never a sum that overflows.
        let huge = "$NODEID+0x7FFFFFFFFFFFFFFFFFFFFFFFFFFFFFFF";
        assert!(
            n(huge).is_err_and(|e| e.to_string().contains("beyond any 64-bit")),
            "{:?}",
            n(huge)
        );
        assert!(n("-170141183460469231731687303715884105727").is_err());
        assert!(n("0x10000000000000000").is_err());
        assert_eq!(n("-9223372036854775808"), Ok((i64::MIN.into(), false)));
        let cob = EdsNumber::parse("$NODEID+0x80").unwrap();
        assert_eq!(cob.resolve(Some(5)), Some(0x85));
        assert_eq!(cob.resolve(None), None);
        assert_eq!(EdsNumber::parse("7").unwrap().resolve(None), Some(7));
    }
}
