//! Modbus as pure functions: the PDU of functions 03, 04, 06, 16 and 23 with the
//! specification's quantity limits, every exception code with its standard text, RTU
//! framing (slave, PDU, CRC-16 low byte first; the inter-frame silence) and the MBAP header
//! of Modbus TCP. No I/O, no clock.
//!
//! Sources: MODBUS Application Protocol Specification V1.1b3 (PDUs, section 6; exceptions,
//! section 7), MODBUS over Serial Line Specification and Implementation Guide V1.02 (RTU
//! framing 2.5.1, timing 2.5.1.1, CRC 6.2.2), MODBUS Messaging on TCP/IP Implementation
//! Guide V1.0b (MBAP 3.1.3); restated in shared/protocols/modbus.md.
//!
//! Written here rather than taken from `rmodbus`: its client builds a request and parses the
//! reply to that request only, and its server answers from its own register context; the
//! explainer and the simulator need to read any request or reply from bytes alone, and the
//! link needs the RTU frame length from the first bytes to cut a reply out of a stream.

mod codec_error;
mod crc;
mod exception;
pub mod mbap;
mod pdu;
pub mod rtu;

pub use codec_error::CodecError;
pub use crc::crc16;
pub use exception::ExceptionCode;
pub use pdu::{Function, Request, Response};
