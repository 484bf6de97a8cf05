//! Engineering units: what commissioning engineers type (`rpm`, `%`, `V`, `A`, `s`, `°C`,
//! `K`, `Hz`, `N·m`, `kW`, `mm/s`, `bar`, …), each with its dimension and its factor to that
//! dimension's base unit. A temperature (`°C`) and a temperature difference (`K`) are
//! different dimensions, so `80 °C` is never taken for 80 K of rise and a tolerance of
//! `2 K` cannot be written where a temperature is wanted; [`Unit::difference`] names the
//! unit a difference of a quantity is written in. Pure arithmetic; it knows nothing of
//! objects or raw counts.

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
    /// A temperature on the Celsius scale. Base: °C.
    Temperature,
    /// A difference of temperatures (a rise, a tolerance, a ripple). Base: K.
    TemperatureDifference,
    /// How fast a temperature changes. Base: K/min.
    TemperatureRate,
    /// Base: Hz.
    Frequency,
    /// Base: N·m.
    Torque,
    /// Base: W.
    Power,
    /// A linear velocity, as vibration is given. Base: mm/s.
    Velocity,
    /// Base: mm (what a dial gauge shows).
    Length,
    /// Base: bar.
    Pressure,
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
            Dimension::Temperature => Unit::DegreeCelsius,
            Dimension::TemperatureDifference => Unit::Kelvin,
            Dimension::TemperatureRate => Unit::KelvinPerMinute,
            Dimension::Frequency => Unit::Hertz,
            Dimension::Torque => Unit::NewtonMetre,
            Dimension::Power => Unit::Watt,
            Dimension::Velocity => Unit::MillimetrePerSecond,
            Dimension::Pressure => Unit::Bar,
            Dimension::Length => Unit::Millimetre,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Dimension::Speed => "speed",
            Dimension::Ratio => "ratio",
            Dimension::Voltage => "voltage",
            Dimension::Current => "current",
            Dimension::Time => "time",
            Dimension::Temperature => "temperature",
            Dimension::TemperatureDifference => "temperature_difference",
            Dimension::TemperatureRate => "temperature_rate",
            Dimension::Frequency => "frequency",
            Dimension::Torque => "torque",
            Dimension::Power => "power",
            Dimension::Velocity => "velocity",
            Dimension::Pressure => "pressure",
            Dimension::Length => "length",
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
    DegreeCelsius,
    Kelvin,
    KelvinPerSecond,
    KelvinPerMinute,
    KelvinPerHour,
    Hertz,
    Kilohertz,
    NewtonMetre,
    Watt,
    Kilowatt,
    MillimetrePerSecond,
    Bar,
    Millimetre,
    Micrometre,
}

/// Other spellings people type for a unit, each standing for exactly one unit.
const ALIASES: [(&str, Unit); 7] = [
    ("degC", Unit::DegreeCelsius),
    ("℃", Unit::DegreeCelsius),
    ("Nm", Unit::NewtonMetre),
    ("N m", Unit::NewtonMetre),
    ("N*m", Unit::NewtonMetre),
    ("N.m", Unit::NewtonMetre),
    ("K/s", Unit::KelvinPerSecond),
];

impl Unit {
    pub const ALL: [Unit; 23] = [
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
        Unit::DegreeCelsius,
        Unit::Kelvin,
        Unit::KelvinPerSecond,
        Unit::KelvinPerMinute,
        Unit::KelvinPerHour,
        Unit::Hertz,
        Unit::Kilohertz,
        Unit::NewtonMetre,
        Unit::Watt,
        Unit::Kilowatt,
        Unit::MillimetrePerSecond,
        Unit::Bar,
    ];

