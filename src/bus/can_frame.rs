//! One CAN frame: an 11-bit (or 29-bit extended) identifier and up to 8 data bytes. Plain
//! data for frame buses; what the identifier means is the family's business. Also the
//! frame's text forms (candump `60C#409C5F0000000000`, a candump log line, or `ID data…`)
//! and the byte string that observers and explainers, which take bytes, receive.

use super::CanFrameTextError;

/// A classic CAN data frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CanFrame {
    pub id: u32,
    pub extended: bool,
    len: u8,
    data: [u8; 8],
}

impl CanFrame {
    /// A standard (11-bit) frame; `None` when the identifier or the data do not fit.
    pub fn new(id: u32, data: &[u8]) -> Option<CanFrame> {
        Self::build(id, false, data)
    }

    /// A standard frame of 8 data bytes; the identifier is cut to its 11 bits.
    pub fn standard8(id: u32, data: [u8; 8]) -> CanFrame {
        CanFrame {
            id: id & 0x7FF,
            extended: false,
            len: 8,
            data,
        }
    }

    /// An extended (29-bit) frame.
    pub fn extended(id: u32, data: &[u8]) -> Option<CanFrame> {
        Self::build(id, true, data)
    }

    fn build(id: u32, extended: bool, data: &[u8]) -> Option<CanFrame> {
        let max_id = if extended { 0x1FFF_FFFF } else { 0x7FF };
        if id > max_id || data.len() > 8 {
            return None;
        }
        let mut bytes = [0u8; 8];
        bytes[..data.len()].copy_from_slice(data);
        Some(CanFrame {
            id,
            extended,
            len: data.len() as u8,
            data: bytes,
        })
    }

    pub fn data(&self) -> &[u8] {
        &self.data[..usize::from(self.len)]
    }
}

/// Bit 31 of the identifier word in [`CanFrame::to_bytes`]: an extended frame.
const EXTENDED_FLAG: u32 = 0x8000_0000;

impl CanFrame {
    /// The frame as one byte string for observers and explainers: the identifier as 4
    /// bytes big-endian (bit 31 set for an extended frame), then the data.
    pub fn to_bytes(&self) -> Vec<u8> {
        let word = self.id | if self.extended { EXTENDED_FLAG } else { 0 };
        let mut out = word.to_be_bytes().to_vec();
        out.extend_from_slice(self.data());
        out
    }

    /// The inverse of [`to_bytes`](Self::to_bytes); `None` when `bytes` is no such string.
    pub fn from_bytes(bytes: &[u8]) -> Option<CanFrame> {
        let (word, data) = bytes.split_first_chunk::<4>()?;
        let word = u32::from_be_bytes(*word);
        if word & EXTENDED_FLAG != 0 {
            Self::extended(word & !EXTENDED_FLAG, data)
        } else {
            Self::new(word, data)
        }
    }

    /// candump's compact form: `60C#409C5F0000000000` (8 hex digits of identifier for an
    /// extended frame).
    pub fn to_candump(&self) -> String {
        let mut out = if self.extended {
            format!("{:08X}#", self.id)
        } else {
            format!("{:03X}#", self.id)
        };
        for b in self.data() {
            out.push_str(&format!("{b:02X}"));
        }
        out
    }

