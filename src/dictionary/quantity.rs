//! A number with an optional engineering unit, as engineers write it: `6000 rpm`, `6krpm`,
//! `1.5 A`, `250ms`, `42`, `-3000 rpm`, `0x0F`. Parsing and unit conversion only; which
//! unit an object wants is the object definition's business.

use super::unit::Unit;
use super::value_error::ValueError;
use std::fmt;
use std::str::FromStr;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    pub value: f64,
    /// `None` for a bare number, which an object reads in its own unit.
    pub unit: Option<Unit>,
}

impl Quantity {
    pub fn new(value: f64, unit: Option<Unit>) -> Self {
        Quantity { value, unit }
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
        let rest = rest.trim();
        if rest.is_empty() {
            return Ok(Quantity { value, unit: None });
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
    /// `6000 rpm`, `325.3 V`, `42`; `1e300` rather than its 301 digits.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let number = super::real::Real::of(self.value, false);
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

fn parse_number(number: &str) -> Option<f64> {
    let (negative, unsigned) = match number.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, number.strip_prefix('+').unwrap_or(number)),
    };
    let magnitude = match unsigned
        .strip_prefix("0x")
        .or_else(|| unsigned.strip_prefix("0X"))
    {
        Some(hex) => u64::from_str_radix(hex, 16).ok()? as f64,
        None => unsigned.parse::<f64>().ok()?,
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

    proptest! {
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
