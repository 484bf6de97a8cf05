//! The messages of the protocol, built and read byte for byte: requests from the master
//! (read, write with or without address, the short commands) and replies from the drive
//! (a value, ACK, NAK, EOT). The same bytes mean different things in each direction (`NAK`
//! from the master reads a parameter again, from the drive it refuses a write), so each
//! direction has its own type. Pure.

use super::bcc::bcc;
use super::control::{ACK, BS, ENQ, EOT, ETX, NAK, STX};
use super::data_field::{DataValue, MAX_DATA_LEN};
use super::decode_error::DecodeError;
use super::node_address::NodeAddress;
use super::parameter::Parameter;
use crate::dictionary::WireValueError;

/// What the master sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Request {
    /// `EOT G G U U M M P P ENQ`.
    Read {
        address: NodeAddress,
        parameter: Parameter,
    },
    /// `EOT G G U U STX M M P P data ETX BCC`; without the address (`None`) it is a rewrite
    /// to the drive addressed last.
    Write {
        address: Option<NodeAddress>,
        parameter: Parameter,
        value: DataValue,
    },
    /// `NAK`: read the same parameter again.
    ReadAgain,
    /// `ACK`: read the next parameter.
    ReadNext,
    /// `BS`: read the previous parameter.
    ReadPrevious,
}

/// What a drive answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reply {
    /// `STX M M P P data ETX BCC`: the value of a parameter.
    Value { parameter: Parameter, value: DataValue },
    /// `ACK`: the write was accepted.
    Accepted,
    /// `NAK`: the write was refused (bad BCC, data too long or invalid, out of range,
    /// read-only or unknown parameter; the drive does not say which).
    Refused,
    /// `EOT`: the parameter read does not exist.
    NoSuchParameter,
}

impl Request {
    pub fn encode(&self) -> Result<Vec<u8>, WireValueError> {
        Ok(match *self {
            Request::Read { address, parameter } => {
                let mut b = vec![EOT];
                b.extend(address.wire());
                b.extend(parameter.digits());
                b.push(ENQ);
                b
            }
            Request::Write {
                address,
                parameter,
                value,
            } => {
                let mut b = Vec::with_capacity(24);
                if let Some(a) = address {
                    b.push(EOT);
                    b.extend(a.wire());
                }
                b.extend(data_block(parameter, &value.write_field()?));
                b
            }
            Request::ReadAgain => vec![NAK],
            Request::ReadNext => vec![ACK],
            Request::ReadPrevious => vec![BS],
        })
    }

    pub fn decode(bytes: &[u8]) -> Result<Request, DecodeError> {
        let first = first_byte(bytes)?;
        let single = |r: Request| single_byte(bytes).map(|()| r);
        match first {
            NAK => single(Request::ReadAgain),
            ACK => single(Request::ReadNext),
            BS => single(Request::ReadPrevious),
            STX => {
                let (parameter, value) = decode_block(bytes, 0)?;
                Ok(Request::Write {
                    address: None,
                    parameter,
                    value,
                })
            }
            EOT => {
                if bytes.len() == 1 {
                    return Err(DecodeError::Truncated {
                        have: 1,
                        expected: "the drive address (4 digits) after EOT",
                    });
                }
                let address = decode_address(bytes, 1)?;
                match bytes.get(5) {
                    Some(&STX) => {
                        let (parameter, value) = decode_block(bytes, 5)?;
                        Ok(Request::Write {
                            address: Some(address),
                            parameter,
                            value,
                        })
                    }
                    _ => {
                        let parameter = decode_parameter(bytes, 5)?;
                        expect_byte(bytes, 9, ENQ, "ENQ at the end of a read")?;
                        no_trailing(bytes, 10)?;
                        Ok(Request::Read { address, parameter })
                    }
                }
            }
            other => Err(DecodeError::Unexpected {
                offset: 0,
                expected: "EOT, STX, NAK, ACK or BS",
                actual: other,
            }),
        }
    }
}

