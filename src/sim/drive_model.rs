//! The simulated drive without its bytes: device state, speed ramp, measurements and the
//! object values, advanced lazily to the time of each telegram. It must not parse or build
//! telegrams, and must not know about fault injection beyond being told to trip.

use super::device_state_machine::DeviceStateMachine;
use super::motor::Motor;
use super::noise::XorShift64;
use super::sim_config::SimConfig;
use super::sim_objects::{
    SimObject, ACTUAL_CURRENT, ACTUAL_SPEED, ACTUAL_SPEED_2, BUS_VOLTAGE, CONTROL_WORD, DRIVE_ERROR,
    IDENT_MAX, IDENT_STRING, PARAMETER_SET, POWER_STAGE_LOAD, SPEED_SETPOINT, STATUS_WORD, STORE_PARAMETERS,
};
use crate::drive::device_control::{DeviceCommand, DeviceState};
use crate::protocol::sd2::{Cyclic, Data, ErrorCode};
use std::time::Duration;

/// 230 V mains rectified: 230 V × 1.414.
const BUS_VOLTAGE_V: f64 = 325.3;
const BUS_VOLTAGE_NOISE_V: f64 = 0.3;
/// DC-link sag per ampere of motor current.
const BUS_SAG_V_PER_A: f64 = 0.5;
/// Current at which the power stage load is 100 %.
const POWER_STAGE_RATED_A: f64 = 20.0;
const CURRENT_NOISE_A: f64 = 0.005;
/// Highest parameter set (spindle selection).
const MAX_PARAMETER_SET: u16 = 64;
/// The value that triggers "store parameters".
const STORE_COMMAND: u16 = 1;
/// 0x3FFF in the cyclic telegram is 100 % of the velocity scaling.
const CYCLIC_FULL_SCALE: f64 = 16383.0;
/// Inside this distance from the target the status word shows "target reached".
const TARGET_WINDOW_RPM: f64 = 1.0;

#[derive(Debug, Clone)]
pub(crate) struct DriveModel {
    config: SimConfig,
    machine: DeviceStateMachine,
    motor: Motor,
    /// The time the model has been advanced to; never goes back.
    time: Duration,
    setpoint_rpm: f64,
    parameter_set: u16,
    noise: XorShift64,
}

impl DriveModel {
    pub(crate) fn new(config: SimConfig) -> Self {
        let noise = XorShift64::new(config.seed);
        DriveModel {
            config,
            machine: DeviceStateMachine::booted(),
            motor: Motor::at_rest(),
            time: Duration::ZERO,
            setpoint_rpm: 0.0,
            parameter_set: 0,
            noise,
        }
    }

    pub(crate) fn config(&self) -> &SimConfig {
        &self.config
    }

    pub(crate) fn state(&self) -> DeviceState {
        self.machine.state()
    }

    pub(crate) fn setpoint_rpm(&self) -> f64 {
        self.setpoint_rpm
    }

    /// Model speed at the model's time, without noise.
    pub(crate) fn speed_rpm(&self) -> f64 {
        self.motor.speed_at(self.time)
    }

    /// Moves the model to `now` (earlier times leave it where it is). The ramp is closed
    /// form, so this costs the same for a microsecond as for an hour.
    pub(crate) fn advance_to(&mut self, now: Duration) {
        self.time = self.time.max(now);
        self.update();
    }

    pub(crate) fn trip(&mut self, drive_error: u16) {
        self.machine.trip(drive_error);
        self.update();
    }

    /// What `control_word` would command now, without carrying it out.
    pub(crate) fn command_for(&self, control_word: u16) -> DeviceCommand {
        self.machine.command_for(control_word)
    }

    pub(crate) fn write_control_word(&mut self, control_word: u16, reset_blocked: bool) -> DeviceCommand {
        let command = self.machine.write_control_word(control_word, reset_blocked);
        self.update();
        command
    }

    /// The cyclic telegram's speed reference: a fraction of the velocity scaling.
    pub(crate) fn set_speed_reference(&mut self, reference: i16) {
        self.setpoint_rpm = f64::from(reference) / CYCLIC_FULL_SCALE * self.config.velocity_scaling_rpm;
        self.update();
    }

    /// Steers the motor for the current state, then lets the braking states end if the
    /// motor is (already) at rest, which can change the steering once more.
    fn update(&mut self) {
        self.steer();
        if self.motor.speed_at(self.time) == 0.0 && self.machine.at_standstill() {
            self.steer();
        }
    }

    fn steer(&mut self) {
        let c = &self.config;
        let (target, rate) = match self.machine.state() {
            DeviceState::OperationEnabled => (self.target_rpm(), c.ramp_rpm_per_s),
            DeviceState::QuickStopActive | DeviceState::FaultReactionActive => {
                (0.0, c.quick_stop_ramp_rpm_per_s)
            }
            _ => (0.0, c.coast_rpm_per_s),
        };
        self.motor.steer(self.time, target, rate);
    }

