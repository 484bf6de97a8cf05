//! The block check character: XOR of every byte after STX up to and including ETX, moved
//! up by 0x20 when it would be a control character. Pure.

/// The check byte for `covered` (the bytes after STX, ETX included).
pub fn bcc(covered: &[u8]) -> u8 {
    let x = covered.iter().fold(0u8, |acc, b| acc ^ b);
    if x < 0x20 {
        x + 0x20
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn worked_examples_of_the_notes() {
        assert_eq!(bcc(b"0121-47.6\x03"), b'7');
        assert_eq!(bcc(b"0121-0047.6\x03"), b'7');
        assert_eq!(bcc(b"0121-34.5\x03"), b'0');
        assert_eq!(bcc(b"0125-34.5\x03"), b'4');
        assert_eq!(bcc(b"0125+076.4\x03"), b'%');
        // The UD70 manual prints `1` here; the XOR is 0x01, so the check byte is `!`.
        assert_eq!(bcc(b"0121+076.4\x03"), b'!');
    }
}
