//! One SDO transfer as a pure state machine: [`SdoClient::upload`] or
//! [`SdoClient::download`] gives the first request; each response fed to
//! [`SdoClient::on_response`] gives the next request, the result, the node's abort, or a
//! protocol error together with the abort to send so the node does not wait for a
//! transfer that will not continue. No I/O and no clock: timeouts are the link's business
//! ([`SdoClient::timeout_abort`] is what it sends then).
//!
//! Checked: the multiplexer of every initiate response, the toggle bit of every segment
//! (it starts at 0 and alternates), the command specifier, the indicated size against the
//! data that arrived, and [`MAX_TRANSFER`] so that a node that never sets the last bit
//! cannot make the client store without bound.

use super::{AbortCode, SdoDecodeError, SdoRequest, SdoResponse, Segment};

/// Most bytes one transfer carries: the longest value a dictionary may declare (a byte
/// string, UTF-16 text or DOMAIN of [`crate::dictionary::MAX_BLOCK_LEN`]), with room for
/// a node that pads a string. More is refused and aborted.
pub const MAX_TRANSFER: usize = crate::dictionary::MAX_BLOCK_LEN;

/// What the client does next.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SdoStep {
    /// Send this request and feed the response back.
    Send(SdoRequest),
    /// The upload finished.
    Uploaded(Uploaded),
    /// The download finished.
    Downloaded,
    /// The node aborted the transfer.
    Aborted(AbortCode),
    /// The response broke the protocol: send `abort` (if any) and report `problem`.
    Failed {
        problem: String,
        abort: Option<SdoRequest>,
    },
    /// The response is not for this transfer (another object's late answer): keep waiting.
    Ignored(String),
    /// The node's value is longer than a transfer takes here: send `abort` and report
    /// `problem`. Not tried again: it is the node's answer, which it would give again.
    TooLong { problem: String, abort: SdoRequest },
}

/// The value an upload delivered.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Uploaded {
    pub data: Vec<u8>,
    /// Whether the node said how many bytes the value has (an expedited response without
    /// size carries 4 bytes of which an unknown number are the value).
    pub size_indicated: bool,
    /// Whether the value came in segments.
    pub segmented: bool,
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum State {
    UploadInitiate,
    UploadSegments {
        toggle: bool,
        size: Option<u32>,
        data: Vec<u8>,
    },
    DownloadInitiate {
        segmented: bool,
    },
    DownloadSegments {
        toggle: bool,
        sent: usize,
    },
    Done,
}

/// One transfer to one object of one node.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SdoClient {
    index: u16,
    subindex: u8,
    /// The value of a download.
    value: Vec<u8>,
    state: State,
}

impl SdoClient {
    /// A read of `index`/`subindex` and its first request.
    pub fn upload(index: u16, subindex: u8) -> (SdoClient, SdoRequest) {
        let client = SdoClient {
            index,
            subindex,
            value: Vec::new(),
            state: State::UploadInitiate,
        };
        (client, SdoRequest::UploadInitiate { index, subindex })
    }

    /// A write of `data`: expedited up to 4 bytes, segmented beyond (at most
    /// [`MAX_TRANSFER`]); `None` for an empty or too long value.
    pub fn download(index: u16, subindex: u8, data: &[u8]) -> Option<(SdoClient, SdoRequest)> {
        if data.is_empty() || data.len() > MAX_TRANSFER {
            return None;
        }
        let segmented = data.len() > 4;
        let request = if segmented {
            SdoRequest::DownloadInitiate {
                index,
                subindex,
                size: Some(data.len() as u32),
            }
        } else {
            let mut value = [0u8; 4];
            value[..data.len()].copy_from_slice(data);
            SdoRequest::DownloadExpedited {
                index,
                subindex,
                data: value,
                size: Some(data.len() as u8),
            }
        };
        let client = SdoClient {
            index,
            subindex,
            value: data.to_vec(),
            state: State::DownloadInitiate { segmented },
        };
        Some((client, request))
    }

    pub fn object(&self) -> (u16, u8) {
        (self.index, self.subindex)
    }

