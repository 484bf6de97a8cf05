//! The 8 data bytes of an SDO frame, both ways: [`SdoRequest`] (client → node, on
//! 0x600 + node) and [`SdoResponse`] (node → client, on 0x580 + node). Byte 1 is the
//! command specifier, bytes 2–4 the multiplexer (index little-endian, subindex), bytes 5–8
//! a value, a length or an abort code; segments carry 7 data bytes after the command.
//! The same command byte means different things in the two directions (0x60 is an upload
//! segment request and a download response), so the direction decides the decoder. Block
//! transfers are not used by the 9400 sources and are refused with the reason. Pure.

use super::AbortCode;
use std::fmt;

/// An SDO frame always carries 8 data bytes.
pub const SDO_LEN: usize = 8;

/// What the client sends.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SdoRequest {
    /// 0x40: read (initiate upload).
    UploadInitiate { index: u16, subindex: u8 },
    /// 0x60 / 0x70: the next upload segment, toggle bit 4.
    UploadSegment { toggle: bool },
    /// 0x23 / 0x27 / 0x2B / 0x2F (size indicated) or 0x22: write up to 4 bytes at once.
    DownloadExpedited {
        index: u16,
        subindex: u8,
        data: [u8; 4],
        /// 1..=4 when indicated.
        size: Option<u8>,
    },
    /// 0x21 (size indicated) / 0x20: write in segments.
    DownloadInitiate {
        index: u16,
        subindex: u8,
        size: Option<u32>,
    },
    /// 0x00..0x1F: one download segment of 1..=7 bytes.
    DownloadSegment(Segment),
    /// 0x80 with the abort code.
    Abort {
        index: u16,
        subindex: u8,
        code: AbortCode,
    },
}

/// What the node answers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SdoResponse {
    /// 0x43 / 0x47 / 0x4B / 0x4F (size indicated) or 0x42: the value, up to 4 bytes.
    UploadExpedited {
        index: u16,
        subindex: u8,
        data: [u8; 4],
        size: Option<u8>,
    },
    /// 0x41 (size in bytes 5..8) or 0x40: the value follows in segments.
    UploadInitiate {
        index: u16,
        subindex: u8,
        size: Option<u32>,
    },
    /// 0x00..0x1F: one upload segment of 0..=7 bytes.
    UploadSegment(Segment),
    /// 0x60: the write (or its start) was accepted.
    DownloadInitiate { index: u16, subindex: u8 },
    /// 0x20 / 0x30: a download segment was accepted.
    DownloadSegment { toggle: bool },
    /// 0x80 with the abort code.
    Abort {
        index: u16,
        subindex: u8,
        code: AbortCode,
    },
}

/// A segment of a segmented transfer, laid out alike in both directions: the command
/// `000t nnnc` (toggle bit, 7 − the length, last bit), then up to seven bytes of data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Segment {
    pub toggle: bool,
    pub data: Vec<u8>,
    pub last: bool,
}

impl Segment {
    fn encode(&self) -> [u8; SDO_LEN] {
        let mut out = [0u8; SDO_LEN];
        let n = self.data.len().min(7);
        let unused = 7 - n as u8;
        out[0] = (u8::from(self.toggle) << 4) | (unused << 1) | u8::from(self.last);
        out[1..=n].copy_from_slice(&self.data[..n]);
        out
    }

    fn decode(bytes: &[u8; SDO_LEN]) -> Segment {
        let command = bytes[0];
        let unused = usize::from((command >> 1) & 0b111);
        Segment {
            toggle: command & 0x10 != 0,
            data: bytes[1..SDO_LEN - unused].to_vec(),
            last: command & 1 == 1,
        }
    }
}

/// `segment, toggle 1, 4 byte(s), last`: the direction names it (`upload segment, …`).
impl fmt::Display for Segment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "segment, toggle {}, {} byte(s){}",
            u8::from(self.toggle),
            self.data.len(),
            if self.last { ", last" } else { "" }
        )
    }
}

/// `what, n byte(s)`, or that the size is not indicated.
fn with_size(f: &mut fmt::Formatter<'_>, what: &str, size: Option<impl fmt::Display>) -> fmt::Result {
    match size {
        Some(n) => write!(f, "{what}, {n} byte(s)"),
        None => write!(f, "{what}, size not indicated"),
    }
}

/// Why 8 bytes are not a valid SDO frame: what was expected where, and what came.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SdoDecodeError {
    #[error("an SDO frame carries 8 data bytes, got {0}")]
    Length(usize),
    #[error("command byte 0x{command:02x} (byte 1): {problem}")]
    Command { command: u8, problem: &'static str },
}

