//! The data types of object values as the drive holds them (each family puts them on its wire):
//! u8 i8 u16 i16 u32 i32, and strings with a maximum length; from a CANopen EDS also
//! integers of 24 to 64 bits, IEEE floats, byte strings, UTF-16 text and domains. Sizes
//! and ranges only; encoding lives with the object definition.

use std::fmt;

/// Longest string an object may declare (for example what one SD2 block carries: 48 data
/// bytes, one of them the length byte).
pub const MAX_STRING_LEN: u8 = 47;

/// Most bytes an OCTET_STRING, UNICODE_STRING or DOMAIN value may have: what one SDO
/// transfer carries here (the SDO client's `MAX_TRANSFER` is this), so that a node sending
/// more cannot grow memory without bound.
pub const MAX_BLOCK_LEN: usize = 256;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DataType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    /// 64-bit integers, from a CANopen EDS (INTEGER64, UNSIGNED64) only: dictionary files
    /// and `--type` do not offer them. Counts are `i64`, so an UNSIGNED64 holds at most
    /// 2^63 − 1 here.
    I64,
    U64,
    /// Integers of 3, 5, 6 or 7 bytes (CANopen INTEGER24 … UNSIGNED56), from an EDS only.
    Int {
        bytes: u8,
        signed: bool,
    },
    /// IEEE 754 single and double precision (REAL32, REAL64), little-endian.
    F32,
    F64,
    /// Characters, at most `max` of them (SD2, for example, sends the maximum length first,
    /// then the characters, NUL-terminated when shorter than the maximum).
    String {
        max: u8,
    },
    /// Bytes (OCTET_STRING), at most [`MAX_BLOCK_LEN`]; shown and written as hex.
    Octets,
    /// UTF-16LE text (UNICODE_STRING), at most [`MAX_BLOCK_LEN`] bytes; read only.
    Unicode,
    /// A block of data (DOMAIN: a program, a log), at most [`MAX_BLOCK_LEN`] bytes; read
    /// (and backed up as hex) but never written.
    Domain,
}

impl DataType {
    pub const INTEGERS: [DataType; 6] = [
        DataType::U8,
        DataType::I8,
        DataType::U16,
        DataType::I16,
        DataType::U32,
        DataType::I32,
    ];

    /// The integer of `bytes` bytes (3, 5, 6 or 7: the widths CANopen adds), signed or not.
    pub const fn int(bytes: u8, signed: bool) -> DataType {
        DataType::Int { bytes, signed }
    }

    /// Bytes on the wire: the integer's width, or for a string the length byte plus `max`.
    pub fn size(self) -> usize {
        match self {
            DataType::U8 | DataType::I8 => 1,
            DataType::U16 | DataType::I16 => 2,
            DataType::U32 | DataType::I32 => 4,
            DataType::I64 | DataType::U64 | DataType::F64 => 8,
            DataType::Int { bytes, .. } => usize::from(bytes),
            DataType::F32 => 4,
            DataType::String { max } => 1 + usize::from(max),
            DataType::Octets | DataType::Unicode | DataType::Domain => MAX_BLOCK_LEN,
        }
    }

    /// The smallest and largest raw count; `None` for floats, strings and bytes.
    pub fn range(self) -> Option<(i64, i64)> {
        Some(match self {
            DataType::U8 => (0, u8::MAX.into()),
            DataType::I8 => (i8::MIN.into(), i8::MAX.into()),
            DataType::U16 => (0, u16::MAX.into()),
            DataType::I16 => (i16::MIN.into(), i16::MAX.into()),
            DataType::U32 => (0, u32::MAX.into()),
            DataType::I32 => (i32::MIN.into(), i32::MAX.into()),
            DataType::I64 => (i64::MIN, i64::MAX),
            DataType::U64 => (0, i64::MAX),
            DataType::Int { bytes, signed } => {
                let bits = 8 * u32::from(bytes.clamp(1, 7));
                match signed {
                    true => (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1),
                    false => (0, (1i64 << bits) - 1),
                }
            }
            DataType::F32
            | DataType::F64
            | DataType::String { .. }
            | DataType::Octets
            | DataType::Unicode
            | DataType::Domain => return None,
        })
    }

