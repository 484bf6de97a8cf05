//! The simulated drive without its bytes and without a family: device state, speed ramp,
//! measurements (speed, current, bus voltage, power-stage load), setpoint, parameter set and
//! identity, advanced lazily to the time of each telegram. Each family's simulator front maps
//! its objects and telegrams onto this. It must not know objects, encodings or error codes,
//! and must not know about fault injection beyond being told to trip.

use super::device_state_machine::DeviceStateMachine;
use super::motor::Motor;
use super::noise::XorShift64;
use super::sim_config::SimConfig;
use super::thermal::Thermal;
use crate::drive::device_control::{DeviceCommand, DeviceState};
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
pub const MAX_PARAMETER_SET: u16 = 64;
/// Inside this distance from the target the status word shows "target reached".
const TARGET_WINDOW_RPM: f64 = 1.0;

#[derive(Debug, Clone)]
pub struct DriveModel {
    config: SimConfig,
    machine: DeviceStateMachine,
    motor: Motor,
    thermal: Thermal,
    /// The time the model has been advanced to; never goes back.
    time: Duration,
    setpoint_rpm: f64,
    parameter_set: u16,
    noise: XorShift64,
    /// Every state change a control word made, as (time, from, to): the latest ones
    /// (bounded like the request log), for tests that judge which way a stop moved it.
    commanded: Vec<(Duration, DeviceState, DeviceState)>,
}

impl DriveModel {
    /// The speed (without noise) at `now`, with the trips `faults` schedules up to then
    /// applied, leaving this model as it is: what a test or the safe stop's final line asks
    /// between requests.
    pub fn speed_at(&self, faults: &super::FaultInjection, now: Duration) -> f64 {
        let mut model = self.clone();
        for (at, code) in faults.trips_due(now) {
            model.advance_to(at);
            model.trip(code);
        }
        model.advance_to(now);
        model.speed_rpm()
    }

    pub fn new(config: SimConfig) -> Self {
        let noise = XorShift64::new(config.seed);
        let thermal = Thermal::at(config.ambient_c, config.thermal_time_constant);
        DriveModel {
            config,
            machine: DeviceStateMachine::booted(),
            motor: Motor::at_rest(),
            thermal,
            time: Duration::ZERO,
            setpoint_rpm: 0.0,
            parameter_set: 0,
            noise,
            commanded: Vec::new(),
        }
    }

    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    pub fn state(&self) -> DeviceState {
        self.machine.state()
    }

    /// The state changes control words made, as (time, from, to), oldest first (the
    /// latest ones: bounded like the request log). A trip is not one of them.
    pub fn commanded_changes(&self) -> &[(Duration, DeviceState, DeviceState)] {
        &self.commanded
    }

    pub fn setpoint_rpm(&self) -> f64 {
        self.setpoint_rpm
    }

    /// Model speed at the model's time, without noise.
    pub fn speed_rpm(&self) -> f64 {
        self.motor.speed_at(self.time)
    }

    /// Moves the model to `now` (earlier times leave it where it is). The ramp is closed
    /// form, so this costs the same for a microsecond as for an hour.
    pub fn advance_to(&mut self, now: Duration) {
        self.time = self.time.max(now);
        self.update();
    }

    pub fn trip(&mut self, drive_error: u16) {
        self.machine.trip(drive_error);
        self.update();
    }

    /// What `control_word` would command now, without carrying it out.
    pub fn command_for(&self, control_word: u16) -> DeviceCommand {
        self.machine.command_for(control_word)
    }

    pub fn write_control_word(&mut self, control_word: u16, reset_blocked: bool) -> DeviceCommand {
        let before = self.machine.state();
        let command = self.machine.write_control_word(control_word, reset_blocked);
        self.update();
        let after = self.machine.state();
        if after != before {
            super::keep_recent(&mut self.commanded, (self.time, before, after));
        }
        command
    }

    /// Walks the CiA 402 state machine to `target` (switch on disabled, switched on or
    /// operation enabled), one control word per transition, for a simulated drive whose
    /// own protocol commands states rather than control words (Control Techniques' run
    /// bits, an inverter's run command codes). Tripped or braking, it waits for a reset.
    pub fn walk_to(&mut self, target: DeviceState, reset_blocked: bool) {
        for _ in 0..3 {
            let word = match (self.state(), target) {
                (from, to) if from == to => return,
                (_, DeviceState::SwitchOnDisabled) => 0,
                (DeviceState::SwitchOnDisabled, _) => 6,
                (DeviceState::ReadyToSwitchOn, _) | (DeviceState::OperationEnabled, _) => 7,
                (DeviceState::SwitchedOn, _) => 15,
                _ => return,
            };
            self.write_control_word(word, reset_blocked);
        }
    }

