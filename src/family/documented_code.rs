//! How a family's error, exception or abort code is shown, one way for every family: its
//! number and the text its manual gives it, or its number and that the manual does not
//! list it, never a guessed text. Pure.

/// `Display` for a code type (a tuple struct of the number) with a `meaning(self) ->
/// Option<&'static str>`: `$number` formats the number (`"0x{:08X}"`), `$unlisted` stands
/// in for the text of a code the manual does not list.
macro_rules! documented_code {
    ($code:ty, $number:literal, $unlisted:literal) => {
        impl std::fmt::Display for $code {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, $number, self.0)?;
                match self.meaning() {
                    Some(text) => write!(f, " {text}"),
                    None => write!(f, concat!(" (", $unlisted, ")")),
                }
            }
        }
    };
}

pub(crate) use documented_code;