fn mux(bytes: &[u8; SDO_LEN]) -> (u16, u8) {
    (u16::from_le_bytes([bytes[1], bytes[2]]), bytes[3])
}

fn value4(bytes: &[u8; SDO_LEN]) -> [u8; 4] {
    [bytes[4], bytes[5], bytes[6], bytes[7]]
}

fn with_mux(command: u8, index: u16, subindex: u8, tail: [u8; 4]) -> [u8; SDO_LEN] {
    let [lo, hi] = index.to_le_bytes();
    [command, lo, hi, subindex, tail[0], tail[1], tail[2], tail[3]]
}

/// Bits 2–3 of an expedited command: 4 − size. `None` size means "not indicated" (s = 0).
fn expedited_command(base: u8, size: Option<u8>) -> u8 {
    match size {
        Some(n) if (1..=4).contains(&n) => base | ((4 - n) << 2) | 0b11,
        _ => base | 0b10,
    }
}

fn expedited_size(command: u8) -> Option<u8> {
    (command & 1 == 1).then(|| 4 - ((command >> 2) & 0b11))
}

/// A non-expedited initiate in either direction: `base`, with bit 0 set when the size is
/// indicated (then in the four data bytes).
fn initiate_frame(base: u8, index: u16, subindex: u8, size: Option<u32>) -> [u8; SDO_LEN] {
    let command = if size.is_some() { base | 1 } else { base };
    with_mux(command, index, subindex, size.unwrap_or(0).to_le_bytes())
}

fn fixed(bytes: &[u8]) -> Result<&[u8; SDO_LEN], SdoDecodeError> {
    bytes.try_into().map_err(|_| SdoDecodeError::Length(bytes.len()))
}

/// The size an initiate frame indicates (bit 0 set), in both directions.
fn indicated_size(command: u8, bytes: &[u8; SDO_LEN]) -> Option<u32> {
    (command & 1 == 1).then(|| u32::from_le_bytes(value4(bytes)))
}

/// The code of an abort (command specifier 4), which is 0x80 in both directions.
fn abort_code(command: u8, bytes: &[u8; SDO_LEN]) -> Result<AbortCode, SdoDecodeError> {
    match command {
        0x80 => Ok(AbortCode(u32::from_le_bytes(value4(bytes)))),
        _ => Err(refuse(command, "an abort is 0x80")),
    }
}

/// Command specifiers 5 and 6, in both directions.
fn block_transfer(command: u8) -> SdoDecodeError {
    refuse(
        command,
        "block transfers (command specifier 5 and 6) are not supported",
    )
}

fn refuse(command: u8, problem: &'static str) -> SdoDecodeError {
    SdoDecodeError::Command { command, problem }
}

impl SdoRequest {
    pub fn encode(&self) -> [u8; SDO_LEN] {
        match self {
            SdoRequest::UploadInitiate { index, subindex } => with_mux(0x40, *index, *subindex, [0; 4]),
            SdoRequest::UploadSegment { toggle } => [0x60 | (u8::from(*toggle) << 4), 0, 0, 0, 0, 0, 0, 0],
            SdoRequest::DownloadExpedited {
                index,
                subindex,
                data,
                size,
            } => with_mux(expedited_command(0x20, *size), *index, *subindex, *data),
            SdoRequest::DownloadInitiate {
                index,
                subindex,
                size,
            } => initiate_frame(0x20, *index, *subindex, *size),
            SdoRequest::DownloadSegment(segment) => segment.encode(),
            SdoRequest::Abort {
                index,
                subindex,
                code,
            } => with_mux(0x80, *index, *subindex, code.to_bytes()),
        }
    }

    pub fn decode(bytes: &[u8]) -> Result<SdoRequest, SdoDecodeError> {
        let b = fixed(bytes)?;
        let command = b[0];
        let (index, subindex) = mux(b);
        Ok(match command >> 5 {
            0 => SdoRequest::DownloadSegment(Segment::decode(b)),
            1 if command & 0x10 != 0 => {
                return Err(refuse(command, "bit 4 must be 0 in an initiate download request"))
            }
            1 if command & 0b10 != 0 => SdoRequest::DownloadExpedited {
                index,
                subindex,
                data: value4(b),
                size: expedited_size(command),
            },
            1 => SdoRequest::DownloadInitiate {
                index,
                subindex,
                size: indicated_size(command, b),
            },
            2 if command & 0x1F == 0 => SdoRequest::UploadInitiate { index, subindex },
            2 => return Err(refuse(command, "a read request is 0x40; the low bits must be 0")),
            3 if command & 0x0F == 0 => SdoRequest::UploadSegment {
                toggle: command & 0x10 != 0,
            },
            3 => return Err(refuse(command, "an upload segment request is 0x60 or 0x70")),
            4 => SdoRequest::Abort {
                index,
                subindex,
                code: abort_code(command, b)?,
            },
            _ => return Err(block_transfer(command)),
        })
    }

