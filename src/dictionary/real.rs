//! An IEEE 754 float as a drive holds it (CANopen REAL32 and REAL64), kept as its bits so
//! that a value read is written back byte for byte, NaN and infinities included, and so
//! that two values compare equal exactly when their bits do. Its text is the shortest
//! decimal that reads back to the same bits (`1.5`, `-3.4e38`, `NaN`, `-inf`): backups
//! store it, diffs compare it. Pure.

use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Real {
    /// REAL32: single precision.
    Single(u32),
    /// REAL64: double precision.
    Double(u64),
}

impl Real {
    /// `value` in this precision: rounded to the nearest single for [`Real::Single`].
    pub fn of(value: f64, single: bool) -> Real {
        if single {
            Real::Single((value as f32).to_bits())
        } else {
            Real::Double(value.to_bits())
        }
    }

    /// The value as a double (a single widens exactly).
    pub fn value(self) -> f64 {
        match self {
            Real::Single(bits) => f64::from(f32::from_bits(bits)),
            Real::Double(bits) => f64::from_bits(bits),
        }
    }

    pub fn is_single(self) -> bool {
        matches!(self, Real::Single(_))
    }

    /// The little-endian IEEE bytes, as CiA 301 sends them.
    pub fn to_le_bytes(self) -> Vec<u8> {
        match self {
            Real::Single(bits) => bits.to_le_bytes().to_vec(),
            Real::Double(bits) => bits.to_le_bytes().to_vec(),
        }
    }

    /// From 4 (single) or 8 (double) little-endian bytes; `None` for another count.
    pub fn from_le_bytes(bytes: &[u8], single: bool) -> Option<Real> {
        if single {
            Some(Real::Single(u32::from_le_bytes(bytes.try_into().ok()?)))
        } else {
            Some(Real::Double(u64::from_le_bytes(bytes.try_into().ok()?)))
        }
    }

    /// Reads decimal text (`1.5`, `-3.4E+38`, `1e-3`, `NaN`, `inf`) in this precision;
    /// `None` for anything else. A single is rounded once, from the text.
    pub fn parse(text: &str, single: bool) -> Option<Real> {
        let t = text.trim();
        // Rust reads `inf`, `NaN` and `infinity` in any case; a bare sign or `+` alone is not a number.
        if single {
            t.parse::<f32>().ok().map(|v| Real::Single(v.to_bits()))
        } else {
            t.parse::<f64>().ok().map(|v| Real::Double(v.to_bits()))
        }
    }
}

impl fmt::Display for Real {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.value();
        if v.is_nan() {
            return f.write_str("NaN");
        }
        if v.is_infinite() {
            return f.write_str(if v < 0.0 { "-inf" } else { "inf" });
        }
        // Plain digits for everyday magnitudes, exponent notation for the rest (3.4e38
        // instead of 39 digits); both are the shortest text that reads back exactly.
        let plain = v == 0.0 || (1e-5..1e16).contains(&v.abs());
        match (self, plain) {
            (Real::Single(bits), true) => write!(f, "{}", f32::from_bits(*bits)),
            (Real::Single(bits), false) => write!(f, "{:e}", f32::from_bits(*bits)),
            (Real::Double(_), true) => write!(f, "{v}"),
            (Real::Double(_), false) => write!(f, "{v:e}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn text_is_the_shortest_that_reads_back() {
        let s = |t: &str| Real::parse(t, true).unwrap().to_string();
        assert_eq!(s("1.5"), "1.5");
        assert_eq!(s("1.1"), "1.1", "not the double 1.100000023841858");
        assert_eq!(s("-3.4E+38"), "-3.4e38");
        assert_eq!(s("0.000001"), "1e-6");
        assert_eq!(s("-0"), "-0");
        assert_eq!(s("NaN"), "NaN");
        assert_eq!(s("-inf"), "-inf");
        assert_eq!(Real::parse("1e400", false).unwrap().to_string(), "inf");
        assert_eq!(Real::parse("0.1", false).unwrap().to_string(), "0.1");
        assert_eq!(Real::parse("abc", true), None);
        assert_eq!(Real::parse("", true), None);
        assert_eq!(Real::of(1.5, true).to_le_bytes(), [0x00, 0x00, 0xc0, 0x3f]);
        assert_eq!(
            Real::from_le_bytes(&[0, 0, 0xc0, 0x3f], true),
            Some(Real::Single(0x3fc0_0000))
        );
        assert_eq!(Real::from_le_bytes(&[0, 0, 0xc0], true), None);
    }

    /// `r` survives its bytes and its text; a single also its text read as a double and
    /// narrowed, the way a quantity is written.
    fn round_trips_through_text_and_bytes(r: Real, single: bool) -> Result<(), TestCaseError> {
        prop_assert_eq!(Real::from_le_bytes(&r.to_le_bytes(), single), Some(r));
        let back = Real::parse(&r.to_string(), single).unwrap();
        if r.value().is_nan() {
            prop_assert!(back.value().is_nan());
        } else {
            prop_assert_eq!(back, r);
            if single {
                prop_assert_eq!(Real::of(r.to_string().parse::<f64>().unwrap(), true), r);
            }
        }
        Ok(())
    }

    proptest! {
        /// Every single and double, NaNs with their payload aside, survives text and bytes.
        #[test]
        fn singles_round_trip_through_text_and_bytes(bits in any::<u32>()) {
            round_trips_through_text_and_bytes(Real::Single(bits), true)?;
        }

        #[test]
        fn doubles_round_trip_through_text_and_bytes(bits in any::<u64>()) {
            round_trips_through_text_and_bytes(Real::Double(bits), false)?;
        }

        #[test]
        fn any_text_parses_or_not_without_panic(text in ".{0,20}") {
            let _ = Real::parse(&text, true);
            let _ = Real::parse(&text, false);
        }
    }
}