    /// Units of what an operator measures by hand (a dial gauge) and types in at a
    /// prompt; no drive object has them.
    pub const MEASURED: [Unit; 2] = [Unit::Millimetre, Unit::Micrometre];

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
            Unit::DegreeCelsius => "°C",
            Unit::Kelvin => "K",
            Unit::KelvinPerSecond => "K/s",
            Unit::KelvinPerMinute => "K/min",
            Unit::KelvinPerHour => "K/h",
            Unit::Hertz => "Hz",
            Unit::Kilohertz => "kHz",
            Unit::NewtonMetre => "N·m",
            Unit::Watt => "W",
            Unit::Kilowatt => "kW",
            Unit::MillimetrePerSecond => "mm/s",
            Unit::Bar => "bar",
            Unit::Millimetre => "mm",
            Unit::Micrometre => "µm",
        }
    }

    pub fn dimension(self) -> Dimension {
        match self {
            Unit::Rpm | Unit::Krpm => Dimension::Speed,
            Unit::Percent => Dimension::Ratio,
            Unit::Volt | Unit::Millivolt => Dimension::Voltage,
            Unit::Ampere | Unit::Milliampere => Dimension::Current,
            Unit::Second | Unit::Millisecond | Unit::Minute | Unit::Hour => Dimension::Time,
            Unit::DegreeCelsius => Dimension::Temperature,
            Unit::Kelvin => Dimension::TemperatureDifference,
            Unit::KelvinPerSecond | Unit::KelvinPerMinute | Unit::KelvinPerHour => Dimension::TemperatureRate,
            Unit::Hertz | Unit::Kilohertz => Dimension::Frequency,
            Unit::NewtonMetre => Dimension::Torque,
            Unit::Watt | Unit::Kilowatt => Dimension::Power,
            Unit::MillimetrePerSecond => Dimension::Velocity,
            Unit::Bar => Dimension::Pressure,
            Unit::Millimetre | Unit::Micrometre => Dimension::Length,
        }
    }

    /// How many base units (rpm, %, V, A, s, °C, K, K/min, Hz, N·m, W, mm/s, bar, mm) one
    /// of this unit is.
    pub fn factor(self) -> f64 {
        match self {
            Unit::Rpm
            | Unit::Percent
            | Unit::Volt
            | Unit::Ampere
            | Unit::Second
            | Unit::DegreeCelsius
            | Unit::Kelvin
            | Unit::KelvinPerMinute
            | Unit::Hertz
            | Unit::NewtonMetre
            | Unit::Watt
            | Unit::MillimetrePerSecond
            | Unit::Bar
            | Unit::Millimetre => 1.0,
            Unit::Krpm | Unit::Kilohertz | Unit::Kilowatt => 1000.0,
            Unit::Millivolt | Unit::Milliampere | Unit::Millisecond | Unit::Micrometre => 0.001,
            Unit::Minute | Unit::KelvinPerSecond => 60.0,
            Unit::Hour => 3600.0,
            Unit::KelvinPerHour => 1.0 / 60.0,
        }
    }

    /// The unit a difference of two values in this unit is written in: K for °C (a rise
    /// of 2 K, not of 2 °C), the unit itself for every other (a ripple of 20 rpm).
    pub fn difference(self) -> Unit {
        match self {
            Unit::DegreeCelsius => Unit::Kelvin,
            other => other,
        }
    }

    /// The unit of how fast a value in this unit changes, where it has one of its own
    /// (K/min for a temperature).
    pub fn rate(self) -> Option<Unit> {
        match self.difference() {
            Unit::Kelvin => Some(Unit::KelvinPerMinute),
            _ => None,
        }
    }

    /// Why `self` cannot stand where `wanted` is needed, when the reason is not just "other
    /// dimension": a temperature written for a difference, or the other way round.
    pub fn mismatch_help(self, wanted: Unit) -> Option<String> {
        match (self.dimension(), wanted.dimension()) {
            (Dimension::TemperatureDifference, Dimension::Temperature) => Some(
                "K is a temperature difference; a temperature is written in °C (20 °C, not 293.15 K)".into(),
            ),
            (Dimension::Temperature, Dimension::TemperatureDifference) => Some(
                "this is a temperature difference (a rise, a tolerance, a ripple): write it in K (2 K, not 2 °C)"
                    .into(),
            ),
            _ => None,
        }
    }

    /// The unit with exactly this symbol (as dictionaries must write it), or one of its
    /// [`ALIASES`].
    pub fn from_symbol(symbol: &str) -> Option<Unit> {
        Self::ALL
            .into_iter()
            .find(|u| u.symbol() == symbol)
            .or_else(|| ALIASES.iter().find(|(a, _)| *a == symbol).map(|(_, u)| *u))
    }

    /// A unit as people type it: the exact symbol or an alias, or a spelling that differs
    /// only in case when that is unambiguous (`RPM`, `v`, `MS`). The error lists close
    /// symbols.
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
            "degC" | "C" => Some(Unit::DegreeCelsius),
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
        for u in Unit::ALL {
            assert_eq!(u.dimension().base().factor(), 1.0, "{u}");
            assert_eq!(u.dimension().base().dimension(), u.dimension());
        }
    }

    #[test]
    fn run_in_and_vfd_units_convert_within_their_dimension_only() {
        assert_eq!(Unit::Kilohertz.convert(8.0, Unit::Hertz), Some(8000.0));
        assert_eq!(Unit::Kilowatt.convert(2.2, Unit::Watt), Some(2200.0));
        assert_eq!(
            Unit::KelvinPerHour.convert(30.0, Unit::KelvinPerMinute),
            Some(0.5)
        );
        assert_eq!(
            Unit::KelvinPerSecond.convert(0.5, Unit::KelvinPerMinute),
            Some(30.0)
        );
        assert_eq!(Unit::parse("degC").ok(), Some(Unit::DegreeCelsius));
        assert_eq!(Unit::parse("Nm").ok(), Some(Unit::NewtonMetre));
        assert_eq!(Unit::parse("KW").ok(), Some(Unit::Kilowatt));
        assert_eq!(Unit::parse("MM/S").ok(), Some(Unit::MillimetrePerSecond));
        // A temperature is not a temperature difference, either way round.
        assert_eq!(Unit::Kelvin.convert(20.0, Unit::DegreeCelsius), None);
        assert_eq!(Unit::DegreeCelsius.convert(20.0, Unit::Kelvin), None);
        assert_eq!(Unit::DegreeCelsius.difference(), Unit::Kelvin);
        assert_eq!(Unit::Rpm.difference(), Unit::Rpm);
        assert_eq!(Unit::DegreeCelsius.rate(), Some(Unit::KelvinPerMinute));
        assert_eq!(Unit::Rpm.rate(), None);
        assert!(Unit::Kelvin
            .mismatch_help(Unit::DegreeCelsius)
            .is_some_and(|h| h.contains("°C")));
        assert_eq!(Unit::Rpm.mismatch_help(Unit::Ampere), None);
        assert_eq!(Unit::Hertz.convert(1.0, Unit::Rpm), None);
        assert_eq!(Unit::Bar.convert(1.0, Unit::MillimetrePerSecond), None);
    }

    #[test]
    fn measured_units_are_for_typed_values_only() {
        assert_eq!(Unit::Micrometre.convert(250.0, Unit::Millimetre), Some(0.25));
        assert_eq!(Unit::parse_measured("um").ok(), Some(Unit::Micrometre));
        assert_eq!(Unit::parse_measured("degC").ok(), Some(Unit::DegreeCelsius));
        assert_eq!(Unit::parse_measured("MM/S").ok(), Some(Unit::MillimetrePerSecond));
        assert_eq!(Unit::parse_measured("rpm").ok(), Some(Unit::Rpm));
        assert!(Unit::parse("mm").is_err(), "no drive object is in mm");
        let e = Unit::parse_measured("mm/z").unwrap_err().to_string();
        assert!(e.contains("mm/s") && e.contains("µm"), "{e}");
        assert_eq!(Unit::MillimetrePerSecond.convert(1.0, Unit::Millimetre), None);
        for u in Unit::MEASURED {
            assert_eq!(u.dimension().base().factor(), 1.0, "{u}");
            assert_eq!(u.dimension().base().dimension(), u.dimension());
        }
    }
}
