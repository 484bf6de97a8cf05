//! Frequency inverters over Modbus RTU (RS485) and Modbus TCP: the pure codec.

pub mod codec;
