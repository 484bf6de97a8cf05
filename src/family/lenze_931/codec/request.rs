//! Request lines the PC sends: building them (with the closing CR) and reading them back
//! (for the simulated drive and `decode`).

use super::decode_error::DecodeError;
use std::fmt;

/// Most data bytes an SDO-simulation command may carry here (a CANopen expedited
/// transfer carries at most 4; the sources give no rule, see the module docs).
pub const MAX_SDO_BYTES: usize = 8;

/// The five object commands, by their two-letter prefix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ObjectCommand {
    /// `OW`: write the set value.
    Write,
    /// `OR`: read the set value.
    Read,
    /// `OI`: read the controller-internal value.
    Internal,
    /// `ON`: read the minimum.
    Min,
    /// `OX`: read the maximum.
    Max,
}

impl ObjectCommand {
    pub const ALL: [ObjectCommand; 5] = [
        ObjectCommand::Write,
        ObjectCommand::Read,
        ObjectCommand::Internal,
        ObjectCommand::Min,
        ObjectCommand::Max,
    ];

    pub fn prefix(self) -> &'static str {
        match self {
            ObjectCommand::Write => "OW",
            ObjectCommand::Read => "OR",
            ObjectCommand::Internal => "OI",
            ObjectCommand::Min => "ON",
            ObjectCommand::Max => "OX",
        }
    }

    pub fn from_prefix(text: &str) -> Option<ObjectCommand> {
        Self::ALL.into_iter().find(|c| c.prefix() == text)
    }

    /// `read the maximum of`, for messages.
    pub fn describe(self) -> &'static str {
        match self {
            ObjectCommand::Write => "write",
            ObjectCommand::Read => "read",
            ObjectCommand::Internal => "read the internal value of",
            ObjectCommand::Min => "read the minimum of",
            ObjectCommand::Max => "read the maximum of",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Request {
    /// `OW:NNNN:DDDDDDDD`.
    Write { object: u16, value: u32 },
    /// `OR:NNNN`, `OI:NNNN`, `ON:NNNN`, `OX:NNNN`.
    Read { command: ObjectCommand, object: u16 },
    /// `BAUDbbbb`.
    Baud(u32),
    /// `BOOT?`.
    Boot,
    /// `BUS?`.
    Bus,
    /// `INIT!`: load the default parameter set.
    Init,
    /// `RESET!`: hardware reset.
    Reset,
    /// `SAVE!`: save the parameter set in flash.
    Save,
    /// `SEP!`: load the parameter set from flash.
    Sep,
    /// `TYPE?`.
    Type,
    /// `VERSION?`.
    Version,
    /// `=iiiiss:dd..`: write a CANopen object.
    SdoWrite { index: u16, subindex: u8, data: Vec<u8> },
    /// `?iiiiss`: read a CANopen object.
    SdoRead { index: u16, subindex: u8 },
}

impl Request {
    /// An object command; `Write` needs a value, so it is built with [`Request::Write`].
    pub fn read(command: ObjectCommand, object: u16) -> Request {
        Request::Read { command, object }
    }

    /// The line without its CR.
    pub fn text(&self) -> String {
        match self {
            Request::Write { object, value } => format!("OW:{object:04X}:{value:08X}"),
            Request::Read { command, object } => format!("{}:{object:04X}", command.prefix()),
            Request::Baud(b) => format!("BAUD{b}"),
            Request::Boot => "BOOT?".into(),
            Request::Bus => "BUS?".into(),
            Request::Init => "INIT!".into(),
            Request::Reset => "RESET!".into(),
            Request::Save => "SAVE!".into(),
            Request::Sep => "SEP!".into(),
            Request::Type => "TYPE?".into(),
            Request::Version => "VERSION?".into(),
            Request::SdoWrite {
                index,
                subindex,
                data,
            } => format!("={index:04X}{subindex:02X}:{}", hex_bytes(data)),
            Request::SdoRead { index, subindex } => format!("?{index:04X}{subindex:02X}"),
        }
    }

    /// The bytes on the wire: the line and its CR.
    pub fn encode(&self) -> Vec<u8> {
        let mut bytes = self.text().into_bytes();
        bytes.push(super::CR);
        bytes
    }

    /// The object command this is, if any: (command, object number).
    pub fn object_command(&self) -> Option<(ObjectCommand, u16)> {
        match *self {
            Request::Write { object, .. } => Some((ObjectCommand::Write, object)),
            Request::Read { command, object } => Some((command, object)),
            _ => None,
        }
    }

    /// True when sending the request twice can do something sending it once does not:
    /// the link never repeats these after a lost reply (a second `SAVE!` writes the flash
    /// again, a second `RESET!` resets a drive that already restarted).
    pub fn is_not_repeatable(&self) -> bool {
        matches!(
            self,
            Request::Baud(_) | Request::Init | Request::Reset | Request::Save | Request::Sep
        )
    }

    /// True for requests that change the drive (writes and service commands).
    pub fn changes_the_drive(&self) -> bool {
        matches!(self, Request::Write { .. } | Request::SdoWrite { .. }) || self.is_not_repeatable()
    }

    /// `read object 0x0011`, for messages.
    pub fn describe(&self) -> String {
        match self {
            Request::Write { object, value } => {
                format!("write object 0x{object:04X} = 0x{value:08X} ({})", *value as i32)
            }
            Request::Read { command, object } => format!("{} object 0x{object:04X}", command.describe()),
            Request::Baud(b) => format!("set the baud rate to {b}"),
            Request::Boot => "ask whether the boot loader is active".into(),
            Request::Bus => "read the CAN bus status".into(),
            Request::Init => "load the default parameter set".into(),
            Request::Reset => "hardware reset".into(),
            Request::Save => "save the parameter set in flash".into(),
            Request::Sep => "load the parameter set from flash".into(),
            Request::Type => "read the device type".into(),
            Request::Version => "read the firmware version".into(),
            Request::SdoWrite {
                index,
                subindex,
                data,
            } => format!(
                "write CANopen object 0x{index:04X} subindex {subindex} = {}",
                crate::hex::to_hex(data)
            ),
            Request::SdoRead { index, subindex } => {
                format!("read CANopen object 0x{index:04X} subindex {subindex}")
            }
        }
    }

    /// Reads a request line (without its CR; surrounding whitespace is ignored).
    pub fn parse(line: &str) -> Result<Request, DecodeError> {
        let line = check_ascii(line)?;
        let unknown = || DecodeError::UnknownRequest {
            line: line.to_string(),
        };
        let fixed = match line {
            "BOOT?" => Some(Request::Boot),
            "BUS?" => Some(Request::Bus),
            "INIT!" => Some(Request::Init),
            "RESET!" => Some(Request::Reset),
            "SAVE!" => Some(Request::Save),
            "SEP!" => Some(Request::Sep),
            "TYPE?" => Some(Request::Type),
            "VERSION?" => Some(Request::Version),
            _ => None,
        };
        if let Some(r) = fixed {
            return Ok(r);
        }
        if let Some(rate) = line.strip_prefix("BAUD") {
            let baud = decimal(rate, 4, "the baud rate", 4)?;
            return Ok(Request::Baud(baud));
        }
        if let Some(rest) = line.strip_prefix('=') {
            let (index, subindex, data) = sdo_value(rest, || DecodeError::BadField {
                what: "the SDO write",
                offset: line.len(),
                expected: "`:` and the data after iiiiss".into(),
                actual: rest.to_string(),
            })?;
            return Ok(Request::SdoWrite {
                index,
                subindex,
                data,
            });
        }
        if let Some(rest) = line.strip_prefix('?') {
            let (index, subindex) = sdo_address(rest, 1)?;
            return Ok(Request::SdoRead { index, subindex });
        }
        let Some((prefix, rest)) = line.split_once(':') else {
            return Err(unknown());
        };
        let command = ObjectCommand::from_prefix(prefix).ok_or_else(unknown)?;
        if command == ObjectCommand::Write {
            let (object, value) = rest.split_once(':').ok_or_else(|| DecodeError::BadField {
                what: "the write command",
                offset: line.len(),
                expected: "OW:NNNN:DDDDDDDD".into(),
                actual: line.to_string(),
            })?;
            let object = hex_field(object, 4, "the object number", 3)? as u16;
            let value = hex_field(value, 8, "the value", 8)?;
            return Ok(Request::Write { object, value });
        }
        let object = hex_field(rest, 4, "the object number", 3)? as u16;
        Ok(Request::Read { command, object })
    }
}

impl fmt::Display for Request {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text())
    }
}