    /// A speed reference given as a fraction of the velocity scaling (1.0 = +100 %), as
    /// cyclic process data carries it; not range-checked, like the drive's own.
    pub fn set_speed_fraction(&mut self, fraction: f64) {
        self.setpoint_rpm = fraction * self.config.velocity_scaling_rpm;
        self.update();
    }

    /// A speed setpoint written as a parameter: refused beyond ± the maximum speed.
    pub fn set_setpoint_rpm(&mut self, rpm: f64) -> Result<(), ModelRefusal> {
        let max = self.config.max_speed_rpm.abs();
        if rpm > max {
            return Err(ModelRefusal::TooHigh);
        }
        if rpm < -max {
            return Err(ModelRefusal::TooLow);
        }
        self.setpoint_rpm = rpm;
        self.update();
        Ok(())
    }

    pub fn parameter_set(&self) -> u16 {
        self.parameter_set
    }

    /// Selects a parameter set (a spindle): refused out of range, and while enabled.
    pub fn set_parameter_set(&mut self, set: u16) -> Result<(), ModelRefusal> {
        if set > MAX_PARAMETER_SET {
            return Err(ModelRefusal::OutOfRange);
        }
        if self.state() == DeviceState::OperationEnabled {
            return Err(ModelRefusal::NotInThisState);
        }
        self.parameter_set = set;
        Ok(())
    }

    pub fn control_word(&self) -> u16 {
        self.machine.control_word()
    }

    pub fn drive_error(&self) -> u16 {
        self.machine.drive_error()
    }

    pub fn ident(&self) -> &str {
        &self.config.ident
    }

    /// DC-link voltage with its sag under load and noise.
    pub fn measured_bus_voltage_v(&mut self) -> f64 {
        BUS_VOLTAGE_V - BUS_SAG_V_PER_A * self.current_a().abs()
            + BUS_VOLTAGE_NOISE_V * self.noise.symmetric()
    }

    /// Power-stage load in percent of its rated current.
    pub fn power_stage_load_percent(&self) -> f64 {
        self.current_a().abs() / POWER_STAGE_RATED_A * 100.0
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
        match c.response {
            Some(response) if self.machine.state() == DeviceState::OperationEnabled => {
                self.motor.follow(self.time, target, response)
            }
            _ => self.motor.steer(self.time, target, rate),
        }
        let heat = if self.state().is_powered() {
            c.heating_k_per_a * self.motor.steady_current()
        } else {
            0.0
        };
        self.thermal.aim(self.time, c.ambient_c + heat);
    }

    /// Motor winding temperature in °C at the model's time.
    pub fn motor_temperature_c(&self) -> f64 {
        self.thermal.temperature_at(self.time)
    }

    fn target_rpm(&self) -> f64 {
        let max = self.config.max_speed_rpm.abs();
        self.setpoint_rpm.clamp(-max, max)
    }

    /// The CiA 402 status word of the state (the profile the model's state machine follows).
    pub fn status_word(&self) -> u16 {
        let at_target = (self.speed_rpm() - self.target_rpm()).abs() < TARGET_WINDOW_RPM;
        self.machine.status_word(at_target)
    }

    /// Actual speed as measured: noise while the motor turns or the power stage is on,
    /// an exact 0 for a motor at rest with the power stage off.
    pub fn measured_speed_rpm(&mut self) -> f64 {
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

    pub fn measured_current_a(&mut self) -> f64 {
        if self.state().is_powered() {
            self.current_a() + CURRENT_NOISE_A * self.noise.symmetric()
        } else {
            0.0
        }
    }
}

/// Why the model refuses a value (each family's front turns it into its own error code).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelRefusal {
    TooHigh,
    TooLow,
    OutOfRange,
    NotInThisState,
}

