//! The PDUs of the register functions (Application Protocol V1.1b3, section 6): read
//! holding registers (03), read input registers (04), write single register (06), write
//! multiple registers (16), read/write multiple registers (23), and the exception response
//! (function + 0x80, one code byte, section 7). Register values are big-endian.

use super::{CodecError, ExceptionCode};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Function {
    ReadHolding,
    ReadInput,
    WriteSingle,
    WriteMultiple,
    ReadWrite,
}

impl Function {
    pub const ALL: [Function; 5] = [
        Function::ReadHolding,
        Function::ReadInput,
        Function::WriteSingle,
        Function::WriteMultiple,
        Function::ReadWrite,
    ];

    pub fn code(self) -> u8 {
        match self {
            Function::ReadHolding => 0x03,
            Function::ReadInput => 0x04,
            Function::WriteSingle => 0x06,
            Function::WriteMultiple => 0x10,
            Function::ReadWrite => 0x17,
        }
    }

    pub fn of(code: u8) -> Result<Function, CodecError> {
        Function::ALL
            .into_iter()
            .find(|f| f.code() == code)
            .ok_or(CodecError::Function(code))
    }

    pub fn name(self) -> &'static str {
        match self {
            Function::ReadHolding => "read holding registers",
            Function::ReadInput => "read input registers",
            Function::WriteSingle => "write single register",
            Function::WriteMultiple => "write multiple registers",
            Function::ReadWrite => "read/write multiple registers",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Request {
    /// 03 or 04: `count` registers from `start`.
    Read {
        function: Function,
        start: u16,
        count: u16,
    },
    WriteSingle {
        address: u16,
        value: u16,
    },
    WriteMultiple {
        start: u16,
        values: Vec<u16>,
    },
    ReadWrite {
        read_start: u16,
        read_count: u16,
        write_start: u16,
        values: Vec<u16>,
    },
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Response {
    /// The values a 03, 04 or 23 read.
    Registers {
        function: Function,
        values: Vec<u16>,
    },
    WriteSingle {
        address: u16,
        value: u16,
    },
    WriteMultiple {
        start: u16,
        count: u16,
    },
    Exception {
        function: u8,
        code: ExceptionCode,
    },
}

fn word(b: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([b[at], b[at + 1]])
}

fn push_words(out: &mut Vec<u8>, words: &[u16]) {
    for w in words {
        out.extend_from_slice(&w.to_be_bytes());
    }
}

fn words(b: &[u8]) -> Vec<u16> {
    b.chunks_exact(2)
        .map(|c| u16::from_be_bytes([c[0], c[1]]))
        .collect()
}

fn quantity(what: &'static str, value: usize, max: usize, allowed: &'static str) -> Result<(), CodecError> {
    if (1..=max).contains(&value) {
        Ok(())
    } else {
        Err(CodecError::Quantity { what, value, allowed })
    }
}

/// `what` is at least `least` bytes long.
fn at_least(what: &'static str, b: &[u8], least: usize) -> Result<(), CodecError> {
    if b.len() >= least {
        return Ok(());
    }
    Err(CodecError::Length {
        what,
        len: b.len(),
        expected: format!("at least {least}"),
    })
}

fn length(what: &'static str, b: &[u8], expected: usize) -> Result<(), CodecError> {
    if b.len() == expected {
        Ok(())
    } else {
        Err(CodecError::Length {
            what,
            len: b.len(),
            expected: expected.to_string(),
        })
    }
}

/// The registers a writing request carries after its header of `header` bytes: the byte
/// before them counts them, and the word two bytes before that counts the registers (6.12,
/// 6.17); both must agree with what came.
fn written_words(b: &[u8], header: usize) -> Result<Vec<u16>, CodecError> {
    at_least("the request PDU", b, header)?;
    let count = usize::from(word(b, header - 3));
    let data = &b[header..];
    if usize::from(b[header - 1]) != data.len() || data.len() != count * 2 {
        return Err(CodecError::ByteCount {
            count: b[header - 1].into(),
            actual: data.len(),
        });
    }
    Ok(words(data))
}

/// Reads of at most 125 registers, writes of at most 123, 23 writing at most 121
/// (Application Protocol V1.1b3, 6.3, 6.4, 6.12, 6.17).
const MAX_READ: usize = 125;
const MAX_WRITE: usize = 123;
const MAX_READ_WRITE: usize = 121;

impl Request {
    pub fn function(&self) -> Function {
        match self {
            Request::Read { function, .. } => *function,
            Request::WriteSingle { .. } => Function::WriteSingle,
            Request::WriteMultiple { .. } => Function::WriteMultiple,
            Request::ReadWrite { .. } => Function::ReadWrite,
        }
    }

    /// Whether the request changes the drive (a broadcast may carry only these).
    pub fn writes(&self) -> bool {
        !matches!(self, Request::Read { .. })
    }

    /// The PDU, or why the specification forbids this request.
    pub fn encode(&self) -> Result<Vec<u8>, CodecError> {
        let mut out = vec![self.function().code()];
        match self {
            Request::Read {
                function,
                start,
                count,
            } => {
                if !matches!(function, Function::ReadHolding | Function::ReadInput) {
                    return Err(CodecError::Function(function.code()));
                }
                quantity("the quantity of registers", (*count).into(), MAX_READ, "1..=125")?;
                push_words(&mut out, &[*start, *count]);
            }
            Request::WriteSingle { address, value } => push_words(&mut out, &[*address, *value]),
            Request::WriteMultiple { start, values } => {
                quantity("the quantity of registers", values.len(), MAX_WRITE, "1..=123")?;
                push_words(&mut out, &[*start, values.len() as u16]);
                out.push((values.len() * 2) as u8);
                push_words(&mut out, values);
            }
            Request::ReadWrite {
                read_start,
                read_count,
                write_start,
                values,
            } => {
                quantity("the quantity to read", (*read_count).into(), MAX_READ, "1..=125")?;
                quantity("the quantity to write", values.len(), MAX_READ_WRITE, "1..=121")?;
                push_words(
                    &mut out,
                    &[*read_start, *read_count, *write_start, values.len() as u16],
                );
                out.push((values.len() * 2) as u8);
                push_words(&mut out, values);
            }
        }
        Ok(out)
    }

    /// The PDU's length from its first bytes, for cutting requests out of a stream:
    /// `None` while too few bytes have come to tell.
    pub fn length_from(prefix: &[u8]) -> Option<Result<usize, CodecError>> {
        let code = *prefix.first()?;
        Some(match Function::of(code) {
            Err(e) => Err(e),
            Ok(Function::ReadHolding | Function::ReadInput | Function::WriteSingle) => Ok(5),
            Ok(Function::WriteMultiple) => Ok(6 + usize::from(*prefix.get(5)?)),
            Ok(Function::ReadWrite) => Ok(10 + usize::from(*prefix.get(9)?)),
        })
    }

    pub fn decode(b: &[u8]) -> Result<Request, CodecError> {
        at_least("the request PDU", b, 1)?;
        let code = b[0];
        let function = Function::of(code)?;
        let request = match function {
            Function::ReadHolding | Function::ReadInput => {
                length("the request PDU", b, 5)?;
                Request::Read {
                    function,
                    start: word(b, 1),
                    count: word(b, 3),
                }
            }
            Function::WriteSingle => {
                length("the request PDU", b, 5)?;
                Request::WriteSingle {
                    address: word(b, 1),
                    value: word(b, 3),
                }
            }
            // The values first: their check is the one of the PDU's length.
            Function::WriteMultiple => {
                let values = written_words(b, 6)?;
                Request::WriteMultiple {
                    start: word(b, 1),
                    values,
                }
            }
            Function::ReadWrite => {
                let values = written_words(b, 10)?;
                Request::ReadWrite {
                    read_start: word(b, 1),
                    read_count: word(b, 3),
                    write_start: word(b, 5),
                    values,
                }
            }
        };
        // What encodes is what the specification allows: the same check both ways.
        request.encode()?;
        Ok(request)
    }

    /// Whether `response` answers this request; the error says what was expected.
    pub fn check(&self, response: &Response) -> Result<(), CodecError> {
        let code = self.function().code();
        match (self, response) {
            (_, Response::Exception { function, .. }) if *function == code => Ok(()),
            (Request::Read { function, count, .. }, Response::Registers { function: f, values })
                if f == function && values.len() == usize::from(*count) =>
            {
                Ok(())
            }
            (
                Request::ReadWrite { read_count, .. },
                Response::Registers {
                    function: Function::ReadWrite,
                    values,
                },
            ) if values.len() == usize::from(*read_count) => Ok(()),
            (Request::WriteSingle { address, value }, Response::WriteSingle { address: a, value: v })
                if a == address && v == value =>
            {
                Ok(())
            }
            (Request::WriteMultiple { start, values }, Response::WriteMultiple { start: s, count })
                if s == start && usize::from(*count) == values.len() =>
            {
                Ok(())
            }
            _ => Err(CodecError::NotTheAnswer {
                function: self.function().name(),
                expected: self.expected(),
            }),
        }
    }

    fn expected(&self) -> String {
        match self {
            Request::Read { count, .. }
            | Request::ReadWrite {
                read_count: count, ..
            } => {
                format!("{count} register(s)")
            }
            Request::WriteSingle { address, value } => format!("the echo of register {address} = {value}"),
            Request::WriteMultiple { start, values } => format!("start {start}, quantity {}", values.len()),
        }
    }
}

impl Response {
    pub fn encode(&self) -> Vec<u8> {
        match self {
            Response::Registers { function, values } => {
                let mut out = vec![function.code(), (values.len() * 2) as u8];
                push_words(&mut out, values);
                out
            }
            Response::WriteSingle { address, value } => {
                let mut out = vec![Function::WriteSingle.code()];
                push_words(&mut out, &[*address, *value]);
                out
            }
            Response::WriteMultiple { start, count } => {
                let mut out = vec![Function::WriteMultiple.code()];
                push_words(&mut out, &[*start, *count]);
                out
            }
            Response::Exception { function, code } => vec![function | 0x80, code.0],
        }
    }

    /// The PDU's length from its first bytes, for cutting a reply out of a stream.
    pub fn length_from(prefix: &[u8]) -> Option<Result<usize, CodecError>> {
        let code = *prefix.first()?;
        if code & 0x80 != 0 {
            return Some(Ok(2));
        }
        Some(match Function::of(code) {
            Err(e) => Err(e),
            Ok(Function::ReadHolding | Function::ReadInput | Function::ReadWrite) => {
                Ok(2 + usize::from(*prefix.get(1)?))
            }
            Ok(Function::WriteSingle | Function::WriteMultiple) => Ok(5),
        })
    }

    pub fn decode(b: &[u8]) -> Result<Response, CodecError> {
        at_least("the reply PDU", b, 1)?;
        let code = b[0];
        // An exception names the function it answers; any function may be refused (the
        // specification's own example refuses 01, which drivescript never sends).
        if code & 0x80 != 0 {
            length("the exception reply PDU", b, 2)?;
            return Ok(Response::Exception {
                function: code & 0x7F,
                code: ExceptionCode(b[1]),
            });
        }
        let function = Function::of(code)?;
        match function {
            Function::ReadHolding | Function::ReadInput | Function::ReadWrite => {
                at_least("the reply PDU", b, 2)?;
                let data = &b[2..];
                if usize::from(b[1]) != data.len() || data.is_empty() || !data.len().is_multiple_of(2) {
                    return Err(CodecError::ByteCount {
                        count: b[1].into(),
                        actual: data.len(),
                    });
                }
                Ok(Response::Registers {
                    function,
                    values: words(data),
                })
            }
            Function::WriteSingle => {
                length("the reply PDU", b, 5)?;
                Ok(Response::WriteSingle {
                    address: word(b, 1),
                    value: word(b, 3),
                })
            }
            Function::WriteMultiple => {
                length("the reply PDU", b, 5)?;
                Ok(Response::WriteMultiple {
                    start: word(b, 1),
                    count: word(b, 3),
                })
            }
        }
    }
}

#[cfg(test)]
#[path = "pdu_tests.rs"]
mod tests;
