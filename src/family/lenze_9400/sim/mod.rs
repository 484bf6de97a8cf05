//! The simulated Lenze 9400 node: an SDO server in front of the family-neutral drive
//! model, answering real CAN frames on 0x600 + node with real frames on 0x580 + node.

mod lenze_9400_simulator;
mod sim_codes;

pub use lenze_9400_simulator::{Lenze9400Simulator, FIRMWARE_VERSION};
