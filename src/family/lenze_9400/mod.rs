//! The Lenze 9400 family: parameter access over CANopen SDO on the "CAN on board" system
//! bus. The pure codec, the link (one transfer at a time over a shared frame bus), object
//! access for the drive layer, the simulated node's frame-level front, and the explainer
//! for `decode` and traces.

pub mod codec;
