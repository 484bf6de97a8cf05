//! An object's value as read from a drive: the raw count or text, and its engineering
//! reading with unit. Display is what a commissioning engineer expects to see:
//! `6000 rpm`, `325.3 V`, `0x0237`, `"Test Motor"`. Presentation only; decoding bytes is
//! the object definition's job.

use super::format::Format;
use super::quantity::Quantity;
use super::real::Real;
use super::unit::Unit;
use std::fmt;

/// A value as the drive holds it, in the form its family exchanges: a count, an exact
/// decimal (drives that send `+1500.5` as text), an IEEE float, text, or bytes.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum RawValue {
    Int(i64),
    /// `digits` × 10^−`places`, exactly: 1500.5 is { digits: 15005, places: 1 }.
    Decimal {
        digits: i64,
        places: u8,
    },
    /// A float as its bits (CANopen REAL32, REAL64).
    Real(Real),
    Text(String),
    Bytes(Vec<u8>),
}

impl RawValue {
    pub fn as_int(&self) -> Option<i64> {
        match self {
            RawValue::Int(i) => Some(*i),
            // A whole decimal (a status word read as text) is an integer too.
            RawValue::Decimal { digits, places: 0 } => Some(*digits),
            _ => None,
        }
    }
}

impl fmt::Display for RawValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RawValue::Int(i) => write!(f, "{i}"),
            RawValue::Decimal { digits, places } => {
                let p = usize::from(*places);
                let sign = if *digits < 0 { "-" } else { "" };
                let abs = digits.unsigned_abs().to_string();
                if p == 0 {
                    write!(f, "{sign}{abs}")
                } else {
                    let padded = format!("{abs:0>width$}", width = p + 1);
                    let (whole, frac) = padded.split_at(padded.len() - p);
                    write!(f, "{sign}{whole}.{frac}")
                }
            }
            RawValue::Real(r) => write!(f, "{r}"),
            RawValue::Text(t) => write!(f, "{t:?}"),
            RawValue::Bytes(b) => write!(f, "{}", crate::hex::to_hex(b)),
        }
    }
}

/// A decoded value: raw, and for integers the engineering quantity (raw × scale, in the
/// object's unit, or the count itself when the object has no unit).
#[derive(Debug, Clone, PartialEq)]
pub struct Value {
    pub raw: RawValue,
    /// `None` for text.
    pub quantity: Option<Quantity>,
    /// How the value prints: decimal, or hex `0x0237` with `width` bytes of digits.
    pub format: Format,
    /// Bytes of the type, for the hex width.
    pub width: usize,
    /// Decimal places the object's scale resolves (0.001 → 3), used when printing.
    pub decimals: usize,
}

impl Value {
    /// The engineering value (raw × scale); `None` for text.
    pub fn number(&self) -> Option<f64> {
        self.quantity.map(|q| q.value)
    }

    pub fn unit(&self) -> Option<Unit> {
        self.quantity.and_then(|q| q.unit)
    }

    pub fn text(&self) -> Option<&str> {
        match &self.raw {
            RawValue::Text(t) => Some(t),
            _ => None,
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.raw, self.quantity) {
            (RawValue::Text(t), _) => write!(f, "{t:?}"),
            (RawValue::Int(i) | RawValue::Decimal { digits: i, places: 0 }, _)
                if self.format == Format::Hex && self.unit().is_none() =>
            {
                let digits = self.width.max(1) * 2;
                // Negative counts of signed types print as their two's complement.
                let bits = (self.width.clamp(1, 8) * 8) as u32;
                let mask = if bits >= 64 { u64::MAX } else { (1u64 << bits) - 1 };
                write!(f, "0x{:0digits$x}", (*i as u64) & mask)
            }
            (RawValue::Int(i), None) => write!(f, "{i}"),
            (RawValue::Bytes(_) | RawValue::Decimal { .. } | RawValue::Real(_), None) => {
                write!(f, "{}", self.raw)
            }
            // In the float's own precision, shortest: 1.1 not 1.100000023841858; NaN as NaN.
            (RawValue::Real(r), Some(q)) => {
                write!(f, "{}", Real::of(q.value, r.is_single()))?;
                match q.unit {
                    Some(u) => write!(f, " {u}"),
                    None => Ok(()),
                }
            }
            // Exactly as the drive sent it: its trailing zeros are significant (version 1.10).
            (RawValue::Decimal { .. }, Some(q)) => match q.unit {
                Some(u) => write!(f, "{} {u}", self.raw),
                None => write!(f, "{}", self.raw),
            },
            (RawValue::Int(_) | RawValue::Bytes(_), Some(q)) => {
                // Whole numbers in their exact digits: a 64-bit count beyond a float's precision.
                let number = match (self.decimals, q.whole()) {
                    (0, Some(n)) => n.to_string(),
                    _ => format_number(q.value, self.decimals),
                };
                f.write_str(&number)?;
                match q.unit {
                    Some(u) => write!(f, " {u}"),
                    None => Ok(()),
                }
            }
        }
    }
}

