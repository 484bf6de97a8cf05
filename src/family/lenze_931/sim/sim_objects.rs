//! The simulated 931's object table: the simulator's own numbers (not the real drive's,
//! which the sources do not give), each with its type, limits and how it maps onto the
//! drive model. `dictionary/lenze-931.yaml`'s template, completed with these numbers, is
//! what the tests run recipes with.

use super::super::codec::ErrorCode;
use crate::drive::device_control::DeviceState;
use crate::sim::{DriveModel, ModelRefusal};

/// Largest speed setpoint the simulated drive stores (either sign), rpm.
pub const MAX_SPEED_RPM: i64 = 6000;
/// Largest operating mode (the model's parameter set).
pub const MAX_MODE: i64 = 3;
/// The control-word values the simulated drive accepts (the CiA 402 command table).
const COMMANDS: [i64; 6] = [0, 2, 6, 7, 15, 128];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SimObject {
    /// 0x0001 `rs232_stat_sum`: the manual's status-word bits.
    StatusSum,
    /// 0x0010 speed setpoint, rpm, ±6000, limited beyond.
    SpeedSetpoint,
    /// 0x0011 actual speed, rpm.
    SpeedActual,
    /// 0x0012 motor current, mA.
    CurrentActual,
    /// 0x0013 DC bus voltage, 0.1 V.
    BusVoltage,
    /// 0x0014 operating mode 0..=3, refused beyond, not while enabled.
    Mode,
    /// 0x0020 device-control command word (the CiA 402 values; a simulator choice).
    ControlWord,
    /// 0x0021 device-control status word (the model's CiA 402 status word).
    StatusWord,
    /// 0x0022 the drive error code.
    DriveError,
}

impl SimObject {
    pub const ALL: [SimObject; 9] = [
        SimObject::StatusSum,
        SimObject::SpeedSetpoint,
        SimObject::SpeedActual,
        SimObject::CurrentActual,
        SimObject::BusVoltage,
        SimObject::Mode,
        SimObject::ControlWord,
        SimObject::StatusWord,
        SimObject::DriveError,
    ];

    pub fn number(self) -> u16 {
        match self {
            SimObject::StatusSum => 0x0001,
            SimObject::SpeedSetpoint => 0x0010,
            SimObject::SpeedActual => 0x0011,
            SimObject::CurrentActual => 0x0012,
            SimObject::BusVoltage => 0x0013,
            SimObject::Mode => 0x0014,
            SimObject::ControlWord => 0x0020,
            SimObject::StatusWord => 0x0021,
            SimObject::DriveError => 0x0022,
        }
    }

    pub fn find(number: u16) -> Option<SimObject> {
        Self::ALL.into_iter().find(|o| o.number() == number)
    }

    /// The minimum and maximum `ON`/`OX` report; `None` where the drive has none.
    pub fn limits(self) -> (Option<i64>, Option<i64>) {
        match self {
            SimObject::SpeedSetpoint => (Some(-MAX_SPEED_RPM), Some(MAX_SPEED_RPM)),
            SimObject::Mode => (Some(0), Some(MAX_MODE)),
            SimObject::ControlWord => (Some(0), Some(0xFFFF)),
            _ => (None, None),
        }
    }

    fn writable(self) -> bool {
        matches!(
            self,
            SimObject::SpeedSetpoint | SimObject::Mode | SimObject::ControlWord
        )
    }

    /// The set value (`OR`).
    pub fn read(self, model: &mut DriveModel) -> i64 {
        match self {
            SimObject::StatusSum => i64::from(status_sum(model)),
            SimObject::SpeedSetpoint => model.setpoint_rpm().round() as i64,
            SimObject::SpeedActual => model.measured_speed_rpm().round() as i64,
            SimObject::CurrentActual => (model.measured_current_a() * 1000.0).round() as i64,
            SimObject::BusVoltage => (model.measured_bus_voltage_v() * 10.0).round() as i64,
            SimObject::Mode => i64::from(model.parameter_set()),
            SimObject::ControlWord => i64::from(model.control_word()),
            SimObject::StatusWord => i64::from(model.status_word()),
            SimObject::DriveError => i64::from(model.drive_error()),
        }
    }

    /// The controller-internal value (`OI`): the drive computes the speed in internal
    /// units of 1/4 rpm toward zero, so it may differ slightly from the set value.
    pub fn internal(self, model: &mut DriveModel) -> i64 {
        match self {
            SimObject::SpeedSetpoint => (model.setpoint_rpm() * 4.0).trunc() as i64 / 4,
            other => other.read(model),
        }
    }

    /// Writes `value` (the signed 32-bit reading of the wire value). `Ok(None)`: stored;
    /// `Ok(Some(code))`: stored limited (code 4 or 5); `Err(code)`: refused.
    pub fn write(
        self,
        model: &mut DriveModel,
        value: i64,
        reset_blocked: bool,
    ) -> Result<Option<ErrorCode>, ErrorCode> {
        if !self.writable() {
            return Err(ErrorCode::READ_ONLY);
        }
        match self {
            SimObject::SpeedSetpoint => {
                let stored = value.clamp(-MAX_SPEED_RPM, MAX_SPEED_RPM);
                model
                    .set_setpoint_rpm(stored as f64)
                    .map_err(|_| ErrorCode::TOO_HIGH)?;
                Ok(match value {
                    v if v > MAX_SPEED_RPM => Some(ErrorCode::TOO_HIGH_LIMITED),
                    v if v < -MAX_SPEED_RPM => Some(ErrorCode::TOO_LOW_LIMITED),
                    _ => None,
                })
            }
            SimObject::Mode => {
                if value > MAX_MODE {
                    return Err(ErrorCode::TOO_HIGH);
                }
                if value < 0 {
                    return Err(ErrorCode::TOO_LOW);
                }
                match model.set_parameter_set(value as u16) {
                    Ok(()) => Ok(None),
                    Err(ModelRefusal::NotInThisState) => Err(ErrorCode::BIT_IN_MODE),
                    Err(_) => Err(ErrorCode::TOO_HIGH),
                }
            }
            SimObject::ControlWord => {
                if !COMMANDS.contains(&value) {
                    return Err(ErrorCode::BIT_CONSTANT);
                }
                model.write_control_word(value as u16, reset_blocked);
                Ok(None)
            }
            _ => Err(ErrorCode::READ_ONLY),
        }
    }
}

/// The manual's status bits as the model's state gives them.
pub fn status_sum(model: &DriveModel) -> u32 {
    let state = model.state();
    let speed = model.speed_rpm();
    let at_setpoint = state == DeviceState::OperationEnabled
        && (speed
            - model
                .setpoint_rpm()
                .clamp(-(MAX_SPEED_RPM as f64), MAX_SPEED_RPM as f64))
        .abs()
            < 1.0;
    let mut bits = 0u32;
    let mut set = |bit: u32, on: bool| {
        if on {
            bits |= 1 << bit;
        }
    };
    set(5, at_setpoint);
    set(9, at_setpoint);
    set(13, speed.abs() < 1.0);
    set(14, state.is_powered());
    set(
        15,
        matches!(
            state,
            DeviceState::ReadyToSwitchOn | DeviceState::SwitchedOn | DeviceState::OperationEnabled
        ),
    );
    set(
        17,
        matches!(state, DeviceState::Fault | DeviceState::FaultReactionActive),
    );
    set(24, state == DeviceState::OperationEnabled);
    bits
}
