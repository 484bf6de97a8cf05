//! The length-field choice for Write Wide Object commands (a known quirk of the sources).

/// What the encoder puts in the length field of a Write Wide Object command.
///
/// The manual's formula gives `10 + count` (bytes in the block minus 3, as for every other
/// block). Every write example in the manual and every capture of the integrator's, which
/// were sent to real drives that then changed state, carries `0x0B` whatever the count, with
/// the checksum computed over that `0x0B`. Real drives therefore frame write commands by the
/// count byte and accept `0x0B`; whether they accept the formula value is not documented by
/// any capture. So the default is what is proven on hardware. Decoders accept both forms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WriteLength {
    /// Always `0x0B`, as in the captures sent to real drives (default).
    #[default]
    Captured,
    /// `10 + count`, as the manual's formula says.
    Formula,
}

impl WriteLength {
    /// The value sent in the length field for a write of `count` data bytes.
    pub fn field(self, count: usize) -> u8 {
        match self {
            WriteLength::Captured => 0x0B,
            WriteLength::Formula => 10 + count.min(super::MAX_DATA) as u8,
        }
    }

    pub fn id(self) -> &'static str {
        match self {
            WriteLength::Captured => "captured",
            WriteLength::Formula => "formula",
        }
    }
}
