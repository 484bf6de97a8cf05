//! A number with an optional engineering unit, as engineers write it: `6000 rpm`, `6krpm`,
//! `1.5 A`, `250ms`, `42`, `-3000 rpm`, `0x0F`. Parsing and unit conversion only; which
//! unit an object wants is the object definition's business. A whole number that a float
//! cannot hold (beyond 2^53: a 64-bit count) keeps its exact integer beside the float, so
//! that it is written, shown and compared to the unit.

use super::unit::Unit;
use super::value_error::ValueError;
use std::fmt;
use std::str::FromStr;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// The number; for a whole number beyond 2^53 the nearest float (see [`Quantity::integer`]).
    pub value: f64,
    /// `None` for a bare number, which an object reads in its own unit.
    pub unit: Option<Unit>,
    /// The whole number itself, set only where `value` is not exactly it: one form for
    /// each number, so that equal quantities compare equal.
    exact: Option<i128>,
}

impl Quantity {
    pub fn new(value: f64, unit: Option<Unit>) -> Self {
        Quantity {
            value,
            unit,
            exact: None,
        }
    }

    /// The whole number `n`, exactly (a count of a 64-bit object).
    pub fn integer(n: i128, unit: Option<Unit>) -> Self {
        let value = n as f64;
        Quantity {
            value,
            unit,
            exact: exact_beside(value, n),
        }
    }

    /// The whole number this quantity is, exactly: the integer given or read where a
    /// float cannot hold it, else `value` when it is whole; within 64 bits (every count a
    /// drive holds). `None` for fractions, NaN, infinities and larger numbers.
    pub fn whole(&self) -> Option<i128> {
        const BEYOND_64_BITS: f64 = 18_446_744_073_709_551_616.0;
        self.exact.or_else(|| {
            (self.value.fract() == 0.0 && self.value.abs() < BEYOND_64_BITS).then_some(self.value as i128)
        })
    }

    /// A whole number a float cannot tell from its neighbours (beyond 2^53): what shows
    /// it to the unit is its text, not its float.
    pub fn beyond_float(&self) -> bool {
        self.whole().is_some_and(|n| n.unsigned_abs() > 1 << 53)
    }

    /// The same number in `unit` (`None`: bare, read in an object's own unit), its exact
    /// integer kept.
    pub fn in_unit(self, unit: Option<Unit>) -> Quantity {
        Quantity { unit, ..self }
    }

    /// Parses `NUMBER [UNIT]`, with or without a space. Numbers are decimal (`-3000`, `1.5`,
    /// `2e3`) or hex (`0x0F`); units are those of [`Unit`], case folded when unambiguous.
    pub fn parse(text: &str) -> Result<Quantity, ValueError> {
        Self::parse_with(text, Unit::parse)
    }

    /// [`Quantity::parse`] of a value an operator measured by hand: its unit may also be
    /// one of [`Unit::MEASURED`] (`1.2 mm/s`).
    pub fn parse_measured(text: &str) -> Result<Quantity, ValueError> {
        Self::parse_with(text, Unit::parse_measured)
    }

    fn parse_with(text: &str, unit: fn(&str) -> Result<Unit, ValueError>) -> Result<Quantity, ValueError> {
        let t = text.trim();
        if t.is_empty() {
            return Err(ValueError::Empty);
        }
        let (number, rest) = split_number(t);
        if number.is_empty() {
            return Err(not_a_number(t, ""));
        }
        let value = parse_number(number).ok_or_else(|| not_a_number(t, ""))?;
        if !value.is_finite() {
            return Err(not_a_number(t, ": it is too large"));
        }
        let exact = parse_integer(number).and_then(|n| exact_beside(value, n));
        let rest = rest.trim();
        if rest.is_empty() {
            return Ok(Quantity {
                value,
                unit: None,
                exact,
            });
        }
        if rest.starts_with(|c: char| c.is_ascii_digit() || c == '.' || c == ',') {
            return Err(not_a_number(
                t,
                ": write the number without spaces or separators, e.g. `6000 rpm`",
            ));
        }
        Ok(Quantity {
            value,
            unit: Some(unit(rest)?),
            exact,
        })
    }