#[cfg(test)]
impl DriveModel {
    /// Switches the drive on through control words 6, 7 and 15, as a test's first step.
    pub(crate) fn enable_for_test(&mut self) {
        for cw in [6, 7, 15] {
            self.write_control_word(cw, false);
        }
        assert_eq!(self.state(), DeviceState::OperationEnabled);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn secs(s: f64) -> Duration {
        Duration::from_secs_f64(s)
    }

    #[test]
    fn measurements_at_rest_and_at_speed() {
        let mut m = DriveModel::new(SimConfig::default());
        assert_eq!(m.measured_speed_rpm(), 0.0);
        assert_eq!(m.measured_current_a(), 0.0);
        assert_eq!(m.power_stage_load_percent(), 0.0);
        let v = m.measured_bus_voltage_v();
        assert!((325.0..=325.6).contains(&v), "{v}");
        m.set_setpoint_rpm(10_000.0).unwrap();
        m.enable_for_test();
        m.advance_to(secs(10.0));
        assert!((m.measured_speed_rpm() - 10_000.0).abs() <= 0.5);
        assert!((m.measured_current_a() - 0.8).abs() <= 0.005);
        assert!((m.power_stage_load_percent() - 4.0).abs() < 1e-9);
        assert_eq!(m.status_word(), 0x0637);
    }

    #[test]
    fn setpoint_and_parameter_set_refusals() {
        let mut m = DriveModel::new(SimConfig::default());
        assert_eq!(m.set_setpoint_rpm(70_000.0), Err(ModelRefusal::TooHigh));
        assert_eq!(m.set_setpoint_rpm(-70_000.0), Err(ModelRefusal::TooLow));
        assert_eq!(m.set_parameter_set(64), Ok(()));
        assert_eq!(m.set_parameter_set(65), Err(ModelRefusal::OutOfRange));
        m.enable_for_test();
        assert_eq!(m.set_parameter_set(1), Err(ModelRefusal::NotInThisState));
        assert_eq!(m.parameter_set(), 64);
    }

    #[test]
    fn the_motor_warms_with_load_toward_ambient_plus_heating_times_current() {
        let mut m = DriveModel::new(SimConfig::default());
        assert_eq!(m.motor_temperature_c(), 25.0);
        m.set_setpoint_rpm(10_000.0).unwrap();
        m.enable_for_test();
        // 0.8 A at 10 000 rpm × 25 K/A = 20 K above 25 °C, 63 % of the way after τ = 10 min.
        m.advance_to(secs(600.0));
        let expected = 45.0 - 20.0 * (-1f64).exp();
        assert!(
            (m.motor_temperature_c() - expected).abs() < 1e-9,
            "{}",
            m.motor_temperature_c()
        );
        m.advance_to(secs(6.0 * 3600.0));
        assert!((m.motor_temperature_c() - 45.0).abs() < 1e-6);
        m.write_control_word(6, false);
        m.advance_to(secs(6.0 * 3600.0 + 600.0));
        assert!((m.motor_temperature_c() - (25.0 + 20.0 * (-1f64).exp())).abs() < 1e-6);
    }

    #[test]
    fn coasting_takes_the_speed_difference_over_the_friction_deceleration() {
        let mut m = DriveModel::new(SimConfig::default());
        m.set_setpoint_rpm(6000.0).unwrap();
        m.enable_for_test();
        m.advance_to(secs(10.0));
        m.write_control_word(6, false);
        assert_eq!(m.state(), DeviceState::ReadyToSwitchOn);
        // 300 rpm/s of friction: 6000 → 3000 rpm in 10 s, to rest in 20 s.
        m.advance_to(secs(20.0));
        assert!((m.speed_rpm() - 3000.0).abs() < 1e-9);
        m.advance_to(secs(30.0));
        assert_eq!(m.speed_rpm(), 0.0);
    }

    #[test]
    fn with_a_response_the_speed_follows_a_step_instead_of_ramping() {
        let mut m = DriveModel::new(SimConfig {
            response: Some(super::super::Response {
                time_constant_s: 0.2,
                overshoot: 0.0,
            }),
            ..SimConfig::default()
        });
        m.enable_for_test();
        m.set_setpoint_rpm(6000.0).unwrap();
        m.advance_to(secs(0.2));
        assert!((m.speed_rpm() - 6000.0 * (1.0 - (-1f64).exp())).abs() < 1e-6);
    }

    #[test]
    fn control_words_log_the_state_changes_they_make_and_a_trip_does_not() {
        let mut m = DriveModel::new(SimConfig::default());
        m.advance_to(secs(1.0));
        m.write_control_word(6, false);
        m.write_control_word(6, false);
        m.advance_to(secs(2.0));
        m.write_control_word(7, false);
        m.trip(1);
        use DeviceState::*;
        assert_eq!(
            m.commanded_changes(),
            [
                (secs(1.0), SwitchOnDisabled, ReadyToSwitchOn),
                (secs(2.0), ReadyToSwitchOn, SwitchedOn)
            ]
        );
    }

    #[test]
    fn quick_stop_at_rest_ends_at_once() {
        let mut m = DriveModel::new(SimConfig::default());
        m.enable_for_test();
        m.write_control_word(2, false);
        assert_eq!(m.state(), DeviceState::SwitchOnDisabled);
    }
}
