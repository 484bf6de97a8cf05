//! CiA 306's data type codes (`DataType=0x0007`) and access types (`AccessType=rw`), and
//! which of them drivescript can carry as a dictionary object over SDO. Pure tables.

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

    /// `UNSIGNED16`, or `data type 0x000C` for a code without a name here.
    pub fn name(self) -> String {
        match CODES.iter().find(|(_, t, _)| *t == self) {
            Some((_, _, name)) => (*name).to_string(),
            None => match self {
                EdsType::Other(code) => format!("data type 0x{code:04X}"),
                _ => String::new(),
            },
        }
    }

    /// The dictionary type that carries this one over SDO, with the value range a BOOLEAN
    /// adds; `Err` says why drivescript does not carry it (yet).
    pub fn carried(self) -> Result<(DataType, Option<(f64, f64)>), String> {
        Ok(match self {
            // CiA 301 sends a BOOLEAN in one byte, 0 or 1.
            EdsType::Boolean => (DataType::U8, Some((0.0, 1.0))),
            EdsType::Integer8 => (DataType::I8, None),
            EdsType::Integer16 => (DataType::I16, None),
            EdsType::Integer32 => (DataType::I32, None),
            EdsType::Unsigned8 => (DataType::U8, None),
            EdsType::Unsigned16 => (DataType::U16, None),
            EdsType::Unsigned32 => (DataType::U32, None),
            EdsType::Integer64 => (DataType::I64, None),
            EdsType::Unsigned64 => (DataType::U64, None),
            // The EDS gives no length: up to the longest string a dictionary holds.
            EdsType::VisibleString => (DataType::String { max: MAX_STRING_LEN }, None),
            other => {
                return Err(format!(
                    "drivescript's dictionaries carry integers of 8, 16, 32 and 64 bits and visible strings, not {}",
                    other.name()
                ))
            }
        })
    }
}

/// CiA 306's access types. `rwr`/`rww` (read-write, mapped to a transmit or receive PDO)
/// are read-write over SDO; `const` is read-only.
pub(crate) fn access(text: &str) -> Result<Access, String> {
    match text.trim().to_ascii_lowercase().as_str() {
        "ro" | "const" => Ok(Access::ReadOnly),
        "wo" => Ok(Access::WriteOnly),
        "rw" | "rwr" | "rww" => Ok(Access::ReadWrite),
        _ => Err(format!(
            "`{}` is not an access type; CiA 306 has ro, wo, rw, rwr, rww and const",
            text.trim()
        )),
    }
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
        assert!(access("r").unwrap_err().contains("rww and const"));
    }

    #[test]
    fn codes_names_and_what_is_carried() {
        for (code, t, name) in CODES {
            assert_eq!(EdsType::from_code(code), t);
            assert_eq!(t.name(), name);
        }
        assert_eq!(EdsType::from_code(0x000C).name(), "data type 0x000C");
        assert_eq!(EdsType::Boolean.carried(), Ok((DataType::U8, Some((0.0, 1.0)))));
        assert_eq!(EdsType::Integer16.carried().unwrap().0, DataType::I16);
        assert_eq!(EdsType::Unsigned32.carried().unwrap().0, DataType::U32);
        assert_eq!(EdsType::Unsigned64.carried().unwrap().0, DataType::U64);
        assert_eq!(EdsType::Integer64.carried().unwrap().0, DataType::I64);
        assert!(EdsType::Integer24.carried().unwrap_err().contains("INTEGER24"));
        assert!(EdsType::Real32.carried().unwrap_err().contains("REAL32"));
        assert!(EdsType::Domain.carried().is_err());
    }
}