    /// The multiplexer the request names (`None` for segments).
    pub fn object(&self) -> Option<(u16, u8)> {
        match *self {
            SdoRequest::UploadInitiate { index, subindex }
            | SdoRequest::DownloadExpedited { index, subindex, .. }
            | SdoRequest::DownloadInitiate { index, subindex, .. }
            | SdoRequest::Abort { index, subindex, .. } => Some((index, subindex)),
            SdoRequest::UploadSegment { .. } | SdoRequest::DownloadSegment(_) => None,
        }
    }
}

impl SdoResponse {
    pub fn encode(&self) -> [u8; SDO_LEN] {
        match self {
            SdoResponse::UploadExpedited {
                index,
                subindex,
                data,
                size,
            } => with_mux(expedited_command(0x40, *size), *index, *subindex, *data),
            SdoResponse::UploadInitiate {
                index,
                subindex,
                size,
            } => initiate_frame(0x40, *index, *subindex, *size),
            SdoResponse::UploadSegment(segment) => segment.encode(),
            SdoResponse::DownloadInitiate { index, subindex } => with_mux(0x60, *index, *subindex, [0; 4]),
            SdoResponse::DownloadSegment { toggle } => [0x20 | (u8::from(*toggle) << 4), 0, 0, 0, 0, 0, 0, 0],
            SdoResponse::Abort {
                index,
                subindex,
                code,
            } => with_mux(0x80, *index, *subindex, code.to_bytes()),
        }
    }

    pub fn decode(bytes: &[u8]) -> Result<SdoResponse, SdoDecodeError> {
        let b = fixed(bytes)?;
        let command = b[0];
        let (index, subindex) = mux(b);
        Ok(match command >> 5 {
            0 => SdoResponse::UploadSegment(Segment::decode(b)),
            1 if command & 0x0F == 0 => SdoResponse::DownloadSegment {
                toggle: command & 0x10 != 0,
            },
            1 => return Err(refuse(command, "a download segment response is 0x20 or 0x30")),
            2 if command & 0x10 != 0 => return Err(refuse(command, "bit 4 must be 0 in a read response")),
            2 if command & 0b10 != 0 => SdoResponse::UploadExpedited {
                index,
                subindex,
                data: value4(b),
                size: expedited_size(command),
            },
            2 => SdoResponse::UploadInitiate {
                index,
                subindex,
                size: indicated_size(command, b),
            },
            3 if command == 0x60 => SdoResponse::DownloadInitiate { index, subindex },
            3 => return Err(refuse(command, "a write response is 0x60")),
            4 => SdoResponse::Abort {
                index,
                subindex,
                code: abort_code(command, b)?,
            },
            _ => return Err(block_transfer(command)),
        })
    }

    /// The multiplexer the response names (`None` for segments).
    pub fn object(&self) -> Option<(u16, u8)> {
        match *self {
            SdoResponse::UploadExpedited { index, subindex, .. }
            | SdoResponse::UploadInitiate { index, subindex, .. }
            | SdoResponse::DownloadInitiate { index, subindex }
            | SdoResponse::Abort { index, subindex, .. } => Some((index, subindex)),
            SdoResponse::UploadSegment(_) | SdoResponse::DownloadSegment { .. } => None,
        }
    }
}

impl fmt::Display for SdoRequest {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SdoRequest::UploadInitiate { .. } => f.write_str("read request"),
            SdoRequest::UploadSegment { toggle } => {
                write!(f, "upload segment request, toggle {}", u8::from(*toggle))
            }
            SdoRequest::DownloadExpedited { size, .. } => with_size(f, "write request", *size),
            SdoRequest::DownloadInitiate { size, .. } => with_size(f, "segmented write request", *size),
            SdoRequest::DownloadSegment(segment) => write!(f, "download {segment}"),
            SdoRequest::Abort { code, .. } => write!(f, "abort {code}"),
        }
    }
}

