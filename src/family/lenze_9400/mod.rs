//! The Lenze 9400 family: parameter access over CANopen SDO on the "CAN on board" system
//! bus, in the 9400's code notation (`C00099`). The SDO link and object access are the
//! generic CANopen family's (`family::canopen`); here are the codes, the family's
//! notation, the simulated node's codes and the explainer for `decode` and traces.

pub mod codec;
mod lenze_9400_family;
pub mod sim;

pub use lenze_9400_family::{LENZE_9400_FAMILY, LENZE_EXPLAIN, LENZE_NOTATION};
