//! CRC-16/MODBUS (Serial Line V1.02, 6.2.2): preset 0xFFFF, reflected polynomial 0xA001,
//! no final XOR; the frame carries it low byte first.

/// The CRC of `bytes` as a number (the frame sends `crc as u8` first, then `crc >> 8`).
pub fn crc16(bytes: &[u8]) -> u16 {
    let mut crc: u16 = 0xFFFF;
    for &b in bytes {
        crc ^= u16::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    crc
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Serial Line V1.02, 6.2.2, Figure 30 (p. 39): the CRC of `02 07` is 0x1241, sent `41 12`.
    #[test]
    fn the_serial_line_specifications_example() {
        assert_eq!(crc16(&[0x02, 0x07]), 0x1241);
    }

    /// The catalogue check value of CRC-16/MODBUS (shared/protocols/modbus.md).
    #[test]
    fn the_check_value_of_123456789() {
        assert_eq!(crc16(b"123456789"), 0x4B37);
    }
}
