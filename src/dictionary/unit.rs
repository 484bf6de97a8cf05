//! Engineering units: what commissioning engineers type (`rpm`, `%`, `V`, `A`, `s`, …),
//! each with its dimension and its factor to that dimension's base unit. Pure arithmetic;
//! it knows nothing of objects or raw counts.

use super::value_error::ValueError;
use crate::diag::did_you_mean;
use std::fmt;

/// What a unit measures. Conversion is possible only within one dimension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Dimension {
    /// Base: rpm.
    Speed,
    /// Base: %.
    Ratio,
    /// Base: V.
    Voltage,
    /// Base: A.
    Current,
    /// Base: s.
    Time,
    /// Base: mm/s (a vibration velocity, as hand-held meters show it).
    Velocity,
    /// Base: mm.
    Length,
    /// Base: °C.
    Temperature,
}

impl Dimension {
    /// The unit every other unit of this dimension converts through.
    pub fn base(self) -> Unit {
        match self {
            Dimension::Speed => Unit::Rpm,
            Dimension::Ratio => Unit::Percent,
            Dimension::Voltage => Unit::Volt,
            Dimension::Current => Unit::Ampere,
            Dimension::Time => Unit::Second,
            Dimension::Velocity => Unit::MillimetrePerSecond,
            Dimension::Length => Unit::Millimetre,
            Dimension::Temperature => Unit::Celsius,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Dimension::Speed => "speed",
            Dimension::Ratio => "ratio",
            Dimension::Voltage => "voltage",
            Dimension::Current => "current",
            Dimension::Time => "time",
            Dimension::Velocity => "velocity",
            Dimension::Length => "length",
            Dimension::Temperature => "temperature",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Unit {
    Rpm,
    Krpm,
    Percent,
    Volt,
    Millivolt,
    Ampere,
    Milliampere,
    Second,
    Millisecond,
    Minute,
    Hour,
    MillimetrePerSecond,
    Millimetre,
    Micrometre,
    Celsius,
}

impl Unit {
    /// The units of drive objects (dictionaries, recipes' values for objects).
    pub const ALL: [Unit; 11] = [
        Unit::Rpm,
        Unit::Krpm,
        Unit::Percent,
        Unit::Volt,
        Unit::Millivolt,
        Unit::Ampere,
        Unit::Milliampere,
        Unit::Second,
        Unit::Millisecond,
        Unit::Minute,
        Unit::Hour,
    ];

    /// Units of what an operator measures by hand (a vibration meter, a dial gauge, a
    /// thermometer) and types in at a prompt; no drive object has them.
    pub const MEASURED: [Unit; 4] = [
        Unit::MillimetrePerSecond,
        Unit::Millimetre,
        Unit::Micrometre,
        Unit::Celsius,
    ];

    /// The symbol written in recipes and dictionaries.
    pub fn symbol(self) -> &'static str {
        match self {
            Unit::Rpm => "rpm",
            Unit::Krpm => "krpm",
            Unit::Percent => "%",
            Unit::Volt => "V",
            Unit::Millivolt => "mV",
            Unit::Ampere => "A",
            Unit::Milliampere => "mA",
            Unit::Second => "s",
            Unit::Millisecond => "ms",
            Unit::Minute => "min",
            Unit::Hour => "h",
            Unit::MillimetrePerSecond => "mm/s",
            Unit::Millimetre => "mm",
            Unit::Micrometre => "µm",
            Unit::Celsius => "°C",
        }
    }

    pub fn dimension(self) -> Dimension {
        match self {
            Unit::Rpm | Unit::Krpm => Dimension::Speed,
            Unit::Percent => Dimension::Ratio,
            Unit::Volt | Unit::Millivolt => Dimension::Voltage,
            Unit::Ampere | Unit::Milliampere => Dimension::Current,
            Unit::Second | Unit::Millisecond | Unit::Minute | Unit::Hour => Dimension::Time,
            Unit::MillimetrePerSecond => Dimension::Velocity,
            Unit::Millimetre | Unit::Micrometre => Dimension::Length,
            Unit::Celsius => Dimension::Temperature,
        }
    }

    /// How many base units (rpm, %, V, A, s, mm/s, mm, °C) one of this unit is.
    pub fn factor(self) -> f64 {
        match self {
            Unit::Rpm
            | Unit::Percent
            | Unit::Volt
            | Unit::Ampere
            | Unit::Second
            | Unit::MillimetrePerSecond
            | Unit::Millimetre
            | Unit::Celsius => 1.0,
            Unit::Krpm => 1000.0,
            Unit::Millivolt | Unit::Milliampere | Unit::Millisecond | Unit::Micrometre => 0.001,
            Unit::Minute => 60.0,
            Unit::Hour => 3600.0,
        }
    }

    /// The unit with exactly this symbol (as dictionaries must write it).
    pub fn from_symbol(symbol: &str) -> Option<Unit> {
        Self::ALL.into_iter().find(|u| u.symbol() == symbol)
    }

    /// A unit as people type it: the exact symbol, or a spelling that differs only in case
    /// when that is unambiguous (`RPM`, `v`, `MS`). The error lists close symbols.
    pub fn parse(text: &str) -> Result<Unit, ValueError> {
        let t = text.trim();
        if let Some(u) = Self::from_symbol(t) {
            return Ok(u);
        }
        let mut folded = Self::ALL
            .into_iter()
            .filter(|u| u.symbol().eq_ignore_ascii_case(t));
        if let (Some(u), None) = (folded.next(), folded.next()) {
            return Ok(u);
        }
        Err(ValueError::UnknownUnit {
            unit: t.to_string(),
            suggestions: did_you_mean(t, Self::symbols()),
        })
    }

    /// A unit of a value an operator types in: a drive unit or a [`Unit::MEASURED`] one,
    /// also as a keyboard without µ or ° writes it (`um`, `degC`). The error lists both.
    pub fn parse_measured(text: &str) -> Result<Unit, ValueError> {
        let t = text.trim();
        let measured = match t {
            "um" => Some(Unit::Micrometre),
            "degC" | "C" => Some(Unit::Celsius),
            _ => Self::MEASURED
                .into_iter()
                .find(|u| u.symbol().eq_ignore_ascii_case(t)),
        };
        match (measured, Self::parse(t)) {
            (Some(u), _) | (None, Ok(u)) => Ok(u),
            (None, Err(_)) => {
                let all = Self::symbols().chain(Self::MEASURED.into_iter().map(Unit::symbol));
                Err(ValueError::UnknownMeasuredUnit {
                    unit: t.to_string(),
                    suggestions: did_you_mean(t, all),
                })
            }
        }
    }

    pub fn symbols() -> impl Iterator<Item = &'static str> {
        Self::ALL.into_iter().map(Unit::symbol)
    }

    /// `value` in this unit expressed in `to`; `None` across dimensions.
    pub fn convert(self, value: f64, to: Unit) -> Option<f64> {
        if self.dimension() != to.dimension() {
            return None;
        }
        if self == to {
            return Some(value);
        }
        // Divide by an exact integer ratio where there is one, so 6 krpm is exactly 6000 rpm
        // and 250 ms exactly 0.25 s.
        let ratio = self.factor() / to.factor();
        let inverse = to.factor() / self.factor();
        Some(if ratio >= 1.0 {
            value * ratio.round()
        } else {
            value / inverse.round()
        })
    }
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_round_trip_and_case_folding() {
        for u in Unit::ALL {
            assert_eq!(Unit::from_symbol(u.symbol()), Some(u));
            assert_eq!(Unit::parse(u.symbol()).ok(), Some(u));
        }
        assert_eq!(Unit::parse("RPM").ok(), Some(Unit::Rpm));
        assert_eq!(Unit::parse(" v ").ok(), Some(Unit::Volt));
        assert_eq!(Unit::parse("MS").ok(), Some(Unit::Millisecond));
        assert_eq!(Unit::from_symbol("RPM"), None);
    }

    #[test]
    fn unknown_units_suggest() {
        match Unit::parse("rpn") {
            Err(ValueError::UnknownUnit { unit, suggestions }) => {
                assert_eq!(unit, "rpn");
                assert_eq!(suggestions.first().map(String::as_str), Some("rpm"));
            }
            other => panic!("{other:?}"),
        }
        match Unit::parse("rmp") {
            Err(ValueError::UnknownUnit { suggestions, .. }) => {
                assert_eq!(suggestions.first().map(String::as_str), Some("rpm"));
            }
            other => panic!("{other:?}"),
        }
        let text = Unit::parse("furlong").unwrap_err().to_string();
        assert!(
            text.contains("known units: rpm, krpm, %, V, mV, A, mA, s, ms, min, h"),
            "{text}"
        );
    }

    #[test]
    fn conversions_within_a_dimension() {
        assert_eq!(Unit::Krpm.convert(6.0, Unit::Rpm), Some(6000.0));
        assert_eq!(Unit::Rpm.convert(6500.0, Unit::Krpm), Some(6.5));
        assert_eq!(Unit::Millisecond.convert(250.0, Unit::Second), Some(0.25));
        assert_eq!(Unit::Hour.convert(2.0, Unit::Minute), Some(120.0));
        assert_eq!(Unit::Milliampere.convert(1500.0, Unit::Ampere), Some(1.5));
        assert_eq!(Unit::Rpm.convert(1.0, Unit::Ampere), None);
        assert_eq!(Unit::Percent.convert(3.0, Unit::Percent), Some(3.0));
        assert_eq!(Unit::Micrometre.convert(250.0, Unit::Millimetre), Some(0.25));
        assert_eq!(Unit::parse_measured("um").ok(), Some(Unit::Micrometre));
        assert_eq!(Unit::parse_measured("MM/S").ok(), Some(Unit::MillimetrePerSecond));
        assert_eq!(Unit::parse_measured("rpm").ok(), Some(Unit::Rpm));
        assert!(Unit::parse("mm/s").is_err(), "no drive object is in mm/s");
        let e = Unit::parse_measured("mm/z").unwrap_err().to_string();
        assert!(
            e.contains("known units: rpm, krpm, %, V, mV, A, mA, s, ms, min, h, mm/s, mm, µm, °C"),
            "{e}"
        );
        assert_eq!(Unit::MillimetrePerSecond.convert(1.0, Unit::Millimetre), None);
        for u in Unit::ALL {
            assert_eq!(u.dimension().base().factor(), 1.0, "{u}");
            assert_eq!(u.dimension().base().dimension(), u.dimension());
        }
    }
}
