//! Hex text ⇄ bytes, in the forms engineers paste from manuals, captures and terminals:
//! `00 0b 02`, `000b02`, `0x00 0x0b`, `00:0b:02`, `00,0b`. Pure; no I/O.

use std::fmt::Write as _;

/// Why a piece of text is not a run of hex bytes. `column` is 1-based, in characters.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum HexError {
    #[error("no hex bytes in {text:?}")]
    Empty { text: String },
    #[error(
        "'{found}' at column {column} is not a hex digit (expected 0-9, a-f, or a separator: space , : -)"
    )]
    NotHex { found: char, column: usize },
    #[error("odd number of hex digits in '{token}' at column {column}: write each byte as two digits, e.g. 0b not b")]
    OddDigits { token: String, column: usize },
}

/// Parses hex bytes. A token of one or two digits is one byte (`0x7` is 0x07); a longer
/// token must have an even number of digits and is read two digits per byte.
pub fn parse_hex(text: &str) -> Result<Vec<u8>, HexError> {
    let mut bytes = Vec::new();
    for (column, token) in tokens(text) {
        let digits = token
            .strip_prefix("0x")
            .or_else(|| token.strip_prefix("0X"))
            .unwrap_or(token);
        let digits_column = column + (token.len() - digits.len());
        if let Some((i, c)) = digits.char_indices().find(|(_, c)| !c.is_ascii_hexdigit()) {
            return Err(HexError::NotHex {
                found: c,
                column: digits_column + digits[..i].chars().count(),
            });
        }
        if digits.is_empty() {
            return Err(HexError::OddDigits {
                token: token.to_string(),
                column,
            });
        }
        if digits.len() > 2 && digits.len() % 2 == 1 {
            return Err(HexError::OddDigits {
                token: token.to_string(),
                column,
            });
        }
        if digits.len() <= 2 {
            bytes.push(byte(digits));
        } else {
            for pair in digits.as_bytes().chunks(2) {
                // Only ASCII hex digits remain, so the pair is valid UTF-8.
                bytes.push(byte(std::str::from_utf8(pair).unwrap_or("00")));
            }
        }
    }
    if bytes.is_empty() {
        return Err(HexError::Empty {
            text: text.to_string(),
        });
    }
    Ok(bytes)
}

fn byte(digits: &str) -> u8 {
    u8::from_str_radix(digits, 16).unwrap_or(0)
}

/// Splits on separators, giving each token's 1-based character column.
fn tokens(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start: Option<(usize, usize)> = None; // (byte offset, column)
    for (column, (offset, c)) in text.char_indices().enumerate() {
        let separator = c.is_whitespace() || matches!(c, ',' | ':' | '-' | ';');
        match (separator, start) {
            (true, Some((s, col))) => {
                out.push((col + 1, &text[s..offset]));
                start = None;
            }
            (false, None) => start = Some((offset, column)),
            _ => {}
        }
    }
    if let Some((s, col)) = start {
        out.push((col + 1, &text[s..]));
    }
    out
}

/// Spaced lower-case hex, the layout of the manuals: `00 0b 02`.
pub fn to_hex(bytes: &[u8]) -> String {
    let mut s = String::with_capacity(bytes.len() * 3);
    for (i, b) in bytes.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{b:02x}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn accepts_the_usual_forms() {
        let want = vec![0x00, 0x0b, 0x02];
        for text in [
            "00 0b 02",
            "000b02",
            "0x00 0x0b 0x02",
            "00:0b:02",
            "00,0B,02",
            " 0x000B02 ",
            "0 b 2",
        ] {
            assert_eq!(parse_hex(text).unwrap(), want, "{text}");
        }
    }

    #[test]
    fn says_where_the_bad_character_is() {
        assert_eq!(
            parse_hex("00 0g").unwrap_err(),
            HexError::NotHex {
                found: 'g',
                column: 5
            }
        );
        assert_eq!(
            parse_hex("0x00 0xzz").unwrap_err(),
            HexError::NotHex {
                found: 'z',
                column: 8
            }
        );
    }

    #[test]
    fn odd_digit_runs_and_empty_text_are_refused() {
        assert!(matches!(
            parse_hex("00b"),
            Err(HexError::OddDigits { column: 1, .. })
        ));
        assert!(matches!(parse_hex("   "), Err(HexError::Empty { .. })));
        assert!(matches!(parse_hex("0x"), Err(HexError::OddDigits { .. })));
    }

    proptest! {
        #[test]
        fn round_trips(bytes in proptest::collection::vec(any::<u8>(), 1..64)) {
            prop_assert_eq!(parse_hex(&to_hex(&bytes)).unwrap(), bytes);
        }

        #[test]
        fn never_panics(text in "\\PC{0,40}") {
            let _ = parse_hex(&text);
        }
    }
}