/// Trims the line and refuses anything but printable ASCII.
pub(super) fn check_ascii(line: &str) -> Result<&str, DecodeError> {
    let line = line.trim_matches(|c: char| c == ' ' || c == '\r' || c == '\n');
    if line.is_empty() {
        return Err(DecodeError::Empty);
    }
    if let Some((offset, found)) = line
        .char_indices()
        .find(|(_, c)| !(c.is_ascii_graphic() || *c == ' '))
    {
        return Err(DecodeError::NotAscii { offset, found });
    }
    Ok(line)
}

/// Exactly `digits` hex digits (either case) as a number.
pub(super) fn hex_field(
    text: &str,
    digits: usize,
    what: &'static str,
    offset: usize,
) -> Result<u32, DecodeError> {
    if text.len() != digits || !text.chars().all(|c| c.is_ascii_hexdigit()) {
        return Err(DecodeError::BadField {
            what,
            offset,
            expected: format!("{digits} hex digits"),
            actual: text.to_string(),
        });
    }
    u32::from_str_radix(text, 16).map_err(|_| DecodeError::BadField {
        what,
        offset,
        expected: format!("{digits} hex digits"),
        actual: text.to_string(),
    })
}

fn decimal(text: &str, max_digits: usize, what: &'static str, offset: usize) -> Result<u32, DecodeError> {
    if text.is_empty() || text.len() > max_digits + 2 || !text.chars().all(|c| c.is_ascii_digit()) {
        return Err(DecodeError::BadField {
            what,
            offset,
            expected: "a decimal number".into(),
            actual: text.to_string(),
        });
    }
    text.parse().map_err(|_| DecodeError::BadField {
        what,
        offset,
        expected: "a decimal number".into(),
        actual: text.to_string(),
    })
}

