//! Text from outside (a serial number, an operator's answer, a drive's reply) made safe
//! to show: control characters — an ESC sequence that would recolour, move or retitle a
//! terminal, a CSV cell's bell or backspace — are shown as escapes (`\x1b`), so what is
//! printed is what was given and never acts on the terminal. Printing only; what is
//! stored stays exactly as given.

use std::borrow::Cow;

/// `text` with every control character but line breaks and tabs escaped: for lines
/// whose layout (several lines, indented) is their own.
pub fn visible(text: &str) -> Cow<'_, str> {
    escaped(text, |c| c == '\n' || c == '\t')
}

/// `text` with every control character escaped, line breaks and tabs too: for a table's
/// cell or a CSV field, which must stay on one line.
pub fn visible_inline(text: &str) -> Cow<'_, str> {
    escaped(text, |_| false)
}

fn escaped(text: &str, kept: impl Fn(char) -> bool) -> Cow<'_, str> {
    let shown = |c: char| !c.is_control() || kept(c);
    if text.chars().all(shown) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            c if shown(c) => out.push(c),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if (c as u32) < 0x100 => out.push_str(&format!("\\x{:02x}", c as u32)),
            c => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_shown_as_escapes_and_plain_text_is_untouched() {
        for (text, shown) in [
            ("SP-104233 ✓", "SP-104233 ✓"),
            (
                "\u{1b}[2J\u{1b}]0;owned\u{7}x\u{9b}31m",
                "\\x1b[2J\\x1b]0;owned\\x07x\\x9b31m",
            ),
            ("two\nlines\tand\r\0", "two\nlines\tand\\r\\x00"),
        ] {
            assert_eq!(visible(text), shown, "{text:?}");
        }
        assert_eq!(visible_inline("two\nlines\tx"), "two\\nlines\\tx");
        assert!(matches!(visible("plain"), Cow::Borrowed(_)));
    }
}