    fn target_rpm(&self) -> f64 {
        let max = self.config.max_speed_rpm.abs();
        self.setpoint_rpm.clamp(-max, max)
    }

    fn status_word(&self) -> u16 {
        let at_target = (self.speed_rpm() - self.target_rpm()).abs() < TARGET_WINDOW_RPM;
        self.machine.status_word(at_target)
    }

    /// Actual speed as measured: noise while the motor turns or the power stage is on,
    /// an exact 0 for a motor at rest with the power stage off.
    fn measured_speed_rpm(&mut self) -> f64 {
        let v = self.speed_rpm();
        if v != 0.0 || self.state().is_powered() {
            v + self.config.noise_rpm * self.noise.symmetric()
        } else {
            0.0
        }
    }

    fn current_a(&self) -> f64 {
        if self.state().is_powered() {
            self.motor.current_at(self.time)
        } else {
            0.0
        }
    }

    fn measured_current_a(&mut self) -> f64 {
        if self.state().is_powered() {
            self.current_a() + CURRENT_NOISE_A * self.noise.symmetric()
        } else {
            0.0
        }
    }

    /// The value of object `index`, after the access checks a real drive makes.
    pub(crate) fn read(&mut self, index: u16, subindex: u32) -> Result<Data, ErrorCode> {
        SimObject::find(index)?.check_read(subindex)?;
        Ok(match index {
            IDENT_STRING => self.ident(),
            BUS_VOLTAGE => {
                let v = BUS_VOLTAGE_V - BUS_SAG_V_PER_A * self.current_a().abs()
                    + BUS_VOLTAGE_NOISE_V * self.noise.symmetric();
                u16_data(counts_u16(v * 10.0))
            }
            POWER_STAGE_LOAD => u16_data(counts_u16(
                self.current_a().abs() / POWER_STAGE_RATED_A * 100.0 * 10.0,
            )),
            STATUS_WORD => u16_data(self.status_word()),
            CONTROL_WORD => u16_data(self.machine.control_word()),
            ACTUAL_SPEED | ACTUAL_SPEED_2 => i32_data(counts_i32(self.measured_speed_rpm() * 1000.0)),
            PARAMETER_SET => u16_data(self.parameter_set),
            SPEED_SETPOINT => i32_data(counts_i32(self.setpoint_rpm * 1000.0)),
            ACTUAL_CURRENT => i32_data(counts_i32(self.measured_current_a() * 1000.0)),
            DRIVE_ERROR => u16_data(self.machine.drive_error()),
            // In the table but without a value: the table and this match disagree.
            _ => return Err(INTERNAL_INCOMPATIBILITY),
        })
    }

    /// Writes object `index` after the access, length and range checks.
    pub(crate) fn write(
        &mut self,
        index: u16,
        subindex: u32,
        bytes: &[u8],
        reset_blocked: bool,
    ) -> Result<(), ErrorCode> {
        SimObject::find(index)?.check_write(subindex, bytes.len())?;
        match (index, bytes) {
            (CONTROL_WORD, &[lo, hi]) => {
                self.write_control_word(u16::from_le_bytes([lo, hi]), reset_blocked);
            }
            (PARAMETER_SET, &[lo, hi]) => {
                // Range before state: a value that can never be valid is the clearer error.
                if u16::from_le_bytes([lo, hi]) > MAX_PARAMETER_SET {
                    return Err(ErrorCode::RANGE_EXCEEDED);
                }
                if self.state() == DeviceState::OperationEnabled {
                    return Err(ErrorCode::STATE_OF_CONTROL);
                }
                self.parameter_set = u16::from_le_bytes([lo, hi]);
            }
            (SPEED_SETPOINT, &[a, b, c, d]) => {
                let milli_rpm = f64::from(i32::from_le_bytes([a, b, c, d]));
                let max = self.config.max_speed_rpm.abs() * 1000.0;
                if milli_rpm > max {
                    return Err(ErrorCode::TOO_HIGH);
                }
                if milli_rpm < -max {
                    return Err(ErrorCode::TOO_LOW);
                }
                self.setpoint_rpm = milli_rpm / 1000.0;
                self.update();
            }
            (STORE_PARAMETERS, &[lo, hi]) => {
                // Only the command value is meaningful; nothing is stored in a simulator.
                if u16::from_le_bytes([lo, hi]) != STORE_COMMAND {
                    return Err(ErrorCode::RANGE_EXCEEDED);
                }
            }
            _ => return Err(INTERNAL_INCOMPATIBILITY),
        }
        Ok(())
    }

    /// The process data of a cyclic reply: status word, actual speed in the telegram's
    /// scaling, drive error, current in 0.01 A.
    pub(crate) fn cyclic_reply(&mut self, header: [u8; 2]) -> Cyclic {
        let speed = self.measured_speed_rpm() / self.config.velocity_scaling_rpm * CYCLIC_FULL_SCALE;
        let current = self.measured_current_a() * 100.0;
        Cyclic::reply(
            header,
            self.status_word(),
            counts_i16(speed),
            self.machine.drive_error(),
            counts_i16(current),
        )
    }

