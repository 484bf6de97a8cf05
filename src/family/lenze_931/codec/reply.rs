//! Reply lines the drive sends: reading them (`Reply::parse`, or `parse_for` a request,
//! which also takes the free-text switch-on message after `INIT!`/`RESET!`), checking that
//! a reply answers its request, and building them (for the simulated drive).

use super::decode_error::DecodeError;
use super::error_code::ErrorCode;
use super::request::{check_ascii, hex_bytes, hex_field, sdo_value, ObjectCommand, Request};
use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BootState {
    /// `SERVICE`: the boot loader is active.
    Service,
    /// `APPLICATION`: the firmware runs.
    Application,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Reply {
    /// `OK!`: written (`OW`, `BAUD`).
    Ok,
    /// `NNNN:DDDDDDDD`: an object's value (`OR`, `OI`, `ON`, `OX`).
    Value { object: u16, value: u32 },
    /// `XX:FFFFFFFF` (or `XX:FFFF FFFF`): an object command refused, or written but limited.
    Error { command: ObjectCommand, code: ErrorCode },
    /// `DONE` (`SAVE!`, `SEP!`).
    Done,
    /// `TYPE:dddd`.
    Type(String),
    /// `xxxx:VERSION:dddd`.
    Version { status: String, version: String },
    /// `xxxx:BUS:nn:bbbb:mmmm`.
    Bus {
        status: String,
        node: String,
        baud: String,
        mode: String,
    },
    /// `SERVICE` / `APPLICATION` (`BOOT?`).
    Boot(BootState),
    /// `=iiiiss:dd..` (both SDO-simulation commands).
    Sdo { index: u16, subindex: u8, data: Vec<u8> },
    /// `ERROR!`: the drive did not know the command.
    UnknownCommand,
    /// The switch-on message after `INIT!` or `RESET!` (its text is not in the sources).
    SwitchOn(String),
}

impl Reply {
    /// Reads a reply line without knowing the request. The switch-on message has no fixed
    /// form, so an unknown line is an error here; see [`Reply::parse_for`].
    pub fn parse(line: &str) -> Result<Reply, DecodeError> {
        let line = check_ascii(line)?;
        let unknown = || DecodeError::UnknownReply {
            line: line.to_string(),
        };
        match line {
            "OK!" => return Ok(Reply::Ok),
            "DONE" => return Ok(Reply::Done),
            "SERVICE" => return Ok(Reply::Boot(BootState::Service)),
            "APPLICATION" => return Ok(Reply::Boot(BootState::Application)),
            "ERROR!" => return Ok(Reply::UnknownCommand),
            _ => {}
        }
        if let Some(t) = line.strip_prefix("TYPE:") {
            return Ok(Reply::Type(t.to_string()));
        }
        if let Some(rest) = line.strip_prefix('=') {
            let (index, subindex, data) = sdo_value(rest, unknown)?;
            return Ok(Reply::Sdo {
                index,
                subindex,
                data,
            });
        }
        let parts: Vec<&str> = line.split(':').collect();
        match parts.as_slice() {
            [status, "VERSION", version] => Ok(Reply::Version {
                status: status.to_string(),
                version: version.to_string(),
            }),
            [status, "BUS", node, baud, mode] => Ok(Reply::Bus {
                status: status.to_string(),
                node: node.to_string(),
                baud: baud.to_string(),
                mode: mode.to_string(),
            }),
            [prefix, code] if ObjectCommand::from_prefix(prefix).is_some() => {
                let command = ObjectCommand::from_prefix(prefix).ok_or_else(unknown)?;
                // The manual prints the code as `FFFF FFFF`; drives are expected to send it
                // without the space. Both are read.
                let digits = match code.split_once(' ') {
                    Some((hi, lo)) if hi.len() == 4 && lo.len() == 4 => format!("{hi}{lo}"),
                    _ => code.to_string(),
                };
                let code = hex_field(&digits, 8, "the error code", 3)?;
                Ok(Reply::Error {
                    command,
                    code: ErrorCode(code),
                })
            }
            [object, value] if object.len() == 4 && object.chars().all(|c| c.is_ascii_hexdigit()) => {
                let object = hex_field(object, 4, "the object number", 0)? as u16;
                let value = hex_field(value, 8, "the value", 5)?;
                Ok(Reply::Value { object, value })
            }
            _ => Err(unknown()),
        }
    }

    /// Reads the reply to `request`: after `INIT!` or `RESET!` any printable line that is
    /// not `ERROR!` is the switch-on message.
    pub fn parse_for(request: &Request, line: &str) -> Result<Reply, DecodeError> {
        match (request, Reply::parse(line)) {
            (Request::Init | Request::Reset, Ok(Reply::UnknownCommand)) => Ok(Reply::UnknownCommand),
            (Request::Init | Request::Reset, _) => Ok(Reply::SwitchOn(check_ascii(line)?.to_string())),
            (_, parsed) => parsed,
        }
    }

    /// The line without its CR.
    pub fn text(&self) -> String {
        match self {
            Reply::Ok => "OK!".into(),
            Reply::Value { object, value } => format!("{object:04X}:{value:08X}"),
            Reply::Error { command, code } => format!("{}:{:08X}", command.prefix(), code.0),
            Reply::Done => "DONE".into(),
            Reply::Type(t) => format!("TYPE:{t}"),
            Reply::Version { status, version } => format!("{status}:VERSION:{version}"),
            Reply::Bus {
                status,
                node,
                baud,
                mode,
            } => format!("{status}:BUS:{node}:{baud}:{mode}"),
            Reply::Boot(BootState::Service) => "SERVICE".into(),
            Reply::Boot(BootState::Application) => "APPLICATION".into(),
            Reply::Sdo {
                index,
                subindex,
                data,
            } => format!("={index:04X}{subindex:02X}:{}", hex_bytes(data)),
            Reply::UnknownCommand => "ERROR!".into(),
            Reply::SwitchOn(t) => t.clone(),
        }
    }

    /// The bytes on the wire: the line and its CR.
    pub fn encode(&self) -> Vec<u8> {
        let mut bytes = self.text().into_bytes();
        bytes.push(super::CR);
        bytes
    }
}

impl fmt::Display for Reply {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text())
    }
}

