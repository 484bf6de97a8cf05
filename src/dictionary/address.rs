//! Where an object lives on the drive. SD2 (and CANopen-like families) address objects by
//! a 16-bit index and a 32-bit subindex; other families will add their own variants
//! (menu.parameter, object number, Lenze code). Pure data.

use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Address {
    /// SD2 DNC: index 0..=65535, subindex for arrays and strings (0 otherwise).
    Indexed { index: u16, subindex: u32 },
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