    /// The abort to send when the node stopped answering in the middle of a transfer.
    pub fn timeout_abort(&self) -> SdoRequest {
        self.abort(AbortCode::TIMEOUT)
    }

    fn abort(&self, code: AbortCode) -> SdoRequest {
        SdoRequest::Abort {
            index: self.index,
            subindex: self.subindex,
            code,
        }
    }

    fn too_long(&mut self, problem: String) -> SdoStep {
        self.state = State::Done;
        SdoStep::TooLong {
            problem,
            abort: self.abort(AbortCode::LENGTH_MISMATCH),
        }
    }

    fn fail(&mut self, problem: String, code: AbortCode) -> SdoStep {
        self.state = State::Done;
        SdoStep::Failed {
            problem,
            abort: Some(self.abort(code)),
        }
    }

    /// The failure of a segment whose toggle bit is not `expected`, aborted with
    /// 0x05030000; `None` when it is.
    fn wrong_toggle(&mut self, segment: &str, expected: bool, echoed: bool) -> Option<SdoStep> {
        (echoed != expected).then(|| {
            self.fail(
                format!(
                    "{segment} toggle bit expected {}, got {}",
                    u8::from(expected),
                    u8::from(echoed)
                ),
                AbortCode::TOGGLE_BIT,
            )
        })
    }

    /// Feeds the 8 data bytes of a frame from the node.
    pub fn on_bytes(&mut self, bytes: &[u8]) -> SdoStep {
        match SdoResponse::decode(bytes) {
            Ok(r) => self.on_response(&r),
            Err(e @ SdoDecodeError::Length(_)) => self.fail(e.to_string(), AbortCode::GENERAL_ERROR),
            Err(e) => self.fail(e.to_string(), AbortCode::INVALID_COMMAND),
        }
    }

    /// Feeds one decoded response.
    pub fn on_response(&mut self, response: &SdoResponse) -> SdoStep {
        if let SdoResponse::Abort {
            index,
            subindex,
            code,
        } = *response
        {
            if (index, subindex) == (self.index, self.subindex) || response.object().is_none() {
                self.state = State::Done;
                return SdoStep::Aborted(code);
            }
            return SdoStep::Ignored(format!(
                "abort for index 0x{index:04X}/{subindex}, not this transfer's object"
            ));
        }
        if let Some((index, subindex)) = response.object() {
            if (index, subindex) != (self.index, self.subindex) {
                return SdoStep::Ignored(format!(
                    "response for index 0x{index:04X}/{subindex}, expected 0x{:04X}/{}",
                    self.index, self.subindex
                ));
            }
        }
        let state = std::mem::replace(&mut self.state, State::Done);
        match (state, response) {
            (State::UploadInitiate, SdoResponse::UploadExpedited { data, size, .. }) => {
                let n = usize::from(size.unwrap_or(4));
                SdoStep::Uploaded(Uploaded {
                    data: data[..n].to_vec(),
                    size_indicated: size.is_some(),
                    segmented: false,
                })
            }
            (State::UploadInitiate, SdoResponse::UploadInitiate { size, .. }) => {
                if let Some(s) = size.filter(|s| *s as usize > MAX_TRANSFER) {
                    return self.too_long(format!(
                        "the node announces {s} bytes; drivescript takes at most {MAX_TRANSFER}"
                    ));
                }
                self.state = State::UploadSegments {
                    toggle: false,
                    size: *size,
                    data: Vec::new(),
                };
                SdoStep::Send(SdoRequest::UploadSegment { toggle: false })
            }
            (
                State::UploadSegments {
                    toggle,
                    size,
                    mut data,
                },
                SdoResponse::UploadSegment(Segment {
                    toggle: echoed,
                    data: part,
                    last,
                }),
            ) => {
                if let Some(failed) = self.wrong_toggle("upload segment", toggle, *echoed) {
                    return failed;
                }
                data.extend_from_slice(part);
                match size {
                    Some(s) if data.len() > s as usize => {
                        return self.fail(
                            format!("the segments carry more than the {s} bytes announced"),
                            AbortCode::LENGTH_MISMATCH,
                        );
                    }
                    None if data.len() > MAX_TRANSFER => {
                        return self.too_long(format!(
                            "the node sends more than the {MAX_TRANSFER} bytes drivescript takes (it announced no size)"
                        ));
                    }
                    _ => {}
                }
                if !*last {
                    self.state = State::UploadSegments {
                        toggle: !toggle,
                        size,
                        data,
                    };
                    return SdoStep::Send(SdoRequest::UploadSegment { toggle: !toggle });
                }
                if let Some(s) = size.filter(|&s| s as usize != data.len()) {
                    return SdoStep::Failed {
                        problem: format!("the node announced {s} bytes but sent {}", data.len()),
                        abort: None,
                    };
                }
                SdoStep::Uploaded(Uploaded {
                    data,
                    size_indicated: size.is_some(),
                    segmented: true,
                })
            }
            (State::DownloadInitiate { segmented: false }, SdoResponse::DownloadInitiate { .. }) => {
                SdoStep::Downloaded
            }
            (State::DownloadInitiate { segmented: true }, SdoResponse::DownloadInitiate { .. }) => {
                self.next_download_segment(false, 0)
            }
            (State::DownloadSegments { toggle, sent }, SdoResponse::DownloadSegment { toggle: echoed }) => {
                if let Some(failed) = self.wrong_toggle("download segment", toggle, *echoed) {
                    return failed;
                }
                if sent >= self.value.len() {
                    SdoStep::Downloaded
                } else {
                    self.next_download_segment(!toggle, sent)
                }
            }
            (State::Done, _) => SdoStep::Ignored("the transfer is already over".into()),
            (_, other) => self.fail(
                format!("unexpected {other} at this point of the transfer"),
                AbortCode::INVALID_COMMAND,
            ),
        }
    }

