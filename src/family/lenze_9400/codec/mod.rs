//! The Lenze 9400's codes and their CANopen index (`C00099` is index 0x5F9C), and the
//! CANopen SDO codec it speaks (the generic family's, re-exported). No I/O, no clock.

mod code;

pub use crate::family::canopen::codec::*;
pub use code::{Code, CODE_BASE};