/// `value` with at most `decimals` places, trailing zeros dropped: 6000, 325.3, 1003.647.
pub(crate) fn format_number(value: f64, decimals: usize) -> String {
    let mut text = format!("{value:.decimals$}");
    if text.contains('.') {
        let kept = text.trim_end_matches('0').trim_end_matches('.').len();
        text.truncate(kept);
    }
    if text == "-0" {
        text.remove(0);
    }
    text
}

/// Decimal places needed to show every multiple of `scale` exactly (0.001 → 3, 0.5 → 1);
/// at most 9.
pub(crate) fn decimals_of(scale: f64) -> usize {
    (0..=9)
        .find(|&d| {
            let shifted = scale * 10f64.powi(d as i32);
            (shifted - shifted.round()).abs() < 1e-9 * shifted.abs().max(1.0)
        })
        .unwrap_or(9)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn int(raw: i64, value: f64, unit: Option<Unit>, format: Format, width: usize, decimals: usize) -> Value {
        Value {
            raw: RawValue::Int(raw),
            quantity: Some(Quantity::new(value, unit)),
            format,
            width,
            decimals,
        }
    }

    #[test]
    fn display_as_engineers_read_it() {
        assert_eq!(
            int(6_000_000, 6000.0, Some(Unit::Rpm), Format::Decimal, 4, 3).to_string(),
            "6000 rpm"
        );
        assert_eq!(
            int(1_003_647, 1003.647, Some(Unit::Rpm), Format::Decimal, 4, 3).to_string(),
            "1003.647 rpm"
        );
        assert_eq!(
            int(3253, 325.3, Some(Unit::Volt), Format::Decimal, 2, 1).to_string(),
            "325.3 V"
        );
        assert_eq!(int(0x237, 567.0, None, Format::Hex, 2, 0).to_string(), "0x0237");
        assert_eq!(int(-1, -1.0, None, Format::Hex, 2, 0).to_string(), "0xffff");
        assert_eq!(int(3, 3.0, None, Format::Decimal, 2, 0).to_string(), "3");
        let text = Value {
            raw: RawValue::Text("Test Motor".into()),
            quantity: None,
            format: Format::Decimal,
            width: 33,
            decimals: 0,
        };
        assert_eq!(text.to_string(), "\"Test Motor\"");
        assert_eq!(text.text(), Some("Test Motor"));
        assert_eq!(text.number(), None);
    }

    #[test]
    fn exact_decimals_print_as_written() {
        let d = |digits, places| RawValue::Decimal { digits, places }.to_string();
        assert_eq!(d(15005, 1), "1500.5");
        assert_eq!(d(-5, 2), "-0.05");
        assert_eq!(d(42, 0), "42");
        let status = Value {
            raw: RawValue::Decimal { digits: 3, places: 0 },
            quantity: Some(Quantity::new(3.0, None)),
            format: Format::Hex,
            width: 2,
            decimals: 0,
        };
        assert_eq!(
            status.to_string(),
            "0x0003",
            "a whole decimal shows in hex like an integer"
        );
    }

    #[test]
    fn number_formatting() {
        assert_eq!(format_number(-0.0001, 3), "0");
        assert_eq!(format_number(60000.0, 3), "60000");
        assert_eq!(format_number(0.5, 1), "0.5");
        assert_eq!(decimals_of(0.001), 3);
        assert_eq!(decimals_of(0.1), 1);
        assert_eq!(decimals_of(1.0), 0);
        assert_eq!(decimals_of(0.25), 2);
        assert_eq!(decimals_of(1.0 / 3.0), 9);
    }
}
