//! The bytes of each node's segmented SDO transfer as an explainer sees its frames go by,
//! so that the last segment can be read as the whole value (a 64-bit count comes in two
//! segments). Bounded: a transfer beyond what one SDO transfer carries here is not kept,
//! nor one whose start was not seen. Pure.

use super::codec::MAX_TRANSFER;
use std::collections::HashMap;

#[derive(Debug, Default)]
pub struct TransferBytes {
    /// Per node, the bytes so far; `None` after more than a transfer carries.
    by_node: HashMap<u8, Option<Vec<u8>>>,
}

impl TransferBytes {
    /// A frame that opens a transfer (or is one, expedited) was seen: the node's
    /// segments from here on are this transfer's.
    pub fn start(&mut self, node: u8) {
        self.by_node.insert(node, Some(Vec::new()));
    }

    /// A segment's data; on the last one, the whole transfer's bytes (`None` when its
    /// start was not seen or it grew beyond a transfer).
    pub fn segment(&mut self, node: u8, data: &[u8], last: bool) -> Option<Vec<u8>> {
        let kept = self.by_node.get_mut(&node)?;
        if let Some(bytes) = kept {
            bytes.extend_from_slice(data);
            if bytes.len() > MAX_TRANSFER {
                *kept = None;
            }
        }
        match last {
            true => self.by_node.remove(&node).flatten(),
            false => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn the_last_segment_gives_the_whole_transfer_once() {
        let mut t = TransferBytes::default();
        assert_eq!(t.segment(1, &[1, 2], true), None, "no start seen");
        t.start(1);
        t.start(2);
        assert_eq!(t.segment(1, &[0xff; 7], false), None);
        assert_eq!(t.segment(2, &[9], true), Some(vec![9]), "nodes apart");
        let mut whole = vec![0xff; 7];
        whole.push(0x7f);
        assert_eq!(t.segment(1, &[0x7f], true), Some(whole));
        assert_eq!(t.segment(1, &[0x7f], true), None, "taken");
        t.start(3);
        for _ in 0..37 {
            t.segment(3, &[0; 7], false);
        }
        assert_eq!(t.segment(3, &[0], true), None, "beyond a transfer");
    }

    proptest! {
        /// Whatever segments come, the bytes kept stay within a transfer and nothing panics.
        #[test]
        fn any_segments_stay_bounded(segments in proptest::collection::vec((0u8..3, proptest::collection::vec(any::<u8>(), 0..8), any::<bool>(), any::<bool>()), 0..200)) {
            let mut t = TransferBytes::default();
            for (node, data, last, start) in segments {
                if start {
                    t.start(node);
                }
                if let Some(whole) = t.segment(node, &data, last) {
                    prop_assert!(whole.len() <= MAX_TRANSFER);
                }
            }
        }
    }
}
