//! How the SD2 family talks to a drive: through object access (Read/Write Wide Object, the
//! default) or through the DNC 8-byte cyclic telegram, with the settings the cyclic channel
//! needs. Read from `--link-option NAME=VALUE` (and the CLI's `--channel`,
//! `--velocity-scaling`, `--heartbeat`, `--cycle` which set the same options), and the
//! speed range the cyclic telegram can carry. Pure parsing and arithmetic.

use super::cyclic_access::SPEED_SETPOINT;
use crate::dictionary::{Address, ObjectDef, Quantity, Unit};
use crate::family::{FamilyError, LinkRange};
use std::time::Duration;

/// Which channel carries control word, setpoint and actual values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Channel {
    Object,
    Cyclic(CyclicSettings),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CyclicSettings {
    /// The speed the drive's 0x3FFF (+100 %) stands for: a drive parameter the user must
    /// give, since the telegram carries fractions of it.
    pub velocity_scaling_rpm: f64,
    /// How often a telegram goes out while nothing else is sent (the drive expects them
    /// continuously).
    pub period: Duration,
    /// Toggle header bit 2 in every telegram (drive parameter "heartbeat").
    pub heartbeat: bool,
    /// Amperes per count of the reply's actual current. The sources do not give this
    /// scaling, so the reply's current is used only when the user states it; otherwise
    /// the current is read through the service channel.
    pub current_scale_a: Option<f64>,
}

/// Default interval between telegrams: at 57 600 bit/s a cyclic round trip takes 5.6 ms of
/// wire time, so 20 ms leaves room for service-channel and object telegrams in between.
pub const DEFAULT_PERIOD: Duration = Duration::from_millis(20);

/// The option names this module reads (both spellings are accepted: `velocity-scaling`
/// on the command line, `velocity_scaling` in a recipe's `link:`).
pub const OPTIONS: [&str; 5] = [
    "channel",
    "velocity-scaling",
    "heartbeat",
    "cycle",
    "current-scaling",
];

impl Channel {
    /// The channel the options ask for; an error names the option and what it accepts.
    pub fn from_options(extra: &[(String, String)]) -> Result<Channel, FamilyError> {
        let mut cyclic = false;
        let mut scaling = None;
        let mut period = DEFAULT_PERIOD;
        let mut heartbeat = false;
        let mut current = None;
        for (name, value) in extra {
            let value = value.trim();
            match name.replace('_', "-").as_str() {
                "channel" => match value {
                    "object" => cyclic = false,
                    "cyclic" => cyclic = true,
                    other => {
                        return Err(FamilyError::LinkOption(format!(
                            "channel={other}: the SD2 channels are `object` (Read/Write Wide Object) and `cyclic` (DNC 8-byte telegram)"
                        )))
                    }
                },
                "velocity-scaling" => scaling = Some(rpm(value)?),
                "heartbeat" => {
                    heartbeat = match value {
                        "on" | "true" | "yes" | "1" => true,
                        "off" | "false" | "no" | "0" => false,
                        other => return Err(FamilyError::LinkOption(format!("heartbeat={other}: give `on` or `off`"))),
                    }
                }
                "cycle" => period = cycle(value)?,
                "current-scaling" => current = Some(amps(value)?),
                _ => {}
            }
        }
        if !cyclic {
            return Ok(Channel::Object);
        }
        let velocity_scaling_rpm = scaling.ok_or_else(|| {
            FamilyError::LinkOption("the cyclic channel carries speeds as fractions of the drive's velocity scaling; give it with --velocity-scaling (e.g. 24000rpm, the drive parameter's value)".to_string())
        })?;
        Ok(Channel::Cyclic(CyclicSettings {
            velocity_scaling_rpm,
            period,
            heartbeat,
            current_scale_a: current,
        }))
    }
}

