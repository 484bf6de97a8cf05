//! The motor's pole pairs, which tie an inverter's output frequency to the motor's speed
//! (rpm = Hz × 60 / pole pairs), and where the number came from. Pure arithmetic: it
//! knows nothing of families, links or files; the dictionary applies it to its objects.

use super::unit::{Dimension, Unit};
use super::value_error::ValueError;

/// The name a run's setting (`--link-option pole-pairs=N`, a recipe's `link:`) and a
/// dictionary's key (`pole_pairs:`) give it; `_` and `-` are the same.
pub const POLE_PAIRS_SETTING: &str = "pole-pairs";

/// Beyond any motor built: a typo (`pole-pairs=40` for 4) is refused, not obeyed.
pub const MAX_POLE_PAIRS: u32 = 32;

/// True for `pole-pairs` and `pole_pairs`, the setting's two spellings.
pub fn is_pole_pairs_setting(name: &str) -> bool {
    name.trim()
        .replace('_', "-")
        .eq_ignore_ascii_case(POLE_PAIRS_SETTING)
}

/// How many pole pairs the motor has and who said so.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PolePairs {
    pub count: u32,
    /// `the dictionary`, `--link-option pole-pairs=2`, `the recipe's link: pole_pairs`.
    pub origin: String,
}

impl PolePairs {
    /// `text` as a number of pole pairs, 1..=[`MAX_POLE_PAIRS`].
    pub fn parse(text: &str) -> Result<u32, ValueError> {
        text.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=MAX_POLE_PAIRS).contains(n))
            .ok_or_else(|| ValueError::BadPolePairs {
                text: text.trim().to_string(),
            })
    }
}

/// `value` in `from` expressed in `to` across speed and frequency for a motor with
/// `pole_pairs`: rpm = Hz × 60 / pole pairs, and back. `None` unless one unit is a speed
/// and the other a frequency.
pub fn speed_frequency(value: f64, from: Unit, to: Unit, pole_pairs: u32) -> Option<f64> {
    let pairs = f64::from(pole_pairs);
    match (from.dimension(), to.dimension()) {
        (Dimension::Frequency, Dimension::Speed) => {
            let hz = from.convert(value, Unit::Hertz)?;
            Unit::Rpm.convert(hz * 60.0 / pairs, to)
        }
        (Dimension::Speed, Dimension::Frequency) => {
            let rpm = from.convert(value, Unit::Rpm)?;
            Unit::Hertz.convert(rpm * pairs / 60.0, to)
        }
        _ => None,
    }
}

/// True when `a` and `b` are a speed and a frequency, in either order: the pair pole
/// pairs convert between.
pub fn is_speed_and_frequency(a: Unit, b: Unit) -> bool {
    matches!(
        (a.dimension(), b.dimension()),
        (Dimension::Frequency, Dimension::Speed) | (Dimension::Speed, Dimension::Frequency)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hz_to_rpm_follows_the_pole_pairs() {
        assert_eq!(speed_frequency(100.0, Unit::Hertz, Unit::Rpm, 1), Some(6000.0));
        assert_eq!(speed_frequency(100.0, Unit::Hertz, Unit::Rpm, 2), Some(3000.0));
        assert_eq!(speed_frequency(50.0, Unit::Hertz, Unit::Rpm, 3), Some(1000.0));
        assert_eq!(speed_frequency(0.1, Unit::Kilohertz, Unit::Krpm, 2), Some(3.0));
        assert_eq!(speed_frequency(3000.0, Unit::Rpm, Unit::Hertz, 2), Some(100.0));
        assert_eq!(speed_frequency(1500.0, Unit::Rpm, Unit::Hertz, 4), Some(100.0));
        assert_eq!(speed_frequency(1.0, Unit::Rpm, Unit::Rpm, 2), None);
        assert_eq!(speed_frequency(1.0, Unit::Ampere, Unit::Hertz, 2), None);
    }

    #[test]
    fn pole_pairs_are_a_small_whole_number() {
        assert_eq!(PolePairs::parse(" 2 ").ok(), Some(2));
        assert_eq!(PolePairs::parse("32").ok(), Some(32));
        for bad in ["0", "-1", "2.5", "two", "", "33"] {
            let e = PolePairs::parse(bad).unwrap_err().to_string();
            assert!(e.contains("pole pairs"), "{bad}: {e}");
        }
        assert!(is_pole_pairs_setting("pole_pairs"));
        assert!(is_pole_pairs_setting("pole-pairs"));
        assert!(!is_pole_pairs_setting("poles"));
    }
}
