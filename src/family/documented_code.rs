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

/// A code type from its manual's table, each code written once with its text: declares the
/// tuple struct of the number, an associated constant for each code given a name, `ALL`
/// (every listed code, in the table's order) and `meaning` (the text, or `None` for a code
/// the table does not list).
macro_rules! code_table {
    (
        $(#[$attr:meta])*
        pub struct $code:ident(pub $number:ty);
        $( $($name:ident =)? $value:literal => $text:literal, )*
    ) => {
        $(#[$attr])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub struct $code(pub $number);

        impl $code {
            $( $( pub const $name: $code = $code($value); )? )*

            /// Every code the table lists.
            pub const ALL: [$code; [$(stringify!($value)),*].len()] = [$($code($value)),*];

            /// The manual's text, or `None` for a code the table does not list.
            pub fn meaning(self) -> Option<&'static str> {
                match self.0 {
                    $( $value => Some($text), )*
                    _ => None,
                }
            }
        }
    };
}

pub(crate) use code_table;