    /// Reads a frame as engineers paste it: candump's `60C#409C5F00…`, a candump log line
    /// `(1700000000.123456) can0 60C#409C…`, or `60C 40 9C 5F 00 …` (identifier, then data
    /// bytes in any hex form). Identifiers of more than 3 digits are extended. The error
    /// says what is wrong where.
    pub fn parse_text(text: &str) -> Result<CanFrame, CanFrameTextError> {
        let mut t = text.trim();
        if t.starts_with('(') {
            // A candump log line: the timestamp and the interface name come first;
            // anything after the frame is not read.
            t = t
                .split_whitespace()
                .nth(2)
                .ok_or_else(|| CanFrameTextError::LogLine {
                    line: text.to_string(),
                })?;
        }
        let (id_text, data_text) = match t.split_once('#') {
            Some((id, data)) => (id.trim(), data.trim()),
            None => t
                .split_once(char::is_whitespace)
                .map(|(id, data)| (id, data.trim()))
                .unwrap_or((t, "")),
        };
        if data_text.starts_with('R') || data_text.starts_with('#') {
            return Err(CanFrameTextError::NoData { frame: t.to_string() });
        }
        let hex_id = id_text
            .strip_prefix("0x")
            .or_else(|| id_text.strip_prefix("0X"))
            .unwrap_or(id_text);
        if hex_id.is_empty() || hex_id.len() > 8 || !hex_id.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(CanFrameTextError::Identifier {
                id: id_text.to_string(),
            });
        }
        let id = u32::from_str_radix(hex_id, 16).map_err(|source| CanFrameTextError::IdentifierValue {
            id: id_text.to_string(),
            source,
        })?;
        let data = if data_text.is_empty() {
            Vec::new()
        } else {
            crate::hex::parse_hex(data_text).map_err(|source| CanFrameTextError::Data {
                data: data_text.to_string(),
                source,
            })?
        };
        if data.len() > 8 {
            return Err(CanFrameTextError::TooLong(data.len()));
        }
        let frame = if hex_id.len() > 3 {
            CanFrame::extended(id, &data)
        } else {
            CanFrame::new(id, &data)
        };
        frame.ok_or(CanFrameTextError::Not11Bits(id))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn text_forms() {
        let f = CanFrame::new(0x60C, &[0x40, 0x9C, 0x5F, 0, 0, 0, 0, 0]).unwrap();
        assert_eq!(f.to_candump(), "60C#409C5F0000000000");
        for text in [
            "60C#409C5F0000000000",
            "60c#409c5f0000000000",
            "(1700000000.123456) can0 60C#409C5F0000000000",
            "(1700000000.123456)  can0   60C#409C5F0000000000  # a note",
            "60C 40 9c 5f 00 00 00 00 00",
            "0x60C 409C5F0000000000",
        ] {
            assert_eq!(CanFrame::parse_text(text), Ok(f), "{text}");
        }
        for (text, says) in [
            ("60C#R", "remote"),
            ("XYZ#00", "not a CAN identifier"),
            ("800#00", "11 bits"),
            ("601#000102030405060708", "at most 8"),
        ] {
            let e = CanFrame::parse_text(text).unwrap_err().to_string();
            assert!(e.contains(says), "{text}: {e}");
        }
        assert_eq!(
            CanFrame::parse_text("800#00"),
            Err(CanFrameTextError::Not11Bits(0x800))
        );
        let ext = CanFrame::parse_text("18FF0001#01").unwrap();
        assert!(ext.extended);
        assert_eq!(ext.to_candump(), "18FF0001#01");
    }

    proptest! {
        #[test]
        fn bytes_and_candump_round_trip(id in 0u32..0x800, ext_id in 0u32..0x2000_0000, extended: bool, data in proptest::collection::vec(any::<u8>(), 0..=8)) {
            let f = if extended { CanFrame::extended(ext_id, &data) } else { CanFrame::new(id, &data) }.unwrap();
            prop_assert_eq!(CanFrame::from_bytes(&f.to_bytes()), Some(f));
            prop_assert_eq!(CanFrame::parse_text(&f.to_candump()), Ok(f));
        }

        #[test]
        fn any_text_is_parsed_or_refused(text in "\\PC{0,40}") {
            let _ = CanFrame::parse_text(&text);
        }
    }

    #[test]
    fn identifiers_and_lengths_are_checked() {
        let f = CanFrame::new(0x601, &[0x40, 0x63, 0x5f, 0x00]).unwrap();
        assert_eq!(
            (f.id, f.extended, f.data()),
            (0x601, false, &[0x40, 0x63, 0x5f, 0x00][..])
        );
        assert!(CanFrame::new(0x800, &[]).is_none());
        assert!(CanFrame::extended(0x800, &[]).is_some());
        assert!(CanFrame::new(1, &[0; 9]).is_none());
    }
}
