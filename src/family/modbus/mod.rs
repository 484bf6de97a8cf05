//! Frequency inverters over Modbus RTU (RS485, or a raw serial server) and Modbus TCP:
//! the pure codec, the register notation of the dictionaries and the values in registers,
//! the link (RTU framing with its inter-frame silence and broadcast, or MBAP with
//! transaction ids), object access for the drive layer, the simulated inverter's
//! byte-level front, and the explainer for `decode` and traces. Two family ids,
//! `modbus-rtu` and `modbus-tcp`, share everything but the framing.

pub mod codec;
mod modbus_access;
mod modbus_explainer;
mod modbus_family;
mod modbus_link;
pub mod register_address;
pub mod register_value;
pub mod sim;

#[cfg(test)]
mod dictionary_tests;

pub use modbus_access::ModbusAccess;
pub use modbus_explainer::ModbusExplainer;
pub use modbus_family::ModbusFamily;
pub use modbus_link::{Framing, LinkConfig, ModbusLink};
pub use sim::ModbusSimulator;
