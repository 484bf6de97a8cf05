//! One `--sim NAME=VALUE` setting of the built-in simulated drive's physics: the speed
//! controller's response (`response-time=200ms`, `overshoot=10%`), friction
//! (`coast-rate=300rpm/s`) and heat (`ambient=25°C`, `heating=25K/A`,
//! `thermal-time=10min`), an emergency message without a trip (`emergency-at=20s:0x2310`,
//! a CANopen node's EMCY), a trip (`trip-at=20s:0x1234`), a drive that falls silent
//! (`silent=20s..25s`, its heartbeat too), and how late the drive answers
//! (`reply-latency=1500ms`, a slow slave). Parsing and applying to a [`SimConfig`] only.

use super::motor::Response;
use super::SimConfig;
use crate::dictionary::{Quantity, Unit};
use std::time::Duration;

/// The names, in the order `--help` and errors list them.
pub const SIM_SETTINGS: [&str; 10] = [
    "response-time",
    "overshoot",
    "coast-rate",
    "ambient",
    "heating",
    "thermal-time",
    "emergency-at",
    "trip-at",
    "silent",
    "reply-latency",
];

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SimSetting {
    ResponseTime(Duration),
    Overshoot(f64),
    CoastRate(f64),
    Ambient(f64),
    Heating(f64),
    ThermalTime(Duration),
    /// At this time on the simulator's clock, an emergency message with this error code.
    EmergencyAt(Duration, u16),
    /// At this time the drive trips with this drive error.
    TripAt(Duration, u16),
    /// The drive answers nothing (sends no heartbeat) from the first time until the second.
    Silent(Duration, Duration),
    /// Every reply leaves this long after its request (a slave slower than the master's
    /// reply timeout answers each request during the next one's wait).
    ReplyLatency(Duration),
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimSettingError {
    #[error("`{0}` is not NAME=VALUE (e.g. overshoot=10%)")]
    NotAPair(String),
    #[error("unknown simulator setting `{0}`; known: response-time, overshoot, coast-rate, ambient, heating, thermal-time, emergency-at, trip-at, silent, reply-latency")]
    Unknown(String),
    #[error("{name}: `{value}` is not {wanted}")]
    BadValue {
        name: &'static str,
        value: String,
        wanted: &'static str,
    },
    /// A `--sim` setting for a run that talks to no simulated drive (a port, a TCP
    /// server, a CAN bus, a replayed capture): it would change nothing, and a run that
    /// passes would seem to have proved what it set.
    #[error("--sim sets the built-in simulated drive's physics, but this run talks to {line}, where it would do nothing; leave it out (a simulated drive served on a port takes it: `drivescript simulate --sim …`)")]
    NotSimulated {
        /// What the run talks to, as a trace's header says it.
        line: String,
    },
    /// `emergency-at` for drives whose simulator never sends an emergency message: the
    /// setting would do nothing, and a run that passes would prove nothing.
    #[error("--sim emergency-at: no simulated {families} drive sends emergency messages (an EMCY is a CANopen node's), so the setting would do nothing; give it with --drive {senders}, or leave it out")]
    NoEmergencies {
        /// The run's families: `sd2`, `ct-ansi or sd2`.
        families: String,
        /// The built-in dictionaries whose simulated drives send one: `canopen`.
        senders: String,
    },
}

impl SimSetting {
    pub fn parse(text: &str) -> Result<SimSetting, SimSettingError> {
        let (name, value) = text
            .split_once('=')
            .ok_or_else(|| SimSettingError::NotAPair(text.to_string()))?;
        let (name, value) = (name.trim(), value.trim());
        let Some(&known) = SIM_SETTINGS.iter().find(|n| **n == name) else {
            return Err(SimSettingError::Unknown(name.to_string()));
        };
        let bad = |wanted| SimSettingError::BadValue {
            name: known,
            value: value.to_string(),
            wanted,
        };
        let duration = |wanted| match humantime::parse_duration(value) {
            Ok(d) if !d.is_zero() => Ok(d),
            _ => Err(bad(wanted)),
        };
        let quantity = |unit: Unit, wanted| match Quantity::parse(value).ok().and_then(|q| q.value_in(unit)) {
            Some(v) if v.is_finite() => Ok(v),
            _ => Err(bad(wanted)),
        };
        Ok(match known {
            "response-time" => SimSetting::ResponseTime(duration("a duration above zero (200ms)")?),
            "overshoot" => {
                let v = quantity(Unit::Percent, "a share of the step below 100 % (10%)")?;
                if !(0.0..100.0).contains(&v) {
                    return Err(bad("a share of the step below 100 % (10%)"));
                }
                SimSetting::Overshoot(v / 100.0)
            }
            "coast-rate" => {
                let rpm = value.strip_suffix("/s").unwrap_or(value);
                match Quantity::parse(rpm).ok().and_then(|q| q.value_in(Unit::Rpm)) {
                    Some(v) if v > 0.0 && v.is_finite() => SimSetting::CoastRate(v),
                    _ => return Err(bad("a deceleration above zero in rpm/s (300rpm/s)")),
                }
            }
            "ambient" => SimSetting::Ambient(quantity(Unit::DegreeCelsius, "a temperature (25°C)")?),
            "heating" => {
                let k = value.strip_suffix("/A").unwrap_or(value);
                match Quantity::parse(k).ok().and_then(|q| q.value_in(Unit::Kelvin)) {
                    Some(v) if v >= 0.0 && v.is_finite() => SimSetting::Heating(v),
                    _ => return Err(bad("a temperature rise per ampere (25K/A)")),
                }
            }
            "trip-at" => {
                let wanted = "a time and a non-zero drive error (20s:0x1234)";
                let (at, code) = value.split_once(':').ok_or_else(|| bad(wanted))?;
                let at = humantime::parse_duration(at.trim()).map_err(|_| bad(wanted))?;
                let code = code_of(code).ok_or_else(|| bad(wanted))?;
                SimSetting::TripAt(at, code)
            }
            "silent" => {
                let wanted = "a time span FROM..UNTIL (20s..25s)";
                let (from, until) = value.split_once("..").ok_or_else(|| bad(wanted))?;
                let from = humantime::parse_duration(from.trim()).map_err(|_| bad(wanted))?;
                let until = humantime::parse_duration(until.trim()).map_err(|_| bad(wanted))?;
                if until <= from {
                    return Err(bad(wanted));
                }
                SimSetting::Silent(from, until)
            }
            "emergency-at" => {
                let wanted = "a time and a non-zero error code (20s:0x2310)";
                let (at, code) = value.split_once(':').ok_or_else(|| bad(wanted))?;
                let at = humantime::parse_duration(at.trim()).map_err(|_| bad(wanted))?;
                // A bare number, decimal or `0x` hex; 0 is the error reset, no error.
                match Quantity::parse(code.trim()) {
                    Ok(Quantity {
                        value, unit: None, ..
                    }) if value.fract() == 0.0 && (1.0..=65535.0).contains(&value) => {
                        SimSetting::EmergencyAt(at, value as u16)
                    }
                    _ => return Err(bad(wanted)),
                }
            }
            "reply-latency" => SimSetting::ReplyLatency(duration("a duration above zero (1500ms)")?),
            _ => SimSetting::ThermalTime(duration("a duration above zero (10min)")?),
        })
    }

    pub fn apply(self, config: &mut SimConfig) {
        let mut response = config.response.unwrap_or(Response {
            time_constant_s: 0.2,
            overshoot: 0.0,
        });
        match self {
            SimSetting::ResponseTime(d) => {
                response.time_constant_s = d.as_secs_f64();
                config.response = Some(response);
            }
            SimSetting::Overshoot(o) => {
                response.overshoot = o;
                config.response = Some(response);
            }
            SimSetting::CoastRate(r) => config.coast_rpm_per_s = r,
            SimSetting::Ambient(c) => config.ambient_c = c,
            SimSetting::Heating(k) => config.heating_k_per_a = k,
            SimSetting::ThermalTime(d) => config.thermal_time_constant = d,
            SimSetting::EmergencyAt(at, code) => config.emergencies.push((at, code)),
            SimSetting::TripAt(at, code) => config.trips.push((at, code)),
            SimSetting::Silent(from, until) => config.silent = Some((from, until)),
            SimSetting::ReplyLatency(d) => config.response_latency = d,
        }
    }
}

/// A bare number, decimal or `0x` hex, from 1 to 65535 (0 is no error).
fn code_of(text: &str) -> Option<u16> {
    match Quantity::parse(text.trim()) {
        Ok(Quantity {
            value, unit: None, ..
        }) if value.fract() == 0.0 && (1.0..=65535.0).contains(&value) => Some(value as u16),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_parse_with_their_units_and_apply() {
        let mut c = SimConfig::default();
        for s in [
            "response-time=150ms",
            "overshoot=12.5%",
            "coast-rate=600rpm/s",
            "ambient=20°C",
            "heating=30K/A",
            "thermal-time=5min",
        ] {
            SimSetting::parse(s).unwrap().apply(&mut c);
        }
        assert_eq!(
            c.response,
            Some(Response {
                time_constant_s: 0.15,
                overshoot: 0.125
            })
        );
        assert_eq!(c.coast_rpm_per_s, 600.0);
        assert_eq!((c.ambient_c, c.heating_k_per_a), (20.0, 30.0));
        assert_eq!(c.thermal_time_constant, Duration::from_secs(300));
    }

    #[test]
    fn bad_settings_say_what_is_wanted() {
        assert!(matches!(
            SimSetting::parse("overshoot"),
            Err(SimSettingError::NotAPair(_))
        ));
        assert!(matches!(
            SimSetting::parse("overshot=1%"),
            Err(SimSettingError::Unknown(_))
        ));
        let e = SimSetting::parse("ambient=300K").unwrap_err().to_string();
        assert!(e.contains("a temperature (25°C)"), "{e}");
        assert!(SimSetting::parse("overshoot=120%").is_err());
        assert!(SimSetting::parse("response-time=0s").is_err());
        let mut c = SimConfig::default();
        SimSetting::parse("emergency-at=20s:0x2310")
            .unwrap()
            .apply(&mut c);
        SimSetting::parse("emergency-at=1min:16912")
            .unwrap()
            .apply(&mut c);
        assert_eq!(
            c.emergencies,
            [
                (Duration::from_secs(20), 0x2310),
                (Duration::from_secs(60), 0x4210)
            ]
        );
        SimSetting::parse("trip-at=12s:0x1234").unwrap().apply(&mut c);
        SimSetting::parse("silent=20s..25s").unwrap().apply(&mut c);
        assert_eq!(c.trips, [(Duration::from_secs(12), 0x1234)]);
        assert_eq!(c.silent, Some((Duration::from_secs(20), Duration::from_secs(25))));
        for bad in ["trip-at=12s", "trip-at=12s:0", "silent=25s..20s", "silent=20s"] {
            assert!(SimSetting::parse(bad).is_err(), "{bad}");
        }
        for bad in [
            "emergency-at=20s",
            "emergency-at=20s:0",
            "emergency-at=x:0x2310",
            "emergency-at=1s:0x12345",
        ] {
            let e = SimSetting::parse(bad).unwrap_err().to_string();
            assert!(e.contains("20s:0x2310"), "{bad}: {e}");
        }
    }
}
