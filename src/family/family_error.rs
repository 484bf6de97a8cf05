//! What a family refuses at the seam, by kind, so a caller can tell a wrong address or
//! option on the command line from a wrong dictionary entry or a bus that does not fit;
//! what the drive itself says (refusals, silence, a dead line) is an
//! [`AccessError`](crate::drive::AccessError) instead. The texts are the ones users see.

/// A family's refusal before any telegram is sent.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FamilyError {
    /// `--address` (or a `drives:` entry's address) is not in the family's notation.
    #[error("{0}")]
    DriveAddress(String),
    /// A `--link-option` the family does not know, or a value it cannot take.
    #[error("{0}")]
    LinkOption(String),
    /// The bus given is not the kind the family talks over.
    #[error("{0}")]
    WrongBus(String),
    /// An object's address or type in the family's notation is wrong (a dictionary entry's
    /// `address:`, a raw object named on the command line).
    #[error("{0}")]
    Object(String),
    /// No family or built-in dictionary of that name.
    #[error("{0}")]
    Unknown(String),
}

/// For callers that still report errors as text (the command line prints them as they are).
impl From<FamilyError> for String {
    fn from(e: FamilyError) -> String {
        e.to_string()
    }
}

impl From<crate::dictionary::AddressError> for FamilyError {
    fn from(e: crate::dictionary::AddressError) -> Self {
        FamilyError::Object(e.reason)
    }
}