    /// Object 22: max length, the characters, NUL when shorter than the maximum.
    fn ident(&self) -> Data {
        let chars = self.config.ident.as_bytes();
        let chars = &chars[..chars.len().min(IDENT_MAX)];
        let mut out = Vec::with_capacity(IDENT_MAX + 2);
        out.push(IDENT_MAX as u8);
        out.extend_from_slice(chars);
        if chars.len() < IDENT_MAX {
            out.push(0);
        }
        Data::new(&out).unwrap_or_default()
    }
}

const INTERNAL_INCOMPATIBILITY: ErrorCode = ErrorCode(0x8F);

fn u16_data(v: u16) -> Data {
    Data::new(&v.to_le_bytes()).unwrap_or_default()
}

fn i32_data(v: i32) -> Data {
    Data::new(&v.to_le_bytes()).unwrap_or_default()
}

// `as` from f64 saturates at the integer's bounds (and maps NaN to 0), which is the clamp wanted.
fn counts_u16(v: f64) -> u16 {
    v.round() as u16
}

fn counts_i16(v: f64) -> i16 {
    v.round() as i16
}

fn counts_i32(v: f64) -> i32 {
    v.round() as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> DriveModel {
        DriveModel::new(SimConfig::default())
    }

    fn u16_of(d: Data) -> u16 {
        u16::from_le_bytes([d.as_slice()[0], d.as_slice()[1]])
    }

    fn i32_of(d: Data) -> i32 {
        let s = d.as_slice();
        i32::from_le_bytes([s[0], s[1], s[2], s[3]])
    }

    fn secs(s: f64) -> Duration {
        Duration::from_secs_f64(s)
    }

    fn enable(m: &mut DriveModel) {
        for cw in [6, 7, 15] {
            m.write_control_word(cw, false);
        }
        assert_eq!(m.state(), DeviceState::OperationEnabled);
    }

    #[test]
    fn every_object_has_a_value_of_its_size_or_is_write_only() {
        let mut m = model();
        for o in super::super::sim_objects::OBJECTS {
            match m.read(o.index, 0) {
                Ok(d) if o.index == IDENT_STRING => assert_eq!(d.len(), 12),
                Ok(d) => assert_eq!(d.len(), o.size(), "object {}", o.index),
                Err(e) => assert_eq!((o.index, e), (STORE_PARAMETERS, ErrorCode::WRITE_ONLY)),
            }
        }
    }

    #[test]
    fn measurements_at_rest_and_at_speed() {
        let mut m = model();
        // At rest, power off: exact zeros and nominal voltage.
        assert_eq!(i32_of(m.read(ACTUAL_SPEED, 0).unwrap()), 0);
        assert_eq!(i32_of(m.read(ACTUAL_CURRENT, 0).unwrap()), 0);
        assert_eq!(u16_of(m.read(POWER_STAGE_LOAD, 0).unwrap()), 0);
        let v = u16_of(m.read(BUS_VOLTAGE, 0).unwrap());
        assert!((3250..=3256).contains(&v), "{v}");
        m.write(SPEED_SETPOINT, 0, &10_000_000i32.to_le_bytes(), false)
            .unwrap();
        enable(&mut m);
        m.advance_to(secs(10.0));
        let speed = i32_of(m.read(ACTUAL_SPEED, 0).unwrap());
        assert!((speed - 10_000_000).abs() <= 500, "{speed}");
        let current = i32_of(m.read(ACTUAL_CURRENT, 0).unwrap());
        assert!((current - 800).abs() <= 5, "{current}");
        // 0.8 A of 20 A = 4.0 % = 40 counts.
        assert_eq!(u16_of(m.read(POWER_STAGE_LOAD, 0).unwrap()), 40);
        let v = u16_of(m.read(BUS_VOLTAGE, 0).unwrap());
        assert!((3246..=3252).contains(&v), "{v}");
        assert_eq!(u16_of(m.read(STATUS_WORD, 0).unwrap()), 0x0637);
    }

    #[test]
    fn parameter_set_range_and_state() {
        let mut m = model();
        assert_eq!(m.write(PARAMETER_SET, 0, &64u16.to_le_bytes(), false), Ok(()));
        assert_eq!(u16_of(m.read(PARAMETER_SET, 0).unwrap()), 64);
        assert_eq!(
            m.write(PARAMETER_SET, 0, &65u16.to_le_bytes(), false),
            Err(ErrorCode::RANGE_EXCEEDED)
        );
        enable(&mut m);
        assert_eq!(
            m.write(PARAMETER_SET, 0, &1u16.to_le_bytes(), false),
            Err(ErrorCode::STATE_OF_CONTROL)
        );
        assert_eq!(u16_of(m.read(PARAMETER_SET, 0).unwrap()), 64);
    }

    #[test]
    fn quick_stop_at_rest_ends_at_once() {
        let mut m = model();
        enable(&mut m);
        m.write_control_word(2, false);
        assert_eq!(m.state(), DeviceState::SwitchOnDisabled);
    }
}