    pub fn is_integer(self) -> bool {
        self.range().is_some()
    }

    /// `Some(true)` for a single, `Some(false)` for a double, `None` for the rest.
    pub fn float_single(self) -> Option<bool> {
        match self {
            DataType::F32 => Some(true),
            DataType::F64 => Some(false),
            _ => None,
        }
    }

    /// Integers and floats: values given as numbers with units.
    pub fn is_number(self) -> bool {
        self.is_integer() || self.float_single().is_some()
    }

    pub fn is_signed(self) -> bool {
        matches!(
            self,
            DataType::I8 | DataType::I16 | DataType::I32 | DataType::I64 | DataType::Int { signed: true, .. }
        )
    }

    /// The spelling in dictionary files: `u16`, `string(32)`.
    pub fn name(self) -> String {
        match self {
            DataType::U8 => "u8".into(),
            DataType::I8 => "i8".into(),
            DataType::U16 => "u16".into(),
            DataType::I16 => "i16".into(),
            DataType::U32 => "u32".into(),
            DataType::I32 => "i32".into(),
            DataType::I64 => "i64".into(),
            DataType::U64 => "u64".into(),
            DataType::Int { bytes, signed } => {
                format!("{}{}", if signed { 'i' } else { 'u' }, 8 * u32::from(bytes))
            }
            DataType::F32 => "f32".into(),
            DataType::F64 => "f64".into(),
            DataType::String { max } => format!("string({max})"),
            DataType::Octets => "octets".into(),
            DataType::Unicode => "unicode".into(),
            DataType::Domain => "domain".into(),
        }
    }

    /// Parses a dictionary's `type:` value. The error says what is accepted (the reader
    /// puts it in a located diagnostic and `--type` in its argument error).
    pub fn parse(text: &str) -> Result<DataType, DataTypeError> {
        let t = text.trim();
        if let Some(found) = Self::INTEGERS.into_iter().find(|d| d.name() == t) {
            return Ok(found);
        }
        if t == "string" {
            return Err(DataTypeError::StringWithoutLength);
        }
        if let Some(inner) = t.strip_prefix("string(").and_then(|r| r.strip_suffix(')')) {
            return match inner.trim().parse::<u8>() {
                Ok(max) if (1..=MAX_STRING_LEN).contains(&max) => Ok(DataType::String { max }),
                _ => Err(DataTypeError::StringLength {
                    length: inner.trim().to_string(),
                }),
            };
        }
        Err(DataTypeError::Unknown { name: t.to_string() })
    }

    /// The type names a dictionary may use, for suggestions and help texts.
    /// A little-endian integer of 1 to 8 `bytes`, widened with this type's signedness (the
    /// layout SD2 blocks and CANopen SDO share).
    pub fn from_le_bytes(self, bytes: &[u8]) -> i64 {
        let used = bytes.len().min(8);
        let mut buf = [0u8; 8];
        buf[..used].copy_from_slice(&bytes[..used]);
        let unsigned = u64::from_le_bytes(buf);
        if self.is_signed() && used > 0 {
            let shift = 64 - 8 * used as u32;
            ((unsigned << shift) as i64) >> shift
        } else {
            unsigned as i64
        }
    }

    /// `count` little-endian in this type's width; `None` when it is outside the type's
    /// range (it is refused, never sent wrapped).
    pub fn to_le_bytes(self, count: i64) -> Option<Vec<u8>> {
        let (lo, hi) = self.range()?;
        (lo..=hi)
            .contains(&count)
            .then(|| count.to_le_bytes()[..self.size()].to_vec())
    }

    pub fn names() -> [&'static str; 7] {
        ["u8", "i8", "u16", "i16", "u32", "i32", "string(32)"]
    }
}

impl fmt::Display for DataType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