/// Checks that `reply` answers `request`. `ERROR!` answers any request (the drive did not
/// know it); the caller decides what that means.
pub fn check_reply(request: &Request, reply: &Reply) -> Result<(), DecodeError> {
    let expected: String = match (request, reply) {
        (_, Reply::UnknownCommand) => return Ok(()),
        (Request::Write { .. }, Reply::Ok) => return Ok(()),
        (
            Request::Write { .. },
            Reply::Error {
                command: ObjectCommand::Write,
                ..
            },
        ) => return Ok(()),
        (Request::Write { .. }, _) => "`OK!` or `OW:` and an error code".into(),
        (Request::Read { command, object }, Reply::Value { object: o, .. }) if o == object => {
            let _ = command;
            return Ok(());
        }
        (Request::Read { command, .. }, Reply::Error { command: c, .. }) if c == command => return Ok(()),
        (Request::Read { command, object }, _) => {
            format!(
                "`{object:04X}:` and 8 hex digits, or `{}:` and an error code",
                command.prefix()
            )
        }
        (Request::Baud(_), Reply::Ok) => return Ok(()),
        (Request::Baud(_), _) => "`OK!`".into(),
        (Request::Boot, Reply::Boot(_)) => return Ok(()),
        (Request::Boot, _) => "`SERVICE` or `APPLICATION`".into(),
        (Request::Bus, Reply::Bus { .. }) => return Ok(()),
        (Request::Bus, _) => "`xxxx:BUS:nn:bbbb:mmmm`".into(),
        (Request::Init | Request::Reset, _) => return Ok(()),
        (Request::Save | Request::Sep, Reply::Done) => return Ok(()),
        (Request::Save | Request::Sep, _) => "`DONE`".into(),
        (Request::Type, Reply::Type(_)) => return Ok(()),
        (Request::Type, _) => "`TYPE:dddd`".into(),
        (Request::Version, Reply::Version { .. }) => return Ok(()),
        (Request::Version, _) => "`xxxx:VERSION:dddd`".into(),
        (
            Request::SdoWrite { index, subindex, .. } | Request::SdoRead { index, subindex },
            Reply::Sdo {
                index: i,
                subindex: s,
                ..
            },
        ) if i == index && s == subindex => return Ok(()),
        (Request::SdoWrite { index, subindex, .. } | Request::SdoRead { index, subindex }, _) => {
            format!("`={index:04X}{subindex:02X}:` and the data")
        }
    };
    Err(DecodeError::Mismatch {
        request: request.text(),
        reply: reply.text(),
        expected,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn every_reply_of_the_manual() {
        let cases: Vec<(&str, Reply)> = vec![
            ("OK!", Reply::Ok),
            (
                "0011:00000BB8",
                Reply::Value {
                    object: 0x11,
                    value: 3000,
                },
            ),
            (
                "0011:fffff448",
                Reply::Value {
                    object: 0x11,
                    value: -3000i32 as u32,
                },
            ),
            ("DONE", Reply::Done),
            ("TYPE:0931", Reply::Type("0931".into())),
            (
                "0000:VERSION:0102",
                Reply::Version {
                    status: "0000".into(),
                    version: "0102".into(),
                },
            ),
            (
                "0000:BUS:01:0500:0001",
                Reply::Bus {
                    status: "0000".into(),
                    node: "01".into(),
                    baud: "0500".into(),
                    mode: "0001".into(),
                },
            ),
            ("SERVICE", Reply::Boot(BootState::Service)),
            ("APPLICATION", Reply::Boot(BootState::Application)),
            (
                "=604100:3702",
                Reply::Sdo {
                    index: 0x6041,
                    subindex: 0,
                    data: vec![0x37, 0x02],
                },
            ),
            ("ERROR!", Reply::UnknownCommand),
        ];
        for (text, reply) in cases {
            assert_eq!(Reply::parse(text), Ok(reply.clone()), "{text}");
            assert_eq!(Reply::parse(&reply.text()), Ok(reply.clone()));
        }
    }

    #[test]
    fn every_error_code_in_both_spellings_for_every_object_command() {
        for command in ObjectCommand::ALL {
            for code in ErrorCode::ALL {
                let plain = format!("{}:{:08X}", command.prefix(), code.0);
                let spaced = format!(
                    "{}:{:04X} {:04X}",
                    command.prefix(),
                    code.0 >> 16,
                    code.0 & 0xFFFF
                );
                let expected = Reply::Error { command, code };
                assert_eq!(Reply::parse(&plain), Ok(expected.clone()), "{plain}");
                assert_eq!(Reply::parse(&spaced), Ok(expected.clone()), "{spaced}");
                assert_eq!(expected.text(), plain);
            }
        }
        assert_eq!(
            Reply::parse("OW:0000 0004"),
            Ok(Reply::Error {
                command: ObjectCommand::Write,
                code: ErrorCode::TOO_LOW_LIMITED
            })
        );
        let e = Reply::parse("OR:0004 000").unwrap_err();
        assert!(
            e.to_string()
                .contains("the error code at character 3: expected 8 hex digits"),
            "{e}"
        );
    }

    #[test]
    fn unknown_and_garbage_replies_are_refused_with_the_reason() {
        assert!(matches!(
            Reply::parse("HELLO"),
            Err(DecodeError::UnknownReply { .. })
        ));
        assert!(matches!(
            Reply::parse("0011:BB8"),
            Err(DecodeError::BadField {
                what: "the value",
                ..
            })
        ));
        assert!(matches!(
            Reply::parse("\u{1}\u{2}"),
            Err(DecodeError::NotAscii { .. })
        ));
        assert_eq!(Reply::parse("  "), Err(DecodeError::Empty));
    }

    #[test]
    fn the_switch_on_message_is_read_only_after_init_or_reset() {
        assert_eq!(
            Reply::parse_for(&Request::Reset, "931E V1.2 ready"),
            Ok(Reply::SwitchOn("931E V1.2 ready".into()))
        );
        assert_eq!(
            Reply::parse_for(&Request::Init, "ERROR!"),
            Ok(Reply::UnknownCommand)
        );
        assert!(Reply::parse_for(&Request::Type, "931E V1.2 ready").is_err());
    }

    #[test]
    fn replies_are_checked_against_their_request() {
        let read = Request::read(ObjectCommand::Read, 0x11);
        assert!(check_reply(
            &read,
            &Reply::Value {
                object: 0x11,
                value: 1
            }
        )
        .is_ok());
        assert!(check_reply(
            &read,
            &Reply::Error {
                command: ObjectCommand::Read,
                code: ErrorCode::NO_OBJECT
            }
        )
        .is_ok());
        let e = check_reply(
            &read,
            &Reply::Value {
                object: 0x12,
                value: 1,
            },
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "the reply \"0012:00000001\" does not answer \"OR:0011\": expected `0011:` and 8 hex digits, or `OR:` and an error code"
        );
        let max = Request::read(ObjectCommand::Max, 0x11);
        assert!(check_reply(
            &max,
            &Reply::Error {
                command: ObjectCommand::Read,
                code: ErrorCode::NO_OBJECT
            }
        )
        .is_err());
        let write = Request::Write {
            object: 0x10,
            value: 5,
        };
        assert!(check_reply(&write, &Reply::Ok).is_ok());
        assert!(check_reply(
            &write,
            &Reply::Value {
                object: 0x10,
                value: 5
            }
        )
        .is_err());
        assert!(check_reply(&write, &Reply::UnknownCommand).is_ok());
        assert!(check_reply(&Request::Save, &Reply::Done).is_ok());
        assert!(check_reply(&Request::Save, &Reply::Ok).is_err());
        assert!(check_reply(&Request::Type, &Reply::Type("0931".into())).is_ok());
        assert!(check_reply(&Request::Version, &Reply::Done).is_err());
        assert!(check_reply(&Request::Boot, &Reply::Boot(BootState::Service)).is_ok());
        assert!(check_reply(&Request::Bus, &Reply::Ok).is_err());
        assert!(check_reply(&Request::Baud(9600), &Reply::Ok).is_ok());
        let sdo = Request::SdoRead {
            index: 0x6041,
            subindex: 0,
        };
        assert!(check_reply(
            &sdo,
            &Reply::Sdo {
                index: 0x6041,
                subindex: 0,
                data: vec![1]
            }
        )
        .is_ok());
        assert!(check_reply(
            &sdo,
            &Reply::Sdo {
                index: 0x6040,
                subindex: 0,
                data: vec![1]
            }
        )
        .is_err());
    }

    proptest! {
        #[test]
        fn values_round_trip(object in any::<u16>(), value in any::<u32>()) {
            let r = Reply::Value { object, value };
            prop_assert_eq!(Reply::parse(&r.text()), Ok(r));
        }

        #[test]
        fn any_text_parses_or_fails_without_panic(s in "\\PC{0,40}", bytes in proptest::collection::vec(any::<u8>(), 0..40)) {
            let _ = Reply::parse(&s);
            let _ = Reply::parse_for(&Request::Init, &s);
            let _ = Reply::parse(&String::from_utf8_lossy(&bytes));
        }
    }
}
