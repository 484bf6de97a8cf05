//! A parameter as menu.parameter (`#1.21`), sent as four digits (`0121`). Pure.

use crate::dictionary::AddressError;
use std::fmt;

/// Menu and parameter, each 0..=99 (every source sends two digits each).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Parameter {
    pub menu: u8,
    pub param: u8,
}

impl Parameter {
    pub fn new(menu: u8, param: u8) -> Option<Parameter> {
        (menu <= 99 && param <= 99).then_some(Parameter { menu, param })
    }

    /// `#1.21`, `1.21`, `#10.40`, `01.21`; the error says what the notation is.
    pub fn parse(text: &str) -> Result<Parameter, AddressError> {
        let t = text.trim();
        let t = t.strip_prefix('#').unwrap_or(t);
        let help = "write menu.parameter, e.g. `#1.21` or `10.40` (menu and parameter 0..99)";
        let (menu, param) = t
            .split_once('.')
            .ok_or_else(|| AddressError::from(format!("`{text}` is not a parameter; {help}")))?;
        let number = |s: &str| -> Option<u8> {
            (!s.is_empty() && s.len() <= 2 && s.bytes().all(|b| b.is_ascii_digit()))
                .then(|| s.parse().ok())
                .flatten()
        };
        match (number(menu), number(param)) {
            (Some(m), Some(p)) => Ok(Parameter { menu: m, param: p }),
            _ => Err(AddressError::from(format!("`{text}` is not a parameter; {help}"))),
        }
    }

    /// The four digits on the wire.
    pub fn digits(self) -> [u8; 4] {
        [
            b'0' + self.menu / 10,
            b'0' + self.menu % 10,
            b'0' + self.param / 10,
            b'0' + self.param % 10,
        ]
    }

    /// Reads four wire digits; `None` when one is not a digit.
    pub fn from_digits(d: &[u8]) -> Option<Parameter> {
        let [a, b, c, e] = *d else { return None };
        if ![a, b, c, e].iter().all(u8::is_ascii_digit) {
            return None;
        }
        Some(Parameter {
            menu: (a - b'0') * 10 + (b - b'0'),
            param: (c - b'0') * 10 + (e - b'0'),
        })
    }

    /// `1.21`, as the golden vectors write it.
    pub fn dotted(self) -> String {
        format!("{}.{:02}", self.menu, self.param)
    }

    /// The next parameter of the menu (`ACK` short command), wrapping at 99.
    pub fn next(self) -> Parameter {
        Parameter {
            param: (self.param + 1) % 100,
            ..self
        }
    }

    /// The previous parameter of the menu (`BS` short command), wrapping at 0.
    pub fn previous(self) -> Parameter {
        Parameter {
            param: (self.param + 99) % 100,
            ..self
        }
    }
}

impl fmt::Display for Parameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.dotted())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notation_and_digits() {
        let p = Parameter::parse("#1.21").unwrap();
        assert_eq!(p, Parameter { menu: 1, param: 21 });
        assert_eq!(Parameter::parse("1.21"), Ok(p));
        assert_eq!(Parameter::parse("01.21"), Ok(p));
        assert_eq!(&p.digits(), b"0121");
        assert_eq!(Parameter::from_digits(b"1040"), Parameter::new(10, 40));
        assert_eq!(Parameter::parse("#5.04").unwrap().to_string(), "#5.04");
        assert_eq!(Parameter::parse("5.4").unwrap().dotted(), "5.04");
        for bad in ["121", "#1.", "100.1", "1.100", "a.b", "#1.2.3", ""] {
            assert!(Parameter::parse(bad).is_err(), "{bad}");
        }
        assert_eq!(Parameter::from_digits(b"01x1"), None);
        assert_eq!(p.next().dotted(), "1.22");
        assert_eq!(Parameter::new(1, 0).unwrap().previous().dotted(), "1.99");
    }
}
