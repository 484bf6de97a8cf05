//! Modbus exception codes and their standard texts (Application Protocol V1.1b3,
//! section 7, "MODBUS Exception Codes" table).

use crate::family::documented_code::documented_code;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ExceptionCode(pub u8);

impl ExceptionCode {
    pub const ILLEGAL_FUNCTION: ExceptionCode = ExceptionCode(0x01);
    pub const ILLEGAL_DATA_ADDRESS: ExceptionCode = ExceptionCode(0x02);
    pub const ILLEGAL_DATA_VALUE: ExceptionCode = ExceptionCode(0x03);
    pub const SERVER_DEVICE_FAILURE: ExceptionCode = ExceptionCode(0x04);
    pub const ACKNOWLEDGE: ExceptionCode = ExceptionCode(0x05);
    pub const SERVER_DEVICE_BUSY: ExceptionCode = ExceptionCode(0x06);
    pub const MEMORY_PARITY_ERROR: ExceptionCode = ExceptionCode(0x08);
    pub const GATEWAY_PATH_UNAVAILABLE: ExceptionCode = ExceptionCode(0x0A);
    pub const GATEWAY_TARGET_FAILED: ExceptionCode = ExceptionCode(0x0B);

    /// The specification's name and meaning, or `None` for a code it does not define.
    pub fn meaning(self) -> Option<&'static str> {
        Some(match self.0 {
            0x01 => "ILLEGAL FUNCTION: the function code is not an allowable action for the server",
            0x02 => "ILLEGAL DATA ADDRESS: the data address is not an allowable address for the server",
            0x03 => "ILLEGAL DATA VALUE: a value in the request is not an allowable value for the server",
            0x04 => "SERVER DEVICE FAILURE: an unrecoverable error occurred while the server was performing the action",
            0x05 => "ACKNOWLEDGE: the server accepted the request and is processing it; it takes long",
            0x06 => "SERVER DEVICE BUSY: the server is processing a long-duration command; retry later",
            0x08 => "MEMORY PARITY ERROR: the server found a parity error in its memory",
            0x0A => "GATEWAY PATH UNAVAILABLE: the gateway could not allocate a path to the target",
            0x0B => "GATEWAY TARGET DEVICE FAILED TO RESPOND: no response was obtained from the target device",
            _ => return None,
        })
    }
}

// `exception 02 ILLEGAL DATA ADDRESS: …`.
documented_code!(
    ExceptionCode,
    "exception {:02X}",
    "not defined by the specification"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_of_the_specification_has_its_text_and_others_say_so() {
        let defined = [1u8, 2, 3, 4, 5, 6, 8, 0x0A, 0x0B];
        for code in 0..=255u8 {
            assert_eq!(
                ExceptionCode(code).meaning().is_some(),
                defined.contains(&code),
                "{code}"
            );
        }
        assert!(ExceptionCode(2)
            .to_string()
            .starts_with("exception 02 ILLEGAL DATA ADDRESS"));
        assert!(ExceptionCode(7).to_string().contains("not defined"));
    }
}
