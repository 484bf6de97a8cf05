//! The registers of the simulated inverter: the Sunfar E500's Modbus map (E500 Series
//! User Manual, Appendix II, section 3, pp. 89-90: run command 0x1001, frequency setting
//! 0x1002 in 0.1 Hz, inverter status 0x2000, fault message 0x2001, monitoring 0xD000
//! running frequency and 0xD001 output current, shown by the examples on p. 91), the
//! stored parameter F0.08 (0xF008), and the two registers the template dictionary puts
//! where a manual would give them (0x2100 software version, 0x2101 DC bus voltage): the
//! simulator's own, no inverter's. What a read returns and what a write does to the drive
//! model; no bytes here.

use crate::drive::device_control::{DeviceCommand, DeviceState};
use crate::sim::{DriveModel, FaultInjection};

pub const RUN_COMMAND: u16 = 0x1001;
pub const FREQUENCY_SETTING: u16 = 0x1002;
pub const STATUS: u16 = 0x2000;
pub const FAULT: u16 = 0x2001;
pub const SOFTWARE_VERSION: u16 = 0x2100;
pub const BUS_VOLTAGE: u16 = 0x2101;
pub const RUNNING_FREQUENCY: u16 = 0xD000;
pub const OUTPUT_CURRENT: u16 = 0xD001;
/// F0.08 carrier frequency in 0.1 kHz (p. 83; register rule p. 89), stored only.
pub const CARRIER_FREQUENCY: u16 = 0xF008;

/// Run command codes (p. 89).
const RUN_FORWARD: u16 = 0x0001;
const RUN_REVERSE: u16 = 0x0002;
const STOP: u16 = 0x0003;
const FAULT_RESET: u16 = 0x0020;

/// 0.1 Hz is 6 rpm for a motor with one pole pair (rpm = Hz × 60 / pole pairs): the
/// simulated motor's.
pub const RPM_PER_COUNT: f64 = 6.0;
/// At speed within this of the setpoint (the simulator's choice).
const AT_SPEED_RPM: f64 = 3.0;

/// Why a request is refused: the exception code a drive sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// 02: no such register.
    Address,
    /// 03: a value the register does not take.
    Value,
}

#[derive(Debug, Clone, Default)]
pub struct InverterRegisters {
    run_command: u16,
    /// F0.08; `None` until written: the factory 8.0 kHz.
    carrier: Option<u16>,
    frequency: u16,
    reverse: bool,
}

impl InverterRegisters {
    pub fn run_command(&self) -> u16 {
        self.run_command
    }

    /// The status code of 0x2000 (p. 89-90).
    pub fn status(model: &DriveModel) -> u16 {
        let speed = model.speed_rpm();
        let set = model.setpoint_rpm();
        match model.state() {
            DeviceState::Fault | DeviceState::FaultReactionActive => 0x0020,
            DeviceState::NotReadyToSwitchOn => 0x0000,
            DeviceState::OperationEnabled | DeviceState::QuickStopActive => {
                let reverse = u16::from(set < 0.0 || (set == 0.0 && speed < 0.0));
                if (speed - set).abs() <= AT_SPEED_RPM {
                    0x0001 + reverse
                } else if speed.abs() < set.abs() {
                    0x0011 + reverse
                } else {
                    0x0014 + reverse
                }
            }
            _ if speed.abs() > AT_SPEED_RPM => 0x0014 + u16::from(speed < 0.0),
            _ => 0x0003,
        }
    }

    pub fn read(&self, model: &mut DriveModel, register: u16) -> Result<u16, Refusal> {
        let counts = |rpm: f64| (rpm.abs() / RPM_PER_COUNT).round().min(f64::from(u16::MAX)) as u16;
        Ok(match register {
            RUN_COMMAND => self.run_command,
            FREQUENCY_SETTING => self.frequency,
            STATUS => Self::status(model),
            FAULT => model.drive_error(),
            SOFTWARE_VERSION => 100,
            BUS_VOLTAGE => model.measured_bus_voltage_v().round() as u16,
            RUNNING_FREQUENCY => counts(model.measured_speed_rpm()),
            OUTPUT_CURRENT => (model.measured_current_a() * 10.0).round().max(0.0) as u16,
            CARRIER_FREQUENCY => self.carrier.unwrap_or(80),
            _ => return Err(Refusal::Address),
        })
    }

    /// Writes one register; `Some(command)` when it commands the drive (the front decides
    /// whether an injected fault makes the drive ignore it).
    pub fn write(
        &mut self,
        model: &mut DriveModel,
        register: u16,
        value: u16,
    ) -> Result<Option<DeviceCommand>, Refusal> {
        match register {
            RUN_COMMAND => {
                let command = match value {
                    RUN_FORWARD | RUN_REVERSE => DeviceCommand::EnableOperation,
                    STOP => DeviceCommand::DisableOperation,
                    FAULT_RESET => DeviceCommand::FaultReset,
                    _ => return Err(Refusal::Value),
                };
                self.run_command = value;
                if matches!(value, RUN_FORWARD | RUN_REVERSE) {
                    self.reverse = value == RUN_REVERSE;
                    self.apply_setpoint(model)?;
                }
                Ok(Some(command))
            }
            CARRIER_FREQUENCY => {
                self.carrier = Some(value);
                Ok(None)
            }
            FREQUENCY_SETTING => {
                self.frequency = value;
                self.apply_setpoint(model)?;
                Ok(None)
            }
            STATUS | FAULT | SOFTWARE_VERSION | BUS_VOLTAGE | RUNNING_FREQUENCY | OUTPUT_CURRENT => {
                Err(Refusal::Address)
            }
            _ => Err(Refusal::Address),
        }
    }

    fn apply_setpoint(&self, model: &mut DriveModel) -> Result<(), Refusal> {
        let rpm = f64::from(self.frequency) * RPM_PER_COUNT;
        let signed = if self.reverse { -rpm } else { rpm };
        model.set_setpoint_rpm(signed).map_err(|_| Refusal::Value)
    }

    /// Carries out `command` on the CiA 402 model one transition at a time.
    pub fn command(model: &mut DriveModel, faults: &FaultInjection, command: DeviceCommand) {
        let blocked = faults.is_fault_reset_blocked();
        if command == DeviceCommand::FaultReset {
            if model.state() == DeviceState::Fault {
                model.write_control_word(0, blocked);
                model.write_control_word(0x80, blocked);
            }
            return;
        }
        let target = if command == DeviceCommand::EnableOperation {
            DeviceState::OperationEnabled
        } else {
            DeviceState::SwitchedOn
        };
        model.walk_to(target, blocked);
    }
}
