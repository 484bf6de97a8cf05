//! CiA 301 emergency (EMCY) frames, pure: identifier 0x80 + node, 8 bytes of error code
//! (little-endian), error register (0x1001) and five manufacturer bytes; and the texts of
//! the error codes, CiA 301's classes with the CiA 402 drive codes refining them. A code
//! not in the table is named by its class (`0x23xx`: current, device output side).

/// The identifier of `node`'s EMCY frames: 0x80 + node.
pub fn emcy_id(node: u8) -> u32 {
    0x80 + u32::from(node)
}

/// One EMCY frame's content.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Emcy {
    pub code: u16,
    pub register: u8,
    pub manufacturer: [u8; 5],
}

impl Emcy {
    /// `None` unless `data` is the 8 bytes of an EMCY frame.
    pub fn decode(data: &[u8]) -> Option<Emcy> {
        let d: &[u8; 8] = data.try_into().ok()?;
        Some(Emcy {
            code: u16::from_le_bytes([d[0], d[1]]),
            register: d[2],
            manufacturer: [d[3], d[4], d[5], d[6], d[7]],
        })
    }

    /// Error code 0x0000: the node's errors were reset.
    pub fn is_reset(&self) -> bool {
        self.code == 0
    }
}

/// Specific codes first, then the classes (`mask` 0xFFF0, 0xFF00, 0xF000) they belong to.
const TEXTS: [(u16, u16, &str); 37] = [
    (0x0000, 0xFFFF, "error reset or no error"),
    (0x2220, 0xFFFF, "continuous over-current inside the device"),
    (0x2310, 0xFFFF, "continuous over-current (output side)"),
    (0x3110, 0xFFFF, "mains over-voltage"),
    (0x3120, 0xFFFF, "mains under-voltage"),
    (0x3130, 0xFFFF, "mains phase failure"),
    (0x3210, 0xFFFF, "DC link over-voltage"),
    (0x3220, 0xFFFF, "DC link under-voltage"),
    (0x4210, 0xFFFF, "device temperature too high"),
    (0x7121, 0xFFFF, "motor blocked"),
    (0x8110, 0xFFFF, "CAN overrun (objects lost)"),
    (0x8120, 0xFFFF, "CAN in error passive mode"),
    (0x8130, 0xFFFF, "life guard or heartbeat error"),
    (0x8140, 0xFFFF, "recovered from bus off"),
    (0x8150, 0xFFFF, "CAN-ID collision"),
    (0x2100, 0xFF00, "current, device input side"),
    (0x2200, 0xFF00, "current inside the device"),
    (0x2300, 0xFF00, "current, device output side"),
    (0x3100, 0xFF00, "mains voltage"),
    (0x3200, 0xFF00, "voltage inside the device"),
    (0x3300, 0xFF00, "output voltage"),
    (0x4100, 0xFF00, "ambient temperature"),
    (0x4200, 0xFF00, "device temperature"),
    (0x4300, 0xFF00, "drive temperature"),
    (0x6100, 0xFF00, "internal software"),
    (0x6200, 0xFF00, "user software"),
    (0x6300, 0xFF00, "data set"),
    (0x8100, 0xFF00, "communication"),
    (0x8200, 0xFF00, "protocol error"),
    (0xFF00, 0xFF00, "device specific"),
    (0x1000, 0xF000, "generic error"),
    (0x2000, 0xF000, "current"),
    (0x3000, 0xF000, "voltage"),
    (0x4000, 0xF000, "temperature"),
    (0x5000, 0xF000, "device hardware"),
    (0x6000, 0xF000, "device software"),
    (0x8000, 0xF000, "monitoring"),
];

/// The text of an error code: its own when the table has it, else its class's
/// (`0x2350 current, device output side`), else `unknown error code`.
pub fn error_code_text(code: u16) -> &'static str {
    TEXTS.iter().find(|(c, mask, _)| code & mask == *c).map_or(
        match code >> 12 {
            0x7 => "additional modules",
            0x9 => "external error",
            0xF => "additional functions",
            _ => "unknown error code",
        },
        |(_, _, t)| t,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_and_texts() {
        let e = Emcy::decode(&[0x10, 0x32, 0x05, 1, 2, 3, 4, 5]).unwrap();
        assert_eq!(
            (e.code, e.register, e.manufacturer),
            (0x3210, 0x05, [1, 2, 3, 4, 5])
        );
        assert!(Emcy::decode(&[0; 7]).is_none());
        assert!(Emcy::decode(&[0; 8]).unwrap().is_reset());
        assert_eq!(error_code_text(0x3210), "DC link over-voltage");
        assert_eq!(error_code_text(0x2350), "current, device output side");
        assert_eq!(error_code_text(0x5123), "device hardware");
        assert_eq!(error_code_text(0x7305), "additional modules");
        assert_eq!(error_code_text(0xFF42), "device specific");
        assert_eq!(error_code_text(0xA000), "unknown error code");
        assert_eq!(emcy_id(5), 0x85);
    }
}
