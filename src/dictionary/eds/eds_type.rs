//! CiA 306's data type codes (`DataType=0x0007`) and access types (`AccessType=rw`), and
//! the dictionary type each is carried as over SDO. Pure tables.

use crate::dictionary::{Access, DataType, MAX_STRING_LEN};

/// A CiA 301 basic data type as an EDS names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum EdsType {
    Boolean,
    Integer8,
    Integer16,
    Integer32,
    Unsigned8,
    Unsigned16,
    Unsigned32,
    Real32,
    VisibleString,
    OctetString,
    UnicodeString,
    Domain,
    Integer24,
    Real64,
    Integer40,
    Integer48,
    Integer56,
    Integer64,
    Unsigned24,
    Unsigned40,
    Unsigned48,
    Unsigned56,
    Unsigned64,
    /// Another code (TIME_OF_DAY, a vendor's complex type …): read, never carried.
    Other(u16),
}

const CODES: [(u16, EdsType, &str); 23] = [
    (0x0001, EdsType::Boolean, "BOOLEAN"),
    (0x0002, EdsType::Integer8, "INTEGER8"),
    (0x0003, EdsType::Integer16, "INTEGER16"),
    (0x0004, EdsType::Integer32, "INTEGER32"),
    (0x0005, EdsType::Unsigned8, "UNSIGNED8"),
    (0x0006, EdsType::Unsigned16, "UNSIGNED16"),
    (0x0007, EdsType::Unsigned32, "UNSIGNED32"),
    (0x0008, EdsType::Real32, "REAL32"),
    (0x0009, EdsType::VisibleString, "VISIBLE_STRING"),
    (0x000A, EdsType::OctetString, "OCTET_STRING"),
    (0x000B, EdsType::UnicodeString, "UNICODE_STRING"),
    (0x000F, EdsType::Domain, "DOMAIN"),
    (0x0010, EdsType::Integer24, "INTEGER24"),
    (0x0011, EdsType::Real64, "REAL64"),
    (0x0012, EdsType::Integer40, "INTEGER40"),
    (0x0013, EdsType::Integer48, "INTEGER48"),
    (0x0014, EdsType::Integer56, "INTEGER56"),
    (0x0015, EdsType::Integer64, "INTEGER64"),
    (0x0016, EdsType::Unsigned24, "UNSIGNED24"),
    (0x0018, EdsType::Unsigned40, "UNSIGNED40"),
    (0x0019, EdsType::Unsigned48, "UNSIGNED48"),
    (0x001A, EdsType::Unsigned56, "UNSIGNED56"),
    (0x001B, EdsType::Unsigned64, "UNSIGNED64"),
];

impl EdsType {
    pub fn from_code(code: u16) -> EdsType {
        CODES
            .iter()
            .find(|(c, _, _)| *c == code)
            .map_or(EdsType::Other(code), |(_, t, _)| *t)
    }

    /// `UNSIGNED16`, `TIME_OF_DAY (0x000C)`, or `data type 0x0020` for a code without a
    /// name here.
    pub fn name(self) -> String {
        match CODES.iter().find(|(_, t, _)| *t == self) {
            Some((_, _, name)) => (*name).to_string(),
            None => match self {
                EdsType::Other(0x000C) => "TIME_OF_DAY (0x000C)".into(),
                EdsType::Other(0x000D) => "TIME_DIFFERENCE (0x000D)".into(),
                EdsType::Other(code) => format!("data type 0x{code:04X}"),
                _ => String::new(),
            },
        }
    }

    /// The width in bits of a signed integer type, whose limits written in hex are two's
    /// complement at that width (`LowLimit=0x80000000` of an INTEGER32 is −2³¹).
    pub fn signed_bits(self) -> Option<u32> {
        Some(match self {
            EdsType::Integer8 => 8,
            EdsType::Integer16 => 16,
            EdsType::Integer24 => 24,
            EdsType::Integer32 => 32,
            EdsType::Integer40 => 40,
            EdsType::Integer48 => 48,
            EdsType::Integer56 => 56,
            EdsType::Integer64 => 64,
            _ => return None,
        })
    }

    /// The CiA 301 code (`0x0004` for INTEGER32).
    pub fn code(self) -> u16 {
        match self {
            EdsType::Other(code) => code,
            _ => CODES
                .iter()
                .find(|(_, t, _)| *t == self)
                .map_or(0, |(c, _, _)| *c),
        }
    }