impl fmt::Display for SdoResponse {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SdoResponse::UploadExpedited { size, .. } => with_size(f, "read response", *size),
            SdoResponse::UploadInitiate { size, .. } => with_size(f, "read response, segmented", *size),
            SdoResponse::UploadSegment(segment) => write!(f, "upload {segment}"),
            SdoResponse::DownloadInitiate { .. } => f.write_str("write response (accepted)"),
            SdoResponse::DownloadSegment { toggle } => {
                write!(f, "download segment response, toggle {}", u8::from(*toggle))
            }
            SdoResponse::Abort { code, .. } => write!(f, "abort {code}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hex::{parse_hex, to_hex};
    use proptest::prelude::*;

    #[test]
    fn the_manuals_worked_examples_byte_for_byte() {
        // Firmware read C00099 of node 12.
        let read = SdoRequest::UploadInitiate {
            index: 0x5F9C,
            subindex: 0,
        };
        assert_eq!(to_hex(&read.encode()), "40 9c 5f 00 00 00 00 00");
        assert_eq!(
            SdoResponse::decode(&parse_hex("41 9c 5f 00 0b 00 00 00").unwrap()),
            Ok(SdoResponse::UploadInitiate {
                index: 0x5F9C,
                subindex: 0,
                size: Some(11)
            })
        );
        // Heatsink temperature C00061 of node 5: 43 °C.
        assert_eq!(
            SdoResponse::decode(&parse_hex("43 c2 5f 00 2b 00 00 00").unwrap()),
            Ok(SdoResponse::UploadExpedited {
                index: 0x5FC2,
                subindex: 0,
                data: [0x2b, 0, 0, 0],
                size: Some(4)
            })
        );
        // Write C00088 = 102: the corrected bytes (the manuals print 66 00 03 00).
        let write = SdoRequest::DownloadExpedited {
            index: 0x5FA7,
            subindex: 0,
            data: 102u32.to_le_bytes(),
            size: Some(4),
        };
        assert_eq!(to_hex(&write.encode()), "23 a7 5f 00 66 00 00 00");
        assert_ne!(to_hex(&write.encode()), "23 a7 5f 00 66 00 03 00");
        assert_eq!(
            SdoResponse::decode(&parse_hex("60 a7 5f 00 00 00 00 00").unwrap()),
            Ok(SdoResponse::DownloadInitiate {
                index: 0x5FA7,
                subindex: 0
            })
        );
        assert_eq!(
            SdoResponse::decode(&parse_hex("80 9c 5f 00 41 00 04 06").unwrap()),
            Ok(SdoResponse::Abort {
                index: 0x5F9C,
                subindex: 0,
                code: AbortCode(0x0604_0041)
            })
        );
    }

    #[test]
    fn size_bits_of_expedited_transfers() {
        for (size, command) in [
            (Some(4), 0x43),
            (Some(3), 0x47),
            (Some(2), 0x4B),
            (Some(1), 0x4F),
            (None, 0x42),
        ] {
            let r = SdoResponse::UploadExpedited {
                index: 1,
                subindex: 0,
                data: [0; 4],
                size,
            };
            assert_eq!(r.encode()[0], command);
            assert_eq!(SdoResponse::decode(&r.encode()), Ok(r));
        }
        for (size, command) in [(Some(4), 0x23), (Some(2), 0x2B), (Some(1), 0x2F), (None, 0x22)] {
            let r = SdoRequest::DownloadExpedited {
                index: 1,
                subindex: 0,
                data: [0; 4],
                size,
            };
            assert_eq!(r.encode()[0], command);
        }
    }

    #[test]
    fn segments_carry_seven_bytes_less_the_unused_ones() {
        let last = SdoResponse::UploadSegment(Segment {
            toggle: true,
            data: b".yy3".to_vec(),
            last: true,
        });
        // 3 unused bytes → n = 3, bit 0 last, toggle 1: 0001 0111.
        assert_eq!(last.encode()[0], 0x17);
        assert_eq!(SdoResponse::decode(&last.encode()), Ok(last));
        assert_eq!(
            SdoRequest::UploadSegment { toggle: true }.encode(),
            [0x70, 0, 0, 0, 0, 0, 0, 0]
        );
    }

    #[test]
    fn wrong_lengths_and_block_transfers_are_refused_with_the_reason() {
        assert_eq!(SdoResponse::decode(&[0x43, 0, 0]), Err(SdoDecodeError::Length(3)));
        let e = SdoResponse::decode(&[0xC0, 0, 0, 0, 0, 0, 0, 0]).unwrap_err();
        assert!(e.to_string().contains("block transfers"), "{e}");
        assert!(SdoResponse::decode(&[0x61, 0, 0, 0, 0, 0, 0, 0]).is_err());
    }

    proptest! {
        #[test]
        fn response_decoder_never_panics_and_round_trips(bytes in proptest::collection::vec(any::<u8>(), 0..12)) {
            if let Ok(r) = SdoResponse::decode(&bytes) {
                // Unused bytes of a segment and reserved value bytes may differ; the
                // decoded meaning must not.
                prop_assert_eq!(SdoResponse::decode(&r.encode()), Ok(r));
            }
            if let Ok(r) = SdoRequest::decode(&bytes) {
                prop_assert_eq!(SdoRequest::decode(&r.encode()), Ok(r));
            }
        }
    }
}