impl Reply {
    /// A Unidrive SP reply: values always with a sign.
    pub fn encode(&self) -> Result<Vec<u8>, WireValueError> {
        Ok(match *self {
            Reply::Value { parameter, value } => data_block(parameter, &value.reply_field()?),
            Reply::Accepted => vec![ACK],
            Reply::Refused => vec![NAK],
            Reply::NoSuchParameter => vec![EOT],
        })
    }

    pub fn decode(bytes: &[u8]) -> Result<Reply, DecodeError> {
        let first = first_byte(bytes)?;
        match first {
            ACK => single_byte(bytes).map(|()| Reply::Accepted),
            NAK => single_byte(bytes).map(|()| Reply::Refused),
            EOT => single_byte(bytes).map(|()| Reply::NoSuchParameter),
            STX => {
                let (parameter, value) = decode_block(bytes, 0)?;
                Ok(Reply::Value { parameter, value })
            }
            other => Err(DecodeError::Unexpected {
                offset: 0,
                expected: "STX, ACK, NAK or EOT",
                actual: other,
            }),
        }
    }
}

/// `STX M M P P data ETX BCC`.
fn data_block(parameter: Parameter, field: &[u8]) -> Vec<u8> {
    let mut b = vec![STX];
    b.extend(parameter.digits());
    b.extend_from_slice(field);
    b.push(ETX);
    let check = bcc(&b[1..]);
    b.push(check);
    b
}

/// The byte a message starts with, which tells its kind; nothing at all is no message.
fn first_byte(bytes: &[u8]) -> Result<u8, DecodeError> {
    bytes.first().copied().ok_or(DecodeError::Empty)
}

fn single_byte(bytes: &[u8]) -> Result<(), DecodeError> {
    no_trailing(bytes, 1)
}

fn no_trailing(bytes: &[u8], end: usize) -> Result<(), DecodeError> {
    if bytes.len() > end {
        return Err(DecodeError::TrailingBytes {
            extra: bytes.len() - end,
            offset: end,
        });
    }
    Ok(())
}

fn expect_byte(bytes: &[u8], offset: usize, wanted: u8, expected: &'static str) -> Result<(), DecodeError> {
    match bytes.get(offset) {
        Some(&b) if b == wanted => Ok(()),
        Some(&actual) => Err(DecodeError::Unexpected {
            offset,
            expected,
            actual,
        }),
        None => Err(DecodeError::Truncated {
            have: bytes.len(),
            expected,
        }),
    }
}

fn digits_at(bytes: &[u8], offset: usize, n: usize, expected: &'static str) -> Result<(), DecodeError> {
    for i in offset..offset + n {
        match bytes.get(i) {
            Some(b) if b.is_ascii_digit() => {}
            Some(&actual) => {
                return Err(DecodeError::Unexpected {
                    offset: i,
                    expected,
                    actual,
                })
            }
            None => {
                return Err(DecodeError::Truncated {
                    have: bytes.len(),
                    expected,
                })
            }
        }
    }
    Ok(())
}

fn decode_address(bytes: &[u8], offset: usize) -> Result<NodeAddress, DecodeError> {
    digits_at(bytes, offset, 4, "a digit of the drive address (G G U U)")?;
    for i in [offset, offset + 2] {
        if bytes[i] != bytes[i + 1] {
            return Err(DecodeError::AddressNotDoubled {
                offset: i,
                first: bytes[i],
                second: bytes[i + 1],
            });
        }
    }
    Ok(NodeAddress {
        group: bytes[offset] - b'0',
        unit: bytes[offset + 2] - b'0',
    })
}

fn decode_parameter(bytes: &[u8], offset: usize) -> Result<Parameter, DecodeError> {
    digits_at(bytes, offset, 4, "a digit of the parameter (M M P P)")?;
    Parameter::from_digits(&bytes[offset..offset + 4]).ok_or(DecodeError::Truncated {
        have: bytes.len(),
        expected: "the parameter (M M P P)",
    })
}

