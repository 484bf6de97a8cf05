//! Modbus exception codes and their standard texts (Application Protocol V1.1b3,
//! section 7, "MODBUS Exception Codes" table).

use crate::family::documented_code::{code_table, documented_code};

code_table! {
    pub struct ExceptionCode(pub u8);
    ILLEGAL_FUNCTION = 0x01 => "ILLEGAL FUNCTION: the function code is not an allowable action for the server",
    ILLEGAL_DATA_ADDRESS = 0x02 => "ILLEGAL DATA ADDRESS: the data address is not an allowable address for the server",
    ILLEGAL_DATA_VALUE = 0x03 => "ILLEGAL DATA VALUE: a value in the request is not an allowable value for the server",
    SERVER_DEVICE_FAILURE = 0x04 => "SERVER DEVICE FAILURE: an unrecoverable error occurred while the server was performing the action",
    ACKNOWLEDGE = 0x05 => "ACKNOWLEDGE: the server accepted the request and is processing it; it takes long",
    SERVER_DEVICE_BUSY = 0x06 => "SERVER DEVICE BUSY: the server is processing a long-duration command; retry later",
    MEMORY_PARITY_ERROR = 0x08 => "MEMORY PARITY ERROR: the server found a parity error in its memory",
    GATEWAY_PATH_UNAVAILABLE = 0x0A => "GATEWAY PATH UNAVAILABLE: the gateway could not allocate a path to the target",
    GATEWAY_TARGET_FAILED = 0x0B => "GATEWAY TARGET DEVICE FAILED TO RESPOND: no response was obtained from the target device",
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