    fn next_download_segment(&mut self, toggle: bool, from: usize) -> SdoStep {
        let end = (from + 7).min(self.value.len());
        let data = self.value[from..end].to_vec();
        let last = end == self.value.len();
        self.state = State::DownloadSegments { toggle, sent: end };
        SdoStep::Send(SdoRequest::DownloadSegment(Segment { toggle, data, last }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hex::{parse_hex, to_hex};
    use proptest::prelude::*;

    fn feed(client: &mut SdoClient, hex: &str) -> SdoStep {
        client.on_bytes(&parse_hex(hex).unwrap())
    }

    /// The abort frame (hex) a failed step sends to the node.
    #[track_caller]
    fn abort_sent(step: SdoStep) -> String {
        match step {
            SdoStep::Failed { abort: Some(a), .. } => to_hex(&a.encode()),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn firmware_read_of_eleven_characters_in_two_segments() {
        let (mut c, first) = SdoClient::upload(0x5F9C, 0);
        assert_eq!(to_hex(&first.encode()), "40 9c 5f 00 00 00 00 00");
        let SdoStep::Send(seg0) = feed(&mut c, "41 9c 5f 00 0b 00 00 00") else {
            panic!("expected a segment request")
        };
        assert_eq!(to_hex(&seg0.encode()), "60 00 00 00 00 00 00 00");
        // 7 bytes, toggle 0, not last.
        let SdoStep::Send(seg1) = feed(&mut c, "00 30 35 2e 30 30 2e 31") else {
            panic!("expected a second segment request")
        };
        assert_eq!(to_hex(&seg1.encode()), "70 00 00 00 00 00 00 00");
        // 4 bytes, toggle 1, 3 unused, last: 0001 0111.
        let done = feed(&mut c, "17 32 2e 30 37 00 00 00");
        assert_eq!(
            done,
            SdoStep::Uploaded(Uploaded {
                data: b"05.00.12.07".to_vec(),
                size_indicated: true,
                segmented: true
            })
        );
    }

    #[test]
    fn temperature_read_expedited() {
        let (mut c, first) = SdoClient::upload(0x5FC2, 0);
        assert_eq!(to_hex(&first.encode()), "40 c2 5f 00 00 00 00 00");
        assert_eq!(
            feed(&mut c, "43 c2 5f 00 2b 00 00 00"),
            SdoStep::Uploaded(Uploaded {
                data: vec![0x2b, 0, 0, 0],
                size_indicated: true,
                segmented: false
            })
        );
    }

    #[test]
    fn write_of_102_sends_the_corrected_bytes() {
        let (mut c, first) = SdoClient::download(0x5FA7, 0, &102i32.to_le_bytes()).unwrap();
        assert_eq!(to_hex(&first.encode()), "23 a7 5f 00 66 00 00 00");
        assert_eq!(feed(&mut c, "60 a7 5f 00 00 00 00 00"), SdoStep::Downloaded);
    }

    #[test]
    fn a_wrong_toggle_bit_is_aborted_with_the_toggle_code() {
        let (mut c, _) = SdoClient::upload(0x5F9C, 0);
        feed(&mut c, "41 9c 5f 00 0b 00 00 00");
        match feed(&mut c, "10 30 35 2e 30 30 2e 31") {
            SdoStep::Failed {
                problem,
                abort: Some(abort),
            } => {
                assert!(problem.contains("toggle bit expected 0, got 1"), "{problem}");
                assert_eq!(to_hex(&abort.encode()), "80 9c 5f 00 00 00 03 05");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn an_unknown_command_is_aborted_as_invalid() {
        let (mut c, _) = SdoClient::upload(0x5FC2, 0);
        assert_eq!(
            abort_sent(feed(&mut c, "c1 c2 5f 00 00 00 00 00")),
            "80 c2 5f 00 01 00 04 05"
        );
    }

    #[test]
    fn the_nodes_abort_ends_the_transfer() {
        let (mut c, _) = SdoClient::upload(0x5F9C, 0);
        assert_eq!(
            feed(&mut c, "80 9c 5f 00 41 00 04 06"),
            SdoStep::Aborted(AbortCode(0x0604_0041))
        );
    }

    #[test]
    fn another_objects_response_is_ignored() {
        let (mut c, _) = SdoClient::upload(0x5F9C, 0);
        assert!(matches!(
            feed(&mut c, "43 c2 5f 00 2b 00 00 00"),
            SdoStep::Ignored(_)
        ));
        assert!(matches!(
            feed(&mut c, "41 9c 5f 00 0b 00 00 00"),
            SdoStep::Send(_)
        ));
    }

    #[test]
    fn more_data_than_announced_is_aborted() {
        let (mut c, _) = SdoClient::upload(0x5F9C, 0);
        feed(&mut c, "41 9c 5f 00 03 00 00 00");
        assert_eq!(
            abort_sent(feed(&mut c, "00 30 35 2e 30 30 2e 31")),
            "80 9c 5f 00 10 00 07 06"
        );
    }

    #[test]
    fn a_segmented_download_alternates_the_toggle() {
        let text = b"0123456789ABC";
        let (mut c, first) = SdoClient::download(0x5F37, 0, text).unwrap();
        assert_eq!(to_hex(&first.encode()), "21 37 5f 00 0d 00 00 00");
        let SdoStep::Send(s0) = feed(&mut c, "60 37 5f 00 00 00 00 00") else {
            panic!()
        };
        assert_eq!(to_hex(&s0.encode()), "00 30 31 32 33 34 35 36");
        let SdoStep::Send(s1) = feed(&mut c, "20 00 00 00 00 00 00 00") else {
            panic!()
        };
        // 6 bytes, 1 unused, last, toggle 1: 0001 0011.
        assert_eq!(to_hex(&s1.encode()), "13 37 38 39 41 42 43 00");
        assert_eq!(feed(&mut c, "30 00 00 00 00 00 00 00"), SdoStep::Downloaded);
    }

    proptest! {
        /// Any sequence of frames from a node ends the transfer, keeps asking, or is
        /// ignored — never a panic, never more than MAX_TRANSFER bytes kept.
        #[test]
        fn any_responses_are_handled(frames in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 8), 0..50)) {
            let (mut c, _) = SdoClient::upload(0x5F9C, 0);
            for f in frames {
                if let SdoStep::Uploaded(u) = c.on_bytes(&f) {
                    prop_assert!(u.data.len() <= MAX_TRANSFER);
                }
            }
        }
    }
}
