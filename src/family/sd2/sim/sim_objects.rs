//! The simulated drive's object table: which indices exist, their type, size and access,
//! and the access errors a real SD2 answers before a value is touched. It must not compute
//! values or change state; the indices, types and scales are the project dictionary's.

use crate::family::sd2::codec::ErrorCode;

pub(crate) const IDENT_STRING: u16 = 22;
pub(crate) const BUS_VOLTAGE: u16 = 33;
pub(crate) const POWER_STAGE_LOAD: u16 = 39;
pub(crate) const STATUS_WORD: u16 = 67;
pub(crate) const CONTROL_WORD: u16 = 68;
pub(crate) const ACTUAL_SPEED_2: u16 = 168;
pub(crate) const PARAMETER_SET: u16 = 352;
pub(crate) const SPEED_SETPOINT: u16 = 395;
pub(crate) const ACTUAL_SPEED: u16 = 398;
pub(crate) const ACTUAL_CURRENT: u16 = 400;
pub(crate) const DRIVE_ERROR: u16 = 401;
pub(crate) const STORE_PARAMETERS: u16 = 402;
pub(crate) const MOTOR_TEMPERATURE: u16 = 403;

/// Maximum length of the ident string, sent as its first byte.
pub(crate) const IDENT_MAX: usize = 32;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    U16,
    I32,
    /// data[0] = maximum length, then the characters, NUL-terminated when shorter.
    String32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Access {
    ReadOnly,
    ReadWrite,
    WriteOnly,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SimObject {
    pub(crate) index: u16,
    pub(crate) kind: Kind,
    pub(crate) access: Access,
}

const fn object(index: u16, kind: Kind, access: Access) -> SimObject {
    SimObject { index, kind, access }
}

pub(crate) const OBJECTS: [SimObject; 13] = [
    object(IDENT_STRING, Kind::String32, Access::ReadOnly),
    object(BUS_VOLTAGE, Kind::U16, Access::ReadOnly),
    object(POWER_STAGE_LOAD, Kind::U16, Access::ReadOnly),
    object(STATUS_WORD, Kind::U16, Access::ReadOnly),
    object(CONTROL_WORD, Kind::U16, Access::ReadWrite),
    object(ACTUAL_SPEED_2, Kind::I32, Access::ReadOnly),
    object(PARAMETER_SET, Kind::U16, Access::ReadWrite),
    object(SPEED_SETPOINT, Kind::I32, Access::ReadWrite),
    object(ACTUAL_SPEED, Kind::I32, Access::ReadOnly),
    object(ACTUAL_CURRENT, Kind::I32, Access::ReadOnly),
    object(DRIVE_ERROR, Kind::U16, Access::ReadOnly),
    object(STORE_PARAMETERS, Kind::U16, Access::WriteOnly),
    object(MOTOR_TEMPERATURE, Kind::I32, Access::ReadOnly),
];

impl SimObject {
    /// The object at `index`, or 0x8B object does not exist.
    pub(crate) fn find(index: u16) -> Result<&'static SimObject, ErrorCode> {
        OBJECTS
            .iter()
            .find(|o| o.index == index)
            .ok_or(ErrorCode::OBJECT_DOES_NOT_EXIST)
    }

    /// Bytes a write must carry; for the string, the most a read can return.
    pub(crate) fn size(&self) -> usize {
        match self.kind {
            Kind::U16 => 2,
            Kind::I32 => 4,
            Kind::String32 => 1 + IDENT_MAX,
        }
    }

    /// Scalars have only subindex 0. The string accepts 0..=32 and always returns the
    /// whole string: the sources do not say what a string subindex selects, so the
    /// simulator does not pretend to know.
    fn check_subindex(&self, subindex: u32) -> Result<(), ErrorCode> {
        let last = match self.kind {
            Kind::String32 => IDENT_MAX as u32,
            Kind::U16 | Kind::I32 => 0,
        };
        if subindex > last {
            Err(ErrorCode::SUBINDEX_DOES_NOT_EXIST)
        } else {
            Ok(())
        }
    }

    pub(crate) fn check_read(&self, subindex: u32) -> Result<(), ErrorCode> {
        self.check_subindex(subindex)?;
        match self.access {
            Access::WriteOnly => Err(ErrorCode::WRITE_ONLY),
            Access::ReadOnly | Access::ReadWrite => Ok(()),
        }
    }

    /// Subindex, then access, then length: the order in which a drive can know each.
    pub(crate) fn check_write(&self, subindex: u32, len: usize) -> Result<(), ErrorCode> {
        self.check_subindex(subindex)?;
        if self.access == Access::ReadOnly {
            return Err(ErrorCode::READ_ONLY);
        }
        match len.cmp(&self.size()) {
            std::cmp::Ordering::Greater => Err(ErrorCode::TOO_LONG),
            std::cmp::Ordering::Less => Err(ErrorCode::TOO_SHORT),
            std::cmp::Ordering::Equal => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup_and_unknown_index() {
        assert_eq!(SimObject::find(398).map(|o| o.kind), Ok(Kind::I32));
        assert_eq!(SimObject::find(999), Err(ErrorCode::OBJECT_DOES_NOT_EXIST));
        assert!(
            OBJECTS.windows(2).all(|w| w[0].index < w[1].index),
            "sorted and unique"
        );
    }

    #[test]
    fn access_checks() {
        let find = |i| SimObject::find(i).unwrap();
        assert_eq!(find(67).check_read(0), Ok(()));
        assert_eq!(find(67).check_read(1), Err(ErrorCode::SUBINDEX_DOES_NOT_EXIST));
        assert_eq!(find(22).check_read(5), Ok(()));
        assert_eq!(find(22).check_read(33), Err(ErrorCode::SUBINDEX_DOES_NOT_EXIST));
        assert_eq!(find(402).check_read(0), Err(ErrorCode::WRITE_ONLY));
        assert_eq!(find(67).check_write(0, 2), Err(ErrorCode::READ_ONLY));
        assert_eq!(find(22).check_write(0, 2), Err(ErrorCode::READ_ONLY));
        assert_eq!(find(68).check_write(0, 2), Ok(()));
        assert_eq!(find(68).check_write(0, 4), Err(ErrorCode::TOO_LONG));
        assert_eq!(find(395).check_write(0, 2), Err(ErrorCode::TOO_SHORT));
        assert_eq!(
            find(395).check_write(1, 4),
            Err(ErrorCode::SUBINDEX_DOES_NOT_EXIST)
        );
        assert_eq!(find(402).check_write(0, 2), Ok(()));
    }
}
