//! Why a raw value and a family's wire bytes do not meet: a value that does not fit the
//! object's type (refused before sending, never sent wrapped), or bytes from the drive that
//! are not a value of the type (a wrong count). Each family's value codec returns it; the
//! drive layer turns it into an access error. Pure data.

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum WireValueError {
    /// The value cannot be sent as the type (out of range, text for a number, too long).
    #[error("{0}")]
    Unfit(String),
    /// The bytes the drive sent are not a value of the type.
    #[error("{0}")]
    Malformed(String),
}
