//! The parameters of the simulated Unidrive SP: which menu.parameter reads what from the
//! drive model, and what a write does to it. Values are exact decimals with the places the
//! dictionary gives. No bytes here: the simulator front decodes and encodes.
//! Besides the dictionary's parameters it keeps two plain stored ones, the ramp rates
//! #2.11 and #2.21 (no effect on the model), so a scan (`backup --all`) finds parameters
//! no dictionary lists.

use crate::drive::device_control::DeviceState;
use crate::family::ct_ansi::codec::{DataValue, Parameter};
use crate::sim::DriveModel;

/// Zero speed (#10.03) below this (the simulator's choice).
const ZERO_SPEED_RPM: f64 = 5.0;
/// At speed (#10.06) within this of the reference (the simulator's choice).
const AT_SPEED_RPM: f64 = 1.0;
/// #10.38 value that resets a trip.
const RESET: i64 = 100;
/// Control-word bits.
const ENABLE: u16 = 1 << 0;
const RUN_BITS: u16 = (1 << 1) | (1 << 3) | (1 << 5);
const AUTO: u16 = 1 << 7;

/// Why a write is refused (the drive answers NAK).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    NoSuchParameter,
    ReadOnly,
    OutOfRange,
}

/// What the drive should do after a write besides storing it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    None,
    /// The control word acts: go to this state.
    Control(u16),
    /// A trip reset.
    Reset,
}

/// The most #1.06 can be: SPEED_LIMIT_MAX, at most 40000.0 rpm (Unidrive SP Advanced User
/// Guide, table 4-1), as in the dictionary; a drive model allowed more still stops here.
const SPEED_LIMIT_MAX_RPM: f64 = 40_000.0;

/// The parameters the drive stores itself (the others are read from the model).
#[derive(Debug, Clone)]
pub struct CtParameters {
    max_speed: DataValue,
    reference_selector: i64,
    /// #2.11 acceleration and #2.21 deceleration rate, stored only.
    ramp_rates: [DataValue; 2],
    drive_enable: i64,
    sequencing_latch: i64,
    control_word: u16,
    control_word_enable: i64,
    last_trip: i64,
}

impl CtParameters {
    pub fn new(max_speed_rpm: f64) -> Self {
        CtParameters {
            max_speed: DataValue::new((max_speed_rpm.min(SPEED_LIMIT_MAX_RPM) * 10.0).round() as i64, 1),
            reference_selector: 3,
            ramp_rates: [DataValue::new(2000, 3), DataValue::new(2000, 3)],
            drive_enable: 1,
            sequencing_latch: 0,
            control_word: 0,
            control_word_enable: 0,
            last_trip: 0,
        }
    }

    pub fn control_word(&self) -> u16 {
        self.control_word
    }

    /// Remembers the drive's trip code for #10.20 (it outlives the reset).
    pub fn note_trip(&mut self, code: u16) {
        if code != 0 {
            self.last_trip = i64::from(code);
        }
    }

    /// The status word #10.40: bit n is #10.(n+1).
    pub fn status_word(model: &DriveModel) -> u16 {
        let state = model.state();
        let speed = model.speed_rpm();
        let mut w = 0u16;
        let healthy = !matches!(state, DeviceState::Fault | DeviceState::FaultReactionActive);
        let active = state.is_powered();
        if healthy {
            w |= 1;
        }
        if active {
            w |= 1 << 1;
        }
        if speed.abs() <= ZERO_SPEED_RPM {
            w |= 1 << 2;
        }
        if active && (speed - model.setpoint_rpm()).abs() <= AT_SPEED_RPM {
            w |= 1 << 5;
        }
        if model.setpoint_rpm() < 0.0 {
            w |= 1 << 12;
        }
        if speed < 0.0 {
            w |= 1 << 13;
        }
        w
    }

    /// The value of `p`, or `None` when the drive has no such parameter.
    pub fn read(&self, model: &mut DriveModel, p: Parameter) -> Option<DataValue> {
        let tenths = |v: f64| DataValue::new((v * 10.0).round() as i64, 1);
        let whole = |v: i64| DataValue::new(v, 0);
        let bit = |n: u16| whole(i64::from(Self::status_word(model) >> n & 1));
        Some(match (p.menu, p.param) {
            (1, 6) => self.max_speed,
            (1, 14) => whole(self.reference_selector),
            (2, 11) => self.ramp_rates[0],
            (2, 21) => self.ramp_rates[1],
            (1, 21) => tenths(model.setpoint_rpm()),
            (3, 2) => tenths(model.measured_speed_rpm()),
            (4, 1) => DataValue::new((model.measured_current_a() * 100.0).round() as i64, 2),
            (5, 4) => whole(model.measured_speed_rpm().round() as i64),
            (5, 5) => whole(model.measured_bus_voltage_v().round() as i64),
            (6, 15) => whole(self.drive_enable),
            (6, 40) => whole(self.sequencing_latch),
            (6, 42) => whole(i64::from(self.control_word)),
            (6, 43) => whole(self.control_word_enable),
            (10, 1) => bit(0),
            (10, 2) => bit(1),
            (10, 3) => bit(2),
            (10, 6) => bit(5),
            (10, 20) => whole(self.last_trip),
            (10, 38) => whole(0),
            (10, 40) => whole(i64::from(Self::status_word(model))),
            (11, 29) => DataValue::new(110, 2),
            _ => return None,
        })
    }

