//! Where an object lives on the drive: a 16-bit index and a 32-bit subindex, which each
//! family reads in its own way (SD2 and CANopen: index/subindex; a menu.parameter or a
//! code/subcode family maps its notation onto the pair). A dictionary writes either
//! `index:`/`subindex:` or `address: TEXT` in the family's notation, which the family's
//! [`AddressParser`] reads. Pure data.

use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Address {
    /// Index 0..=65535 and subindex (0 for plain objects).
    Indexed { index: u16, subindex: u32 },
}

/// A family's reading of the `address:` text in its dictionaries; the error says what the
/// notation is.
pub type AddressParser = fn(&str) -> Result<Address, AddressError>;

/// An object address not in the family's notation: the dictionary entry (or the object
/// named on the command line) is wrong, not the drive.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{reason}")]
pub struct AddressError {
    /// What is wrong and how the notation goes.
    pub reason: String,
}

impl From<String> for AddressError {
    fn from(reason: String) -> Self {
        AddressError { reason }
    }
}

impl Address {
    pub fn indexed(index: u16, subindex: u32) -> Self {
        Address::Indexed { index, subindex }
    }

    /// The index, for families that have one.
    pub fn index(&self) -> Option<u16> {
        match self {
            Address::Indexed { index, .. } => Some(*index),
        }
    }

    /// The subindex (0 for a plain object).
    pub fn subindex(&self) -> u32 {
        match self {
            Address::Indexed { subindex, .. } => *subindex,
        }
    }
}

impl fmt::Display for Address {
    /// `index 395 (0x018b)`, with `, subindex 1` when the subindex is not 0.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Address::Indexed { index, subindex } => {
                write!(f, "index {index} (0x{index:04x})")?;
                if *subindex != 0 {
                    write!(f, ", subindex {subindex}")?;
                }
                Ok(())
            }
        }
    }
}
