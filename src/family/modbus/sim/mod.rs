//! The simulated inverter: its registers over the family-neutral drive model, and the
//! byte-level front that answers Modbus RTU or Modbus TCP requests with the bytes an
//! inverter sends.

mod inverter_registers;
mod modbus_simulator;

pub use inverter_registers::{InverterRegisters, RPM_PER_COUNT};
pub use modbus_simulator::ModbusSimulator;