/// Why a `type:` value (or `--type`) names no data type, and what to write instead.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DataTypeError {
    #[error("`string` needs its maximum length, e.g. `string(32)` (1..={max})", max = MAX_STRING_LEN)]
    StringWithoutLength,
    #[error("string length `{length}` must be a number from 1 to {max}", max = MAX_STRING_LEN)]
    StringLength { length: String },
    #[error("unknown type `{name}`")]
    Unknown { name: String },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn little_endian_integers_widen_with_the_types_signedness() {
        assert_eq!(DataType::I32.from_le_bytes(&[0xff, 0xff]), -1);
        assert_eq!(DataType::U32.from_le_bytes(&[0xff, 0xff]), 0xffff);
        assert_eq!(DataType::I8.from_le_bytes(&[0x80]), -128);
        assert_eq!(DataType::I16.to_le_bytes(-2), Some(vec![0xfe, 0xff]));
        assert_eq!(DataType::U8.to_le_bytes(256), None);
        assert_eq!(DataType::String { max: 3 }.to_le_bytes(1), None);
    }

    #[test]
    fn integers_of_24_to_56_bits() {
        let i24 = DataType::int(3, true);
        let u48 = DataType::int(6, false);
        assert_eq!((i24.name(), u48.name()), ("i24".into(), "u48".into()));
        assert_eq!(i24.range(), Some((-8_388_608, 8_388_607)));
        assert_eq!(u48.range(), Some((0, (1 << 48) - 1)));
        assert_eq!(i24.from_le_bytes(&[0xfe, 0xff, 0xff]), -2);
        assert_eq!(i24.from_le_bytes(&[0xff, 0xff, 0x7f]), 8_388_607);
        assert_eq!(u48.from_le_bytes(&[0xff; 6]), (1 << 48) - 1);
        assert_eq!(i24.to_le_bytes(-2), Some(vec![0xfe, 0xff, 0xff]));
        assert_eq!(i24.to_le_bytes(8_388_608), None);
        assert_eq!(DataType::int(7, true).size(), 7);
        assert!(i24.is_signed() && !u48.is_signed() && u48.is_integer());
        assert!(DataType::F32.is_number() && !DataType::F32.is_integer());
        assert!(!DataType::Octets.is_number());
    }

    proptest::proptest! {
        /// Every count of every width survives its bytes, sign-extended right.
        #[test]
        fn odd_widths_round_trip(bytes in 3u8..=7, signed: bool, seed: i64) {
            let t = DataType::Int { bytes, signed };
            let (lo, hi) = t.range().unwrap();
            let count = lo + seed.rem_euclid(hi - lo + 1);
            let wire = t.to_le_bytes(count).unwrap();
            proptest::prop_assert_eq!(wire.len(), usize::from(bytes));
            proptest::prop_assert_eq!(t.from_le_bytes(&wire), count);
            let any = seed.to_le_bytes();
            let _ = t.from_le_bytes(&any[..usize::from(bytes)]);
        }
    }

    #[test]
    fn sizes_and_ranges() {
        assert_eq!(DataType::U16.size(), 2);
        assert_eq!(DataType::I32.size(), 4);
        assert_eq!(DataType::String { max: 32 }.size(), 33);
        assert_eq!(DataType::I8.range(), Some((-128, 127)));
        assert_eq!(DataType::U32.range(), Some((0, 4_294_967_295)));
        assert_eq!(DataType::String { max: 3 }.range(), None);
    }

    #[test]
    fn parse_names() {
        for d in DataType::INTEGERS {
            assert_eq!(DataType::parse(&d.name()), Ok(d));
        }
        assert_eq!(DataType::parse("string(32)"), Ok(DataType::String { max: 32 }));
        assert_eq!(DataType::parse("string( 8 )"), Ok(DataType::String { max: 8 }));
        assert_eq!(
            DataType::parse("string").unwrap_err().to_string(),
            "`string` needs its maximum length, e.g. `string(32)` (1..=47)"
        );
        assert_eq!(
            DataType::parse("string(48)").unwrap_err().to_string(),
            "string length `48` must be a number from 1 to 47"
        );
        assert!(DataType::parse("string(x)").is_err());
        assert_eq!(
            DataType::parse("u64").unwrap_err().to_string(),
            "unknown type `u64`"
        );
    }
}