    /// This quantity's value in `to`; a bare number is taken to be in `to` already.
    /// `None` when the units measure different things.
    pub fn value_in(&self, to: Unit) -> Option<f64> {
        match self.unit {
            None => Some(self.value),
            Some(from) => from.convert(self.value, to),
        }
    }
}

impl FromStr for Quantity {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Quantity::parse(s)
    }
}

impl fmt::Display for Quantity {
    /// `6000 rpm`, `325.3 V`, `42`; a whole number of up to 64 bits in its exact digits
    /// (`9007199254740993`), `1e300` rather than its 301 digits.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let number = match self.whole() {
            Some(n) => n.to_string(),
            None => super::real::Real::of(self.value, false).to_string(),
        };
        match self.unit {
            Some(u) => write!(f, "{number} {u}"),
            None => write!(f, "{number}"),
        }
    }
}

fn not_a_number(text: &str, why: &str) -> ValueError {
    let hint = if why.is_empty() {
        ": write a number with an optional unit, e.g. `6000 rpm`, `1.5 A`, `250 ms`, `0x0F`".to_string()
    } else {
        why.to_string()
    };
    ValueError::NotANumber {
        text: text.to_string(),
        hint,
    }
}

/// Splits `t` into the longest number-looking prefix and the rest.
fn split_number(t: &str) -> (&str, &str) {
    let bytes = t.as_bytes();
    let mut i = 0;
    if matches!(bytes.first(), Some(b'+' | b'-')) {
        i += 1;
    }
    if bytes.get(i) == Some(&b'0') && matches!(bytes.get(i + 1), Some(b'x' | b'X')) {
        let digits = bytes[i + 2..]
            .iter()
            .take_while(|b| b.is_ascii_hexdigit())
            .count();
        return if digits == 0 {
            ("", t)
        } else {
            t.split_at(i + 2 + digits)
        };
    }
    let int = bytes[i..].iter().take_while(|b| b.is_ascii_digit()).count();
    i += int;
    let mut frac = 0;
    if bytes.get(i) == Some(&b'.') {
        frac = bytes[i + 1..].iter().take_while(|b| b.is_ascii_digit()).count();
        if int + frac > 0 {
            i += 1 + frac;
        }
    }
    if int + frac == 0 {
        return ("", t);
    }
    if matches!(bytes.get(i), Some(b'e' | b'E')) {
        let mut j = i + 1;
        if matches!(bytes.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let exp = bytes[j.min(bytes.len())..]
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count();
        if exp > 0 {
            i = j + exp;
        }
    }
    t.split_at(i)
}

/// `n` when `value` is not exactly it: the exact integer a quantity keeps beside its float,
/// for whole numbers within 64 bits (every count a drive holds; beyond, a float will do).
fn exact_beside(value: f64, n: i128) -> Option<i128> {
    (n.unsigned_abs() < 1 << 64 && value as i128 != n).then_some(n)
}

/// The digits of a number without its sign.
enum Digits<'a> {
    /// After `0x`.
    Hex(&'a str),
    Decimal(&'a str),
}

/// Whether `number` is negative, and its digits.
fn digits(number: &str) -> (bool, Digits<'_>) {
    let (negative, unsigned) = match number.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, number.strip_prefix('+').unwrap_or(number)),
    };
    let digits = match unsigned
        .strip_prefix("0x")
        .or_else(|| unsigned.strip_prefix("0X"))
    {
        Some(hex) => Digits::Hex(hex),
        None => Digits::Decimal(unsigned),
    };
    (negative, digits)
}

