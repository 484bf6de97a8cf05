//! Turns a capture's telegrams into exchanges: each request with the replies that followed
//! it until the next request. Streams, as the capture reader does. Telegrams that carry no
//! direction (a candump log) are given one by the family's classifier; what it calls
//! neither (heartbeats, other nodes' traffic) is left out.

use super::{CaptureError, CaptureReader};
use crate::link::Direction;
use std::io::BufRead;
use std::time::Duration;

/// Tells a request from a reply in a capture that does not say (CAN frames as
/// [`crate::bus::CanFrame::to_bytes`]).
pub type Classifier = Box<dyn Fn(&[u8]) -> Option<Direction> + Send>;

/// One request of the capture and what came back.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Exchange {
    /// The request's line in the capture.
    pub line: u64,
    pub at: Duration,
    pub request: Vec<u8>,
    /// Each reply with its capture time; none when the drive did not answer.
    pub replies: Vec<(Duration, Vec<u8>)>,
}

pub struct ExchangeReader<R: BufRead> {
    records: CaptureReader<R>,
    classify: Classifier,
    /// The request read ahead while collecting the previous one's replies.
    next: Option<Exchange>,
    /// Whether any telegram was a CAN frame.
    frames: bool,
}

impl<R: BufRead> ExchangeReader<R> {
    pub fn new(records: CaptureReader<R>, classify: Classifier) -> Self {
        ExchangeReader {
            records,
            classify,
            next: None,
            frames: false,
        }
    }

    /// Whether the capture so far holds CAN frames (a candump log).
    pub fn is_frames(&self) -> bool {
        self.frames
    }

    /// The next exchange; `Ok(None)` at the end of the capture.
    pub fn next_exchange(&mut self) -> Result<Option<Exchange>, CaptureError> {
        while let Some(record) = self.records.next_record()? {
            self.frames |= record.frame;
            let direction = record.direction.or_else(|| (self.classify)(&record.bytes));
            match direction {
                Some(Direction::Sent) => {
                    let exchange = Exchange {
                        line: record.line,
                        at: record.at,
                        request: record.bytes,
                        replies: Vec::new(),
                    };
                    if let Some(done) = self.next.replace(exchange) {
                        return Ok(Some(done));
                    }
                }
                // A reply before the first request answers nothing we can be asked.
                Some(Direction::Received) => {
                    if let Some(current) = &mut self.next {
                        current.replies.push((record.at, record.bytes));
                    }
                }
                None => {}
            }
        }
        Ok(self.next.take())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_collect_the_replies_until_the_next_request() {
        let text = "    0.1 RX ff\n    1.0 TX 01\n    1.1 RX 02\n    1.2 RX 03\n    2.0 TX 04\n    3.0 TX 05\n    3.1 RX 06\n";
        let mut r = ExchangeReader::new(CaptureReader::new(text.as_bytes(), "c"), Box::new(|_| None));
        let a = r.next_exchange().unwrap().unwrap();
        assert_eq!((a.line, a.request.clone(), a.replies.len()), (2, vec![1], 2));
        let b = r.next_exchange().unwrap().unwrap();
        assert_eq!((b.request.clone(), b.replies.len()), (vec![4], 0));
        let c = r.next_exchange().unwrap().unwrap();
        assert_eq!(c.replies, vec![(Duration::from_millis(3100), vec![6])]);
        assert_eq!(r.next_exchange().unwrap(), None);
    }

    #[test]
    fn frames_without_direction_are_classified_and_others_left_out() {
        let text = "(1.000000) can0 701#05\n(1.000100) can0 601#40\n(1.000200) can0 581#43\n";
        let classify: Classifier = Box::new(|bytes| match crate::bus::CanFrame::from_bytes(bytes)?.id {
            0x601 => Some(Direction::Sent),
            0x581 => Some(Direction::Received),
            _ => None,
        });
        let mut r = ExchangeReader::new(CaptureReader::new(text.as_bytes(), "c"), classify);
        let a = r.next_exchange().unwrap().unwrap();
        assert_eq!(a.line, 2);
        assert_eq!(a.replies.len(), 1);
        assert!(r.is_frames());
    }
}
