//! The SD2 block check byte. Pure arithmetic.

/// 0xFF − (sum of `bytes`) mod 256, i.e. the one's complement of the byte sum. Pass the
/// block without its leading zero and without the check byte.
pub fn checksum(bytes: &[u8]) -> u8 {
    0xFF - bytes.iter().fold(0u8, |sum, b| sum.wrapping_add(*b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_manuals_write_example() {
        // 00 0b 02 01 0e 44 00 00 00 00 00 02 06 00 | 97
        let body = [0x0b, 0x02, 0x01, 0x0e, 0x44, 0, 0, 0, 0, 0, 0x02, 0x06, 0x00];
        assert_eq!(checksum(&body), 0x97);
        assert_eq!(checksum(&[]), 0xFF);
    }
}