/// A number written as a whole number, decimal or `0x` hex, exactly; `None` for fractions,
/// exponents and what is beyond 128 bits.
fn parse_integer(number: &str) -> Option<i128> {
    let (negative, digits) = digits(number);
    let magnitude = match digits {
        Digits::Hex(hex) => i128::from_str_radix(hex, 16).ok()?,
        Digits::Decimal(d) if d.bytes().all(|b| b.is_ascii_digit()) => d.parse::<i128>().ok()?,
        Digits::Decimal(_) => return None,
    };
    Some(if negative { -magnitude } else { magnitude })
}

fn parse_number(number: &str) -> Option<f64> {
    let (negative, digits) = digits(number);
    let magnitude = match digits {
        Digits::Hex(hex) => u64::from_str_radix(hex, 16).ok()? as f64,
        Digits::Decimal(d) => d.parse::<f64>().ok()?,
    };
    Some(if negative { -magnitude } else { magnitude })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn q(text: &str) -> Quantity {
        Quantity::parse(text).unwrap()
    }

    #[test]
    fn the_forms_engineers_write() {
        assert_eq!(q("6000 rpm"), Quantity::new(6000.0, Some(Unit::Rpm)));
        assert_eq!(q("6000rpm"), Quantity::new(6000.0, Some(Unit::Rpm)));
        assert_eq!(q("6 krpm"), Quantity::new(6.0, Some(Unit::Krpm)));
        assert_eq!(q("1.5 A"), Quantity::new(1.5, Some(Unit::Ampere)));
        assert_eq!(q("250ms"), Quantity::new(250.0, Some(Unit::Millisecond)));
        assert_eq!(q("42"), Quantity::new(42.0, None));
        assert_eq!(q("-3000 rpm"), Quantity::new(-3000.0, Some(Unit::Rpm)));
        assert_eq!(q("0x0F"), Quantity::new(15.0, None));
        assert_eq!(q("  1 %  "), Quantity::new(1.0, Some(Unit::Percent)));
        assert_eq!(q(".5 V"), Quantity::new(0.5, Some(Unit::Volt)));
        assert_eq!(q("2e3 rpm"), Quantity::new(2000.0, Some(Unit::Rpm)));
        assert_eq!(q("10 min"), Quantity::new(10.0, Some(Unit::Minute)));
        assert_eq!(q("+5"), Quantity::new(5.0, None));
        assert_eq!(q("80 °C"), Quantity::new(80.0, Some(Unit::DegreeCelsius)));
        assert_eq!(q("0.5 K/min"), Quantity::new(0.5, Some(Unit::KelvinPerMinute)));
        assert_eq!(q("8kHz"), Quantity::new(8.0, Some(Unit::Kilohertz)));
        assert_eq!(q("12.5 N·m"), Quantity::new(12.5, Some(Unit::NewtonMetre)));
        assert_eq!(q("2.2 kW"), Quantity::new(2.2, Some(Unit::Kilowatt)));
        assert_eq!(q("4.5 mm/s"), Quantity::new(4.5, Some(Unit::MillimetrePerSecond)));
        assert_eq!(q("6 bar"), Quantity::new(6.0, Some(Unit::Bar)));
        assert_eq!(
            "6 krpm".parse::<Quantity>().ok(),
            Some(Quantity::new(6.0, Some(Unit::Krpm)))
        );
    }

    #[test]
    fn clear_errors() {
        assert_eq!(Quantity::parse("  "), Err(ValueError::Empty));
        let e = Quantity::parse("fast").unwrap_err().to_string();
        assert!(e.starts_with("`fast` is not a number: write a number"), "{e}");
        let e = Quantity::parse("6000 rpn").unwrap_err().to_string();
        assert!(
            e.contains("unknown unit `rpn`") && e.contains("did you mean `rpm`"),
            "{e}"
        );
        let e = Quantity::parse("6 000 rpm").unwrap_err().to_string();
        assert!(e.contains("without spaces"), "{e}");
        let e = Quantity::parse("1e999").unwrap_err().to_string();
        assert!(e.contains("too large"), "{e}");
        assert!(Quantity::parse("0x").is_err());
        assert!(Quantity::parse("-").is_err());
        assert!(Quantity::parse(".").is_err());
        assert!(Quantity::parse("0xFFFFFFFFFFFFFFFFFF").is_err());
    }

    #[test]
    fn conversion_to_an_objects_unit() {
        assert_eq!(q("6 krpm").value_in(Unit::Rpm), Some(6000.0));
        assert_eq!(q("42").value_in(Unit::Ampere), Some(42.0));
        assert_eq!(q("1 A").value_in(Unit::Rpm), None);
        assert_eq!(q("6000 rpm").to_string(), "6000 rpm");
        assert_eq!(q("42").to_string(), "42");
    }

    /// A whole number beyond a float's 53 bits keeps its exact integer: 2^53 + 1 is not
    /// 2^53, and shows as written; within 53 bits and for fractions nothing changes.
    #[test]
    fn whole_numbers_beyond_a_float_are_kept_exactly() {
        let above = q("9007199254740993");
        assert_eq!(above.whole(), Some((1 << 53) + 1));
        assert_ne!(above, q("9007199254740992"), "a float cannot tell them apart");
        assert_eq!(above.to_string(), "9007199254740993");
        assert!(above.beyond_float() && !q("9007199254740992").beyond_float());
        assert_eq!(q("-9223372036854775808").whole(), Some(i64::MIN.into()));
        assert_eq!(q("0x7FFFFFFFFFFFFFFF").whole(), Some(i64::MAX.into()));
        assert_eq!(q("0xFFFFFFFFFFFFFFFF").whole(), Some(u64::MAX.into()));
        assert_eq!(q("72057594037927935 rpm").to_string(), "72057594037927935 rpm");
        assert_eq!(q("42"), Quantity::new(42.0, None), "one form for each number");
        assert_eq!(q("2e3").whole(), Some(2000));
        assert_eq!(q("1.5").whole(), None);
        assert_eq!(
            q("-0").value.to_bits(),
            (-0.0f64).to_bits(),
            "the float as before"
        );
        assert_eq!(q("1e300").whole(), None);
        assert_eq!(q("1e300").to_string(), "1e300");
        assert_eq!(
            Quantity::integer(i64::MAX.into(), None).to_string(),
            "9223372036854775807"
        );
        assert_eq!(Quantity::integer(6000, None), Quantity::new(6000.0, None));
        assert_eq!(q("6000 rpm").in_unit(None), q("6000"));
        assert_eq!(
            q("9007199254740993").in_unit(Some(Unit::Rpm)).to_string(),
            "9007199254740993 rpm"
        );
    }

    proptest! {
        /// Every 64-bit whole number, as decimal or hex text, is read to the unit.
        #[test]
        fn every_64_bit_whole_number_parses_exactly(n in any::<i64>(), u in any::<u64>()) {
            prop_assert_eq!(q(&n.to_string()).whole(), Some(i128::from(n)));
            prop_assert_eq!(q(&n.to_string()).to_string(), n.to_string());
            prop_assert_eq!(q(&format!("0x{u:X}")).whole(), Some(i128::from(u)));
            prop_assert_eq!(Quantity::integer(n.into(), None), q(&n.to_string()));
        }

        #[test]
        fn parse_never_panics(text in "\\PC{0,24}") {
            let _ = Quantity::parse(&text);
        }

        #[test]
        fn parse_never_panics_on_number_like_text(text in "[-+0-9xXeE. a-zA-Z%]{0,16}") {
            let _ = Quantity::parse(&text);
        }

        #[test]
        fn decimal_numbers_with_units_parse(v in -1.0e6f64..1.0e6, unit in 0usize..Unit::ALL.len()) {
            let u = Unit::ALL[unit];
            let parsed = Quantity::parse(&format!("{v} {}", u.symbol())).unwrap();
            prop_assert_eq!(parsed, Quantity::new(v, Some(u)));
        }
    }
}