/// `STX M M P P data ETX BCC` starting at `start`, which must end the message.
fn decode_block(bytes: &[u8], start: usize) -> Result<(Parameter, DataValue), DecodeError> {
    expect_byte(bytes, start, STX, "STX")?;
    let parameter = decode_parameter(bytes, start + 1)?;
    let data_start = start + 5;
    let rest = bytes.get(data_start..).unwrap_or_default();
    let Some(len) = rest.iter().position(|b| *b == ETX) else {
        if rest.len() > MAX_DATA_LEN {
            return Err(DecodeError::DataTooLong {
                len: rest.len(),
                offset: data_start,
            });
        }
        return Err(DecodeError::Truncated {
            have: bytes.len(),
            expected: "ETX and the block check",
        });
    };
    let etx = data_start + len;
    let Some(&actual) = bytes.get(etx + 1) else {
        return Err(DecodeError::Truncated {
            have: bytes.len(),
            expected: "the block check after ETX",
        });
    };
    let expected = bcc(&bytes[start + 1..=etx]);
    if actual != expected {
        return Err(DecodeError::BadBcc {
            expected,
            actual,
            offset: etx + 1,
        });
    }
    no_trailing(bytes, etx + 2)?;
    let value = DataValue::parse(&bytes[data_start..etx], data_start)?;
    Ok((parameter, value))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(text: &str) -> Parameter {
        Parameter::parse(text).unwrap()
    }

    fn a(text: &str) -> NodeAddress {
        NodeAddress::parse(text).unwrap()
    }

    /// The notes' spelling with spaces for reading: `EOT 1122 0121 ENQ`.
    fn bytes(spelled: &str) -> Vec<u8> {
        let mut out = Vec::new();
        for part in spelled.split(' ') {
            match part {
                "STX" => out.push(STX),
                "ETX" => out.push(ETX),
                "EOT" => out.push(EOT),
                "ENQ" => out.push(ENQ),
                "ACK" => out.push(ACK),
                "NAK" => out.push(NAK),
                "BS" => out.push(BS),
                text => out.extend_from_slice(text.as_bytes()),
            }
        }
        out
    }

    #[test]
    fn the_worked_examples_of_the_notes() {
        let read = Request::Read {
            address: a("1.2"),
            parameter: p("1.21"),
        };
        assert_eq!(read.encode().unwrap(), bytes("EOT 1122 0121 ENQ"));
        assert_eq!(Request::decode(&bytes("EOT 1122 0121 ENQ")), Ok(read));

        let reply = Reply::Value {
            parameter: p("1.21"),
            value: DataValue::new(-476, 1),
        };
        assert_eq!(Reply::decode(&bytes("STX 0121-47.6 ETX 7")), Ok(reply));
        assert_eq!(Reply::decode(&bytes("STX 0121-0047.6 ETX 7")), Ok(reply));

        let write = |addr: &str, param: &str, digits| Request::Write {
            address: Some(a(addr)),
            parameter: p(param),
            value: DataValue::new(digits, 1),
        };
        assert_eq!(
            write("1.2", "1.21", -345).encode().unwrap(),
            bytes("EOT 1122 STX 0121-34.5 ETX 0")
        );
        assert_eq!(
            write("1.2", "1.25", -345).encode().unwrap(),
            bytes("EOT 1122 STX 0125-34.5 ETX 4")
        );
        assert_eq!(
            Request::decode(&bytes("EOT 2266 STX 0125+076.4 ETX %")),
            Ok(write("2.6", "1.25", 764))
        );
        assert_eq!(
            Request::decode(&bytes("EOT 2266 STX 0121+076.4 ETX !")),
            Ok(write("2.6", "1.21", 764))
        );
    }

    #[test]
    fn the_printed_example_with_the_wrong_block_check_is_rejected() {
        let e = Request::decode(&bytes("EOT 2266 STX 0121+076.4 ETX 1")).unwrap_err();
        assert_eq!(
            e,
            DecodeError::BadBcc {
                expected: b'!',
                actual: b'1',
                offset: 17
            }
        );
        assert_eq!(
            e.to_string(),
            "block check: expected 0x21 (!), got 0x31 (1) at byte 17"
        );
    }

    #[test]
    fn undoubled_address_digits_are_rejected() {
        let e = Request::decode(&bytes("EOT 1222 STX 0121+1.0 ETX %")).unwrap_err();
        assert!(matches!(
            e,
            DecodeError::AddressNotDoubled {
                offset: 1,
                first: b'1',
                second: b'2'
            }
        ));
        assert!(
            e.to_string().starts_with("address digits not doubled (1 2)"),
            "{e}"
        );
    }

    #[test]
    fn short_commands_rewrites_and_single_byte_replies() {
        assert_eq!(Request::decode(&[NAK]), Ok(Request::ReadAgain));
        assert_eq!(Request::decode(&[ACK]), Ok(Request::ReadNext));
        assert_eq!(Request::decode(&[BS]), Ok(Request::ReadPrevious));
        let rewrite = Request::Write {
            address: None,
            parameter: p("1.21"),
            value: DataValue::new(15005, 1),
        };
        let b = rewrite.encode().unwrap();
        assert_eq!(b[..12], bytes("STX 01211500.5 ETX")[..]);
        assert_eq!(Request::decode(&b), Ok(rewrite));
        assert_eq!(Reply::decode(&[ACK]), Ok(Reply::Accepted));
        assert_eq!(Reply::decode(&[NAK]), Ok(Reply::Refused));
        assert_eq!(Reply::decode(&[EOT]), Ok(Reply::NoSuchParameter));
        assert_eq!(Reply::NoSuchParameter.encode().unwrap(), vec![EOT]);
    }

    #[test]
    fn a_hex_data_field_is_read_in_both_directions() {
        let mut reply = bytes("STX 0621X83 ETX");
        reply.push(bcc(&reply[1..]));
        let value = Reply::Value {
            parameter: p("6.21"),
            value: DataValue::new(131, 0),
        };
        assert_eq!(Reply::decode(&reply), Ok(value));
        let mut write = bytes("EOT 1122 STX 0642X83 ETX");
        write.push(bcc(&write[6..]));
        assert!(matches!(
            Request::decode(&write),
            Ok(Request::Write { value, .. }) if value == DataValue::new(131, 0)
        ));
        // The bad digit is named at its place in the message: STX, 4 digits, X, then `G`.
        let mut bad = bytes("STX 0621X8G ETX");
        bad.push(bcc(&bad[1..]));
        let e = Reply::decode(&bad).unwrap_err().to_string();
        assert_eq!(e, "byte 7: expected a hex digit (0-9, A-F) after X, got 'G'");
        // drivescript writes decimal only.
        let sent = Request::Write {
            address: Some(a("1.2")),
            parameter: p("6.42"),
            value: DataValue::new(131, 0),
        };
        assert_eq!(
            sent.encode().unwrap()[..14],
            bytes("EOT 1122 STX 0642131 ETX")[..]
        );
    }

    #[test]
    fn malformed_messages_say_what_and_where() {
        let cases: [(&[u8], &str); 8] = [
            (&[], "no bytes"),
            (&[0x41], "byte 0: expected EOT, STX, NAK, ACK or BS, got 'A'"),
            (&[EOT], "truncated after 1 byte(s)"),
            (
                &bytes("EOT 1122 0121 ETX"),
                "byte 9: expected ENQ at the end of a read, got ETX",
            ),
            (
                &bytes("EOT 1122 01x1 ENQ"),
                "byte 7: expected a digit of the parameter",
            ),
            (
                &bytes("EOT 1122 0121 ENQ ACK"),
                "1 byte(s) after the end of the message at byte 10",
            ),
            (&bytes("STX 0121+1234567890.5 ETX 0"), "at most 12"),
            (
                &bytes("STX 0121+1.0"),
                "truncated after 9 byte(s): expected ETX and the block check",
            ),
        ];
        for (b, want) in cases {
            let e = Request::decode(b).unwrap_err().to_string();
            assert!(e.contains(want), "{b:?}: {e}");
        }
        assert!(Reply::decode(&[ACK, ACK]).is_err());
        let e = Reply::decode(b"7").unwrap_err().to_string();
        assert_eq!(e, "byte 0: expected STX, ACK, NAK or EOT, got '7'");
    }
}
