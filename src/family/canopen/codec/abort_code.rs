//! CiA 301 SDO abort codes: the 32-bit code an abort frame carries (bytes 5..8,
//! little-endian) and its meaning. Only the codes the protocol notes name are given a text;
//! any other code is shown as a number and said to be unnamed, never guessed. Pure.

use crate::family::documented_code::{code_table, documented_code};

code_table! {
    /// A CiA 301 SDO abort code. The table is CiA 301's (V4.2.0, 7.2.4.3.17, the SDO abort
    /// codes): every code it lists.
    pub struct AbortCode(pub u32);
    TOGGLE_BIT = 0x0503_0000 => "toggle bit not alternated",
    TIMEOUT = 0x0504_0000 => "SDO protocol timed out",
    INVALID_COMMAND = 0x0504_0001 => "client/server command specifier not valid or unknown",
    0x0504_0002 => "invalid block size (block mode only)",
    0x0504_0003 => "invalid sequence number (block mode only)",
    0x0504_0004 => "CRC error (block mode only)",
    0x0504_0005 => "out of memory",
    0x0601_0000 => "unsupported access to an object",
    WRITE_ONLY = 0x0601_0001 => "attempt to read a write-only object",
    READ_ONLY = 0x0601_0002 => "attempt to write a read-only object",
    OBJECT_DOES_NOT_EXIST = 0x0602_0000 => "object does not exist in the object dictionary",
    0x0604_0041 => "object cannot be mapped to the PDO",
    0x0604_0042 => "the number and length of the objects to be mapped would exceed the PDO length",
    0x0604_0043 => "general parameter incompatibility reason",
    0x0604_0047 => "general internal incompatibility in the device",
    0x0606_0000 => "access failed due to a hardware error",
    LENGTH_MISMATCH = 0x0607_0010 => "data type does not match, length of service parameter does not match",
    0x0607_0012 => "data type does not match, length of service parameter too high",
    0x0607_0013 => "data type does not match, length of service parameter too low",
    SUBINDEX_DOES_NOT_EXIST = 0x0609_0011 => "subindex does not exist",
    VALUE_RANGE_EXCEEDED = 0x0609_0030 => "value range of parameter exceeded",
    VALUE_TOO_HIGH = 0x0609_0031 => "value of parameter written too high",
    VALUE_TOO_LOW = 0x0609_0032 => "value of parameter written too low",
    0x0609_0036 => "maximum value is less than minimum value",
    0x060A_0023 => "resource not available: SDO connection",
    GENERAL_ERROR = 0x0800_0000 => "general error",
    0x0800_0020 => "data cannot be transferred or stored to the application",
    0x0800_0021 => "data cannot be transferred or stored to the application because of local control",
    DEVICE_STATE = 0x0800_0022 => "data cannot be transferred or stored because of the present device state",
    0x0800_0023 => "object dictionary dynamic generation fails or no object dictionary is present",
    0x0800_0024 => "no data available",
}

impl AbortCode {
    /// The four bytes as they travel in bytes 5..8 of an abort frame.
    pub fn to_bytes(self) -> [u8; 4] {
        self.0.to_le_bytes()
    }
}

// `0x06040041 object cannot be mapped to the PDO`.
documented_code!(
    AbortCode,
    "0x{:08X}",
    "an abort code drivescript does not name; see the device manual or CiA 301"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_printed_abort_travels_little_endian() {
        // Protocol notes: abort code 0x06040041 travels as `41 00 04 06`.
        assert_eq!(AbortCode(0x0604_0041).to_bytes(), [0x41, 0x00, 0x04, 0x06]);
        assert_eq!(
            AbortCode(0x0602_0000).to_string(),
            "0x06020000 object does not exist in the object dictionary"
        );
        assert!(AbortCode(0x1234_5678).to_string().contains("does not name"));
    }

    #[test]
    fn every_abort_code_of_cia_301_is_named() {
        // The table's codes, as python-canopen's SdoAbortedError lists them too.
        let table = [
            0x0503_0000,
            0x0504_0000,
            0x0504_0001,
            0x0504_0002,
            0x0504_0003,
            0x0504_0004,
            0x0504_0005,
            0x0601_0000,
            0x0601_0001,
            0x0601_0002,
            0x0602_0000,
            0x0604_0041,
            0x0604_0042,
            0x0604_0043,
            0x0604_0047,
            0x0606_0000,
            0x0607_0010,
            0x0607_0012,
            0x0607_0013,
            0x0609_0011,
            0x0609_0030,
            0x0609_0031,
            0x0609_0032,
            0x0609_0036,
            0x060A_0023,
            0x0800_0000,
            0x0800_0020,
            0x0800_0021,
            0x0800_0022,
            0x0800_0023,
            0x0800_0024,
        ];
        for code in table {
            assert!(AbortCode(code).meaning().is_some(), "0x{code:08X} is not named");
        }
        assert_eq!(
            AbortCode(0x060A_0023).to_string(),
            "0x060A0023 resource not available: SDO connection"
        );
    }
}
