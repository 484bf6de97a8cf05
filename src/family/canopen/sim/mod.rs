//! Simulated CANopen nodes: the SDO server they share (the Lenze 9400's simulated node uses
//! it too) and the CiA 402 drive served from an EDS.

mod sdo_server;

pub use sdo_server::{ObjectStore, Place, SdoLogged, SdoServer};