    /// Stores a write of `p`; what else must happen is the returned effect.
    pub fn write(&mut self, model: &mut DriveModel, p: Parameter, v: DataValue) -> Result<Effect, Refusal> {
        let whole = |range: std::ops::RangeInclusive<i64>| {
            v.with_places(0)
                .map(|w| w.digits)
                .filter(|w| range.contains(w))
                .ok_or(Refusal::OutOfRange)
        };
        match (p.menu, p.param) {
            (1, 6) => {
                let max = v.with_places(1).ok_or(Refusal::OutOfRange)?;
                let limit = model.config().max_speed_rpm.min(SPEED_LIMIT_MAX_RPM);
                if max.digits < 0 || max.digits as f64 / 10.0 > limit {
                    return Err(Refusal::OutOfRange);
                }
                self.max_speed = max;
            }
            (1, 14) => self.reference_selector = whole(0..=5)?,
            (2, 11) | (2, 21) => {
                let rate = v.with_places(3).filter(|r| (0..=3_200_000).contains(&r.digits));
                self.ramp_rates[usize::from(p.param == 21)] = rate.ok_or(Refusal::OutOfRange)?;
            }
            (1, 21) => {
                let rpm = v.digits as f64 / 10f64.powi(i32::from(v.places));
                if rpm.abs() > self.max_speed.digits as f64 / 10.0 {
                    return Err(Refusal::OutOfRange);
                }
                model.set_setpoint_rpm(rpm).map_err(|_| Refusal::OutOfRange)?;
            }
            (6, 15) => self.drive_enable = whole(0..=1)?,
            (6, 40) => self.sequencing_latch = whole(0..=1)?,
            (6, 42) => {
                let cw = whole(0..=0x7FFF)? as u16;
                self.control_word = cw;
                if self.control_word_enable == 1 && cw & AUTO != 0 {
                    return Ok(Effect::Control(cw));
                }
            }
            (6, 43) => self.control_word_enable = whole(0..=1)?,
            (10, 38) => match whole(0..=255)? {
                0 => {}
                RESET => return Ok(Effect::Reset),
                _ => return Err(Refusal::OutOfRange),
            },
            (3, 2)
            | (4, 1)
            | (5, 4)
            | (5, 5)
            | (10, 1)
            | (10, 2)
            | (10, 3)
            | (10, 6)
            | (10, 20)
            | (10, 40)
            | (11, 29) => return Err(Refusal::ReadOnly),
            _ => return Err(Refusal::NoSuchParameter),
        }
        Ok(Effect::None)
    }
}

/// The state a control word asks for: disabled, enabled and stopped, or running.
pub fn target_state(control_word: u16) -> DeviceState {
    if control_word & ENABLE == 0 {
        DeviceState::SwitchOnDisabled
    } else if control_word & RUN_BITS == 0 {
        DeviceState::SwitchedOn
    } else {
        DeviceState::OperationEnabled
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::SimConfig;

    #[test]
    fn control_words_of_the_notes() {
        assert_eq!(target_state(128), DeviceState::SwitchOnDisabled);
        assert_eq!(target_state(129), DeviceState::SwitchedOn);
        assert_eq!(target_state(131), DeviceState::OperationEnabled);
    }

    #[test]
    fn writes_are_checked_and_stored_exactly() {
        let mut model = DriveModel::new(SimConfig::default());
        let mut p = CtParameters::new(3000.0);
        let param = |m, n| Parameter::new(m, n).unwrap();
        let e = p.write(&mut model, param(1, 21), DataValue::new(15005, 1));
        assert_eq!(e, Ok(Effect::None));
        assert_eq!(p.read(&mut model, param(1, 21)), Some(DataValue::new(15005, 1)));
        assert_eq!(
            p.write(&mut model, param(1, 21), DataValue::new(30001, 1)),
            Err(Refusal::OutOfRange)
        );
        assert_eq!(
            p.write(&mut model, param(10, 40), DataValue::new(0, 0)),
            Err(Refusal::ReadOnly)
        );
        assert_eq!(
            p.write(&mut model, param(6, 42), DataValue::new(131, 0)),
            Ok(Effect::None),
            "the control word does nothing while #6.43 is 0"
        );
        p.write(&mut model, param(6, 43), DataValue::new(1, 0)).unwrap();
        assert_eq!(
            p.write(&mut model, param(6, 42), DataValue::new(131, 0)),
            Ok(Effect::Control(131))
        );
        assert_eq!(
            p.write(&mut model, param(10, 38), DataValue::new(100, 0)),
            Ok(Effect::Reset)
        );
        assert_eq!(p.read(&mut model, param(99, 99)), None);
        assert_eq!(
            CtParameters::status_word(&model) & 0x7,
            0x5,
            "healthy, zero speed"
        );
    }
}