impl CyclicSettings {
    /// The speed setpoint travels in every telegram as a fraction of the velocity scaling
    /// (0x3FFF = +100 %), so it can be written within ± the scaling only; other objects
    /// keep their own range.
    pub fn carried_range(&self, object: &ObjectDef) -> Option<LinkRange> {
        if object.address != Address::indexed(SPEED_SETPOINT, 0) {
            return None;
        }
        let max = match object.unit {
            Some(unit) => Unit::Rpm.convert(self.velocity_scaling_rpm, unit)?,
            None => self.velocity_scaling_rpm,
        };
        Some(LinkRange {
            min: -max,
            max,
            why: format!(
                "the cyclic channel carries at most ±100 % of the velocity scaling, {} rpm",
                self.velocity_scaling_rpm
            ),
        })
    }
}

fn quantity(name: &str, value: &str, unit: Unit) -> Result<f64, FamilyError> {
    let q = Quantity::parse(value).map_err(|e| FamilyError::LinkOption(format!("{name}={value}: {e}")))?;
    let converted = match q.unit {
        Some(u) => u.convert(q.value, unit).ok_or_else(|| {
            FamilyError::LinkOption(format!("{name}={value}: give it in {}", unit.symbol()))
        })?,
        None => q.value,
    };
    if converted.is_finite() && converted > 0.0 {
        Ok(converted)
    } else {
        Err(FamilyError::LinkOption(format!(
            "{name}={value}: must be more than 0 {}",
            unit.symbol()
        )))
    }
}

fn rpm(value: &str) -> Result<f64, FamilyError> {
    quantity("velocity-scaling", value, Unit::Rpm)
}

fn amps(value: &str) -> Result<f64, FamilyError> {
    quantity("current-scaling", value, Unit::Ampere)
}

fn cycle(value: &str) -> Result<Duration, FamilyError> {
    let d = humantime::parse_duration(&value.replace(' ', ""))
        .map_err(|e| FamilyError::LinkOption(format!("cycle={value}: {e} (e.g. 20ms)")))?;
    if d < Duration::from_millis(1) || d > Duration::from_secs(1) {
        return Err(FamilyError::LinkOption(format!(
            "cycle={value}: give 1 ms to 1 s"
        )));
    }
    Ok(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts(list: &[(&str, &str)]) -> Vec<(String, String)> {
        list.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect()
    }

    #[test]
    fn object_access_is_the_default() {
        assert_eq!(Channel::from_options(&[]).unwrap(), Channel::Object);
    }

    #[test]
    fn cyclic_needs_the_velocity_scaling() {
        let e = Channel::from_options(&opts(&[("channel", "cyclic")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("--velocity-scaling"), "{e}");
    }

    #[test]
    fn cyclic_settings_are_read_in_both_spellings() {
        let c = Channel::from_options(&opts(&[
            ("channel", "cyclic"),
            ("velocity_scaling", "24 krpm"),
            ("heartbeat", "on"),
            ("cycle", "10 ms"),
            ("current-scaling", "10mA"),
        ]))
        .unwrap();
        let Channel::Cyclic(s) = c else { panic!("{c:?}") };
        assert_eq!(s.velocity_scaling_rpm, 24_000.0);
        assert!(s.heartbeat);
        assert_eq!(s.period, Duration::from_millis(10));
        assert!((s.current_scale_a.unwrap() - 0.01).abs() < 1e-12);
    }

    #[test]
    fn bad_values_are_named() {
        for (name, value, says) in [
            ("channel", "pdo", "object"),
            ("velocity-scaling", "-5rpm", "more than 0"),
            ("velocity-scaling", "5 V", "rpm"),
            ("heartbeat", "maybe", "on"),
            ("cycle", "5 s", "1 ms to 1 s"),
        ] {
            let e = Channel::from_options(&opts(&[
                ("channel", "cyclic"),
                ("velocity-scaling", "24000rpm"),
                (name, value),
            ]))
            .unwrap_err()
            .to_string();
            assert!(e.contains(says), "{name}={value}: {e}");
        }
    }
}
