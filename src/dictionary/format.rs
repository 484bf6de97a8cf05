//! How an integer object's value is shown: decimal (the default) or hex (bit fields such
//! as the status word, `0x0237`). Presentation only.

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Format {
    #[default]
    Decimal,
    Hex,
}

impl Format {
    pub const ALL: [Format; 2] = [Format::Decimal, Format::Hex];

    pub fn id(self) -> &'static str {
        match self {
            Format::Decimal => "decimal",
            Format::Hex => "hex",
        }
    }

    pub fn from_id(id: &str) -> Option<Format> {
        Self::ALL.into_iter().find(|f| f.id() == id)
    }
}