/// `iiiiss`: a CANopen index (4 hex digits) and subindex (2 hex digits).
pub(super) fn sdo_address(text: &str, offset: usize) -> Result<(u16, u8), DecodeError> {
    let v = hex_field(text, 6, "the CANopen index and subindex (iiiiss)", offset)?;
    Ok(((v >> 8) as u16, (v & 0xFF) as u8))
}

/// `iiiiss:dd..`, the part after the `=` of an SDO write or its reply: the object and the
/// data; `no_colon` is the error when there is no `:`.
pub(super) fn sdo_value(
    rest: &str,
    no_colon: impl FnOnce() -> DecodeError,
) -> Result<(u16, u8, Vec<u8>), DecodeError> {
    let (head, data) = rest.split_once(':').ok_or_else(no_colon)?;
    let (index, subindex) = sdo_address(head, 1)?;
    let data = parse_hex_bytes(data, 1 + head.len() + 1)?;
    Ok((index, subindex, data))
}

/// `dd..`: hex bytes, two digits each, at least one, at most [`MAX_SDO_BYTES`].
pub(super) fn parse_hex_bytes(text: &str, offset: usize) -> Result<Vec<u8>, DecodeError> {
    let bad = |expected: String| DecodeError::BadField {
        what: "the SDO data",
        offset,
        expected,
        actual: text.to_string(),
    };
    if text.is_empty() || !text.len().is_multiple_of(2) || !text.chars().all(|c| c.is_ascii_hexdigit()) {
        return Err(bad("hex bytes, two digits each".into()));
    }
    if text.len() / 2 > MAX_SDO_BYTES {
        return Err(bad(format!("at most {MAX_SDO_BYTES} bytes")));
    }
    (0..text.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&text[i..i + 2], 16).map_err(|_| bad("hex bytes".into())))
        .collect()
}

