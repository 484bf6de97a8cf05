//! One CAN frame: an 11-bit (or 29-bit extended) identifier and up to 8 data bytes. Plain
//! data for frame buses; what the identifier means is the family's business.

/// A classic CAN data frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CanFrame {
    pub id: u32,
    pub extended: bool,
    len: u8,
    data: [u8; 8],
}

impl CanFrame {
    /// A standard (11-bit) frame; `None` when the identifier or the data do not fit.
    pub fn new(id: u32, data: &[u8]) -> Option<CanFrame> {
        Self::build(id, false, data)
    }

    /// An extended (29-bit) frame.
    pub fn extended(id: u32, data: &[u8]) -> Option<CanFrame> {
        Self::build(id, true, data)
    }

    fn build(id: u32, extended: bool, data: &[u8]) -> Option<CanFrame> {
        let max_id = if extended { 0x1FFF_FFFF } else { 0x7FF };
        if id > max_id || data.len() > 8 {
            return None;
        }
        let mut bytes = [0u8; 8];
        bytes[..data.len()].copy_from_slice(data);
        Some(CanFrame {
            id,
            extended,
            len: data.len() as u8,
            data: bytes,
        })
    }

    pub fn data(&self) -> &[u8] {
        &self.data[..usize::from(self.len)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_and_lengths_are_checked() {
        let f = CanFrame::new(0x601, &[0x40, 0x63, 0x5f, 0x00]).unwrap();
        assert_eq!(
            (f.id, f.extended, f.data()),
            (0x601, false, &[0x40, 0x63, 0x5f, 0x00][..])
        );
        assert!(CanFrame::new(0x800, &[]).is_none());
        assert!(CanFrame::extended(0x800, &[]).is_some());
        assert!(CanFrame::new(1, &[0; 9]).is_none());
    }
}
