//! The user-data field of a block: at most 48 bytes, kept inline so a decoded telegram
//! needs no allocation.

use super::MAX_DATA;
use std::fmt;

/// Up to [`MAX_DATA`] bytes.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Data {
    len: u8,
    bytes: [u8; MAX_DATA],
}

impl Data {
    pub const EMPTY: Data = Data {
        len: 0,
        bytes: [0; MAX_DATA],
    };

    /// `None` when `bytes` is longer than 48.
    pub fn new(bytes: &[u8]) -> Option<Data> {
        if bytes.len() > MAX_DATA {
            return None;
        }
        let mut d = Data::EMPTY;
        d.bytes[..bytes.len()].copy_from_slice(bytes);
        d.len = bytes.len() as u8;
        Some(d)
    }

    pub fn as_slice(&self) -> &[u8] {
        &self.bytes[..usize::from(self.len)]
    }

    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The bytes as a little-endian unsigned number, when there are 1 to 4 of them.
    pub fn as_u32_le(&self) -> Option<u32> {
        let s = self.as_slice();
        if s.is_empty() || s.len() > 4 {
            return None;
        }
        Some(s.iter().rev().fold(0u32, |acc, b| (acc << 8) | u32::from(*b)))
    }
}

impl fmt::Debug for Data {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Data[{}]", crate::hex::to_hex(self.as_slice()))
    }
}

impl Default for Data {
    fn default() -> Self {
        Data::EMPTY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_and_numbers() {
        assert!(Data::new(&[0; 48]).is_some());
        assert!(Data::new(&[0; 49]).is_none());
        let d = Data::new(&[0x40, 0x42, 0x0f, 0x00]).unwrap();
        assert_eq!(d.as_u32_le(), Some(1_000_000));
        assert_eq!(Data::EMPTY.as_u32_le(), None);
        assert_eq!(format!("{d:?}"), "Data[40 42 0f 00]");
    }
}