    /// The dictionary type that carries this one over SDO, with the value range a BOOLEAN
    /// adds.
    pub fn carried(self) -> Result<(DataType, Option<(f64, f64)>), NotCarried> {
        let int = DataType::int;
        Ok(match self {
            // CiA 301 sends a BOOLEAN in one byte, 0 or 1.
            EdsType::Boolean => (DataType::U8, Some((0.0, 1.0))),
            EdsType::Integer8 => (DataType::I8, None),
            EdsType::Integer16 => (DataType::I16, None),
            EdsType::Integer24 => (int(3, true), None),
            EdsType::Integer32 => (DataType::I32, None),
            EdsType::Integer40 => (int(5, true), None),
            EdsType::Integer48 => (int(6, true), None),
            EdsType::Integer56 => (int(7, true), None),
            EdsType::Integer64 => (DataType::I64, None),
            EdsType::Unsigned8 => (DataType::U8, None),
            EdsType::Unsigned16 => (DataType::U16, None),
            EdsType::Unsigned24 => (int(3, false), None),
            EdsType::Unsigned32 => (DataType::U32, None),
            EdsType::Unsigned40 => (int(5, false), None),
            EdsType::Unsigned48 => (int(6, false), None),
            EdsType::Unsigned56 => (int(7, false), None),
            EdsType::Unsigned64 => (DataType::U64, None),
            EdsType::Real32 => (DataType::F32, None),
            EdsType::Real64 => (DataType::F64, None),
            // The EDS gives no length: up to the longest string a dictionary holds.
            EdsType::VisibleString => (DataType::String { max: MAX_STRING_LEN }, None),
            EdsType::OctetString => (DataType::Octets, None),
            EdsType::UnicodeString => (DataType::Unicode, None),
            EdsType::Domain => (DataType::Domain, None),
            EdsType::Other(code) => return Err(NotCarried { code }),
        })
    }
}

/// Why an entry's data type is not carried: not one of CiA 301's basic types (a time, a
/// PDO parameter record type, a vendor's own).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("{} is not one of the basic types drivescript carries (BOOLEAN, INTEGER8 to 64, UNSIGNED8 to 64, REAL32, REAL64, VISIBLE_STRING, OCTET_STRING, UNICODE_STRING, DOMAIN); read it with a CANopen tool", EdsType::Other(*code).name())]
pub(crate) struct NotCarried {
    pub code: u16,
}

/// CiA 306's access types. `rwr`/`rww` (read-write, mapped to a transmit or receive PDO)
/// are read-write over SDO; `const` is read-only.
pub(crate) fn access(text: &str) -> Result<Access, UnknownAccess> {
    match text.trim().to_ascii_lowercase().as_str() {
        "ro" | "const" => Ok(Access::ReadOnly),
        "wo" => Ok(Access::WriteOnly),
        "rw" | "rwr" | "rww" => Ok(Access::ReadWrite),
        _ => Err(UnknownAccess {
            text: text.trim().to_string(),
        }),
    }
}

/// An `AccessType` CiA 306 does not define, and the ones it does.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{text}` is not an access type; CiA 306 has ro, wo, rw, rwr, rww and const")]
pub(crate) struct UnknownAccess {
    pub text: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_access_type() {
        let a = |t| access(t).unwrap();
        assert_eq!(
            [a("ro"), a("const"), a("WO"), a("rw"), a("rwr"), a("RWW")],
            [
                Access::ReadOnly,
                Access::ReadOnly,
                Access::WriteOnly,
                Access::ReadWrite,
                Access::ReadWrite,
                Access::ReadWrite
            ]
        );
        assert!(access("r").unwrap_err().to_string().contains("rww and const"));
    }

    #[test]
    fn codes_names_and_what_is_carried() {
        for (code, t, name) in CODES {
            assert_eq!(EdsType::from_code(code), t);
            assert_eq!(t.name(), name);
        }
        assert_eq!(EdsType::from_code(0x000C).name(), "TIME_OF_DAY (0x000C)");
        assert_eq!(EdsType::from_code(0x0020).name(), "data type 0x0020");
        assert_eq!(EdsType::Boolean.carried(), Ok((DataType::U8, Some((0.0, 1.0)))));
        let carried = |t: EdsType| t.carried().unwrap().0;
        assert_eq!(carried(EdsType::Integer16), DataType::I16);
        assert_eq!(carried(EdsType::Unsigned32), DataType::U32);
        assert_eq!(carried(EdsType::Unsigned64), DataType::U64);
        assert_eq!(carried(EdsType::Integer64), DataType::I64);
        assert_eq!(carried(EdsType::Integer24), DataType::int(3, true));
        assert_eq!(carried(EdsType::Unsigned40), DataType::int(5, false));
        assert_eq!(carried(EdsType::Integer56), DataType::int(7, true));
        assert_eq!(carried(EdsType::Real32), DataType::F32);
        assert_eq!(carried(EdsType::Real64), DataType::F64);
        assert_eq!(carried(EdsType::OctetString), DataType::Octets);
        assert_eq!(carried(EdsType::UnicodeString), DataType::Unicode);
        assert_eq!(carried(EdsType::Domain), DataType::Domain);
        // Every named code is carried, in its own width.
        for (_, t, _) in CODES {
            assert!(t.carried().is_ok(), "{t:?}");
        }
        let why = EdsType::from_code(0x000C).carried().unwrap_err().to_string();
        assert!(
            why.contains("TIME_OF_DAY (0x000C) is not one of the basic types"),
            "{why}"
        );
    }
}
