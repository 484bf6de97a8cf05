//! The protocol's control characters, and how bytes are shown to people: control
//! characters by name (`STX`), printable text as it is, anything else in hex. Pure.

pub const STX: u8 = 0x02;
pub const ETX: u8 = 0x03;
pub const EOT: u8 = 0x04;
pub const ENQ: u8 = 0x05;
pub const ACK: u8 = 0x06;
pub const BS: u8 = 0x08;
pub const NAK: u8 = 0x15;

/// The name of a control character of the protocol.
pub fn control_name(byte: u8) -> Option<&'static str> {
    Some(match byte {
        STX => "STX",
        ETX => "ETX",
        EOT => "EOT",
        ENQ => "ENQ",
        ACK => "ACK",
        BS => "BS",
        NAK => "NAK",
        _ => return None,
    })
}

/// One byte for a message: `STX`, `'7'`, `0x9f`.
pub fn show_byte(byte: u8) -> String {
    match control_name(byte) {
        Some(name) => name.to_string(),
        None if byte.is_ascii_graphic() || byte == b' ' => format!("'{}'", byte as char),
        None => format!("0x{byte:02x}"),
    }
}

/// Bytes as the manuals print them: control characters by name, runs of printable text
/// together, other bytes in hex: `EOT 1122 0121 ENQ` is shown `EOT 11220121 ENQ`.
pub fn show_bytes(bytes: &[u8]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut text = String::new();
    for &b in bytes {
        if (b.is_ascii_graphic() || b == b' ') && control_name(b).is_none() {
            text.push(b as char);
            continue;
        }
        if !text.is_empty() {
            parts.push(std::mem::take(&mut text));
        }
        parts.push(match control_name(b) {
            Some(name) => name.to_string(),
            None => format!("0x{b:02x}"),
        });
    }
    if !text.is_empty() {
        parts.push(text);
    }
    parts.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_are_shown_with_control_names() {
        let read = [EOT, b'1', b'1', b'2', b'2', b'0', b'1', b'2', b'1', ENQ];
        assert_eq!(show_bytes(&read), "EOT 11220121 ENQ");
        assert_eq!(show_bytes(&[ACK, NAK, BS, 0xff]), "ACK NAK BS 0xff");
        assert_eq!(show_byte(b'!'), "'!'");
        assert_eq!(show_byte(STX), "STX");
        assert_eq!(show_byte(0x7f), "0x7f");
    }
}