pub(super) fn hex_bytes(data: &[u8]) -> String {
    data.iter().map(|b| format!("{b:02X}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn every_request_as_the_manual_writes_it() {
        let cases: Vec<(Request, &str)> = vec![
            (
                Request::Write {
                    object: 0x10,
                    value: 3000,
                },
                "OW:0010:00000BB8",
            ),
            (
                Request::Write {
                    object: 0x10,
                    value: -3000i32 as u32,
                },
                "OW:0010:FFFFF448",
            ),
            (Request::read(ObjectCommand::Read, 0x11), "OR:0011"),
            (Request::read(ObjectCommand::Internal, 0x11), "OI:0011"),
            (Request::read(ObjectCommand::Min, 0x10), "ON:0010"),
            (Request::read(ObjectCommand::Max, 0x10), "OX:0010"),
            (Request::Baud(9600), "BAUD9600"),
            (Request::Boot, "BOOT?"),
            (Request::Bus, "BUS?"),
            (Request::Init, "INIT!"),
            (Request::Reset, "RESET!"),
            (Request::Save, "SAVE!"),
            (Request::Sep, "SEP!"),
            (Request::Type, "TYPE?"),
            (Request::Version, "VERSION?"),
            (
                Request::SdoWrite {
                    index: 0x6040,
                    subindex: 0,
                    data: vec![0x0F, 0x00],
                },
                "=604000:0F00",
            ),
            (
                Request::SdoRead {
                    index: 0x6041,
                    subindex: 0,
                },
                "?604100",
            ),
        ];
        for (request, text) in cases {
            assert_eq!(request.text(), text);
            let mut wire = text.as_bytes().to_vec();
            wire.push(b'\r');
            assert_eq!(request.encode(), wire);
            assert_eq!(Request::parse(text), Ok(request.clone()), "{text}");
        }
    }

    #[test]
    fn malformed_requests_say_what_was_expected() {
        let e = Request::parse("OR:11").unwrap_err();
        assert_eq!(
            e.to_string(),
            "the object number at character 3: expected 4 hex digits, got \"11\""
        );
        let e = Request::parse("OW:0010:BB8").unwrap_err();
        assert!(
            e.to_string()
                .contains("the value at character 8: expected 8 hex digits"),
            "{e}"
        );
        assert!(matches!(
            Request::parse("HELLO"),
            Err(DecodeError::UnknownRequest { .. })
        ));
        assert!(matches!(
            Request::parse("OQ:0010"),
            Err(DecodeError::UnknownRequest { .. })
        ));
        assert_eq!(Request::parse(""), Err(DecodeError::Empty));
        assert!(matches!(
            Request::parse("OR:00\u{7}1"),
            Err(DecodeError::NotAscii { offset: 5, .. })
        ));
        assert!(Request::parse("=604000:0").is_err());
        assert!(Request::parse("=604000:00112233445566778899")
            .unwrap_err()
            .to_string()
            .contains("at most 8 bytes"));
        assert!(Request::parse("?6041").is_err());
    }

    #[test]
    fn only_service_commands_are_not_repeatable() {
        assert!(Request::Save.is_not_repeatable());
        assert!(Request::Reset.is_not_repeatable());
        assert!(!Request::Write { object: 1, value: 1 }.is_not_repeatable());
        assert!(Request::Write { object: 1, value: 1 }.changes_the_drive());
        assert!(!Request::read(ObjectCommand::Read, 1).changes_the_drive());
    }

    proptest! {
        #[test]
        fn object_commands_round_trip(object in any::<u16>(), value in any::<u32>(), c in 0usize..5) {
            let r = match ObjectCommand::ALL[c] {
                ObjectCommand::Write => Request::Write { object, value },
                command => Request::read(command, object),
            };
            prop_assert_eq!(Request::parse(&r.text()), Ok(r));
        }

        #[test]
        fn any_text_parses_or_fails_without_panic(s in "\\PC{0,40}") {
            let _ = Request::parse(&s);
        }
    }
}
