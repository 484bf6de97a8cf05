//! The simulated Lenze 9400 node as a frame-level peer: decodes every SDO request on
//! 0x600 + node, serves expedited and segmented uploads and downloads with the toggle bit
//! (aborting a broken sequence as a real node does), and encodes every response, applying
//! the injected faults. No shortcuts around the codec, and no clock of its own: time is the
//! `now` it is given.
//!
//! Injected faults on CAN: a dropped or late response as on a serial line; a "corrupt"
//! response goes out with a block-transfer command byte the client must refuse (CAN's own
//! CRC means a damaged frame never reaches the host, so this stands for a confused node);
//! a "wrong address" response comes from the next node's identifier; a lost line is a
//! lost adapter.

use super::sim_codes::{Place, SimCodes};
use crate::bus::{CanFrame, FramePeer};
use crate::family::lenze_9400::codec::{
    request_id, response_id, AbortCode, SdoRequest, SdoResponse, MAX_TRANSFER,
};
use crate::sim::{SimConfig, SimCore, SimFront};
use std::time::Duration;

pub use super::sim_codes::FIRMWARE_VERSION;

#[derive(Debug, Clone)]
enum Transfer {
    Idle,
    Upload {
        place: Place,
        data: Vec<u8>,
        sent: usize,
        toggle: bool,
    },
    Download {
        place: Place,
        size: Option<u32>,
        data: Vec<u8>,
        toggle: bool,
    },
}

#[derive(Debug)]
pub struct Lenze9400Simulator {
    /// The model, the faults and the log of decoded requests (no control words: the 9400
    /// is not commanded through a control word here, it has no profile).
    core: SimCore<(Duration, SdoRequest)>,
    node: u8,
    codes: SimCodes,
    transfer: Transfer,
}

impl Lenze9400Simulator {
    /// A node just powered up at `node` (1..=127).
    pub fn new(node: u8, config: SimConfig) -> Self {
        Lenze9400Simulator {
            core: SimCore::new(config),
            node,
            codes: SimCodes::default(),
            transfer: Transfer::Idle,
        }
    }

    pub fn node(&self) -> u8 {
        self.node
    }

    /// The requests decoded, with the time each arrived (the latest ones, bounded).
    pub fn received(&self) -> &[(Duration, SdoRequest)] {
        self.core.requests()
    }

    /// The stored codes (rated current, reference speed, enable).
    pub fn codes(&self) -> &SimCodes {
        &self.codes
    }

    fn answer(&mut self, request: &SdoRequest) -> Option<SdoResponse> {
        let abort = |place: Place, code: AbortCode| SdoResponse::Abort {
            index: place.0,
            subindex: place.1,
            code,
        };
        let transfer = std::mem::replace(&mut self.transfer, Transfer::Idle);
        Some(match (request, transfer) {
            (SdoRequest::Abort { .. }, _) => return None,
            (&SdoRequest::UploadInitiate { index, subindex }, _) => {
                let place = (index, subindex);
                match self.codes.read(&mut self.core.model, place) {
                    Err(code) => abort(place, code),
                    Ok(data) if data.len() <= 4 => {
                        let mut value = [0u8; 4];
                        value[..data.len()].copy_from_slice(&data);
                        SdoResponse::UploadExpedited {
                            index,
                            subindex,
                            data: value,
                            size: Some(data.len() as u8),
                        }
                    }
                    Ok(data) => {
                        let size = data.len() as u32;
                        self.transfer = Transfer::Upload {
                            place,
                            data,
                            sent: 0,
                            toggle: false,
                        };
                        SdoResponse::UploadInitiate {
                            index,
                            subindex,
                            size: Some(size),
                        }
                    }
                }
            }
            (
                &SdoRequest::UploadSegment { toggle },
                Transfer::Upload {
                    place,
                    data,
                    sent,
                    toggle: expected,
                },
            ) => {
                if toggle != expected {
                    return Some(abort(place, AbortCode::TOGGLE_BIT));
                }
                let end = (sent + 7).min(data.len());
                let part = data[sent..end].to_vec();
                let last = end == data.len();
                if !last {
                    self.transfer = Transfer::Upload {
                        place,
                        data,
                        sent: end,
                        toggle: !toggle,
                    };
                }
                SdoResponse::UploadSegment {
                    toggle,
                    data: part,
                    last,
                }
            }
            (
                &SdoRequest::DownloadExpedited {
                    index,
                    subindex,
                    data,
                    size,
                },
                _,
            ) => {
                let n = usize::from(size.unwrap_or(4));
                match self.codes.write((index, subindex), &data[..n]) {
                    Ok(()) => SdoResponse::DownloadInitiate { index, subindex },
                    Err(code) => abort((index, subindex), code),
                }
            }
            (
                &SdoRequest::DownloadInitiate {
                    index,
                    subindex,
                    size,
                },
                _,
            ) => {
                if size.is_some_and(|s| s as usize > MAX_TRANSFER) {
                    return Some(abort((index, subindex), AbortCode::LENGTH_MISMATCH));
                }
                self.transfer = Transfer::Download {
                    place: (index, subindex),
                    size,
                    data: Vec::new(),
                    toggle: false,
                };
                SdoResponse::DownloadInitiate { index, subindex }
            }
            (
                SdoRequest::DownloadSegment { toggle, data, last },
                Transfer::Download {
                    place,
                    size,
                    data: mut so_far,
                    toggle: expected,
                },
            ) => {
                if *toggle != expected {
                    return Some(abort(place, AbortCode::TOGGLE_BIT));
                }
                so_far.extend_from_slice(data);
                if so_far.len() > size.map_or(MAX_TRANSFER, |s| s as usize) {
                    return Some(abort(place, AbortCode::LENGTH_MISMATCH));
                }
                if *last {
                    if size.is_some_and(|s| s as usize != so_far.len()) {
                        return Some(abort(place, AbortCode::LENGTH_MISMATCH));
                    }
                    if let Err(code) = self.codes.write(place, &so_far) {
                        return Some(abort(place, code));
                    }
                } else {
                    self.transfer = Transfer::Download {
                        place,
                        size,
                        data: so_far,
                        toggle: !expected,
                    };
                }
                SdoResponse::DownloadSegment { toggle: *toggle }
            }
            // A segment without a transfer under way: CiA 301's answer is an abort.
            (SdoRequest::UploadSegment { .. } | SdoRequest::DownloadSegment { .. }, _) => {
                abort((0, 0), AbortCode::INVALID_COMMAND)
            }
        })
    }

    /// The response as a frame, with the injected faults: `None` when it is dropped.
    fn send(&mut self, response: &SdoResponse, now: Duration) -> Option<(Duration, CanFrame)> {
        let fate = self.core.faults.next_reply();
        if fate.dropped {
            return None;
        }
        let mut data = response.encode();
        if fate.corrupt_checksum {
            data[0] = 0xC0;
        }
        let id = if fate.wrong_address {
            response_id(self.node.wrapping_add(1))
        } else {
            response_id(self.node)
        };
        let at = now + self.core.model.config().response_latency + fate.extra_delay;
        Some((at, CanFrame::standard8(id, data)))
    }
}

impl FramePeer for Lenze9400Simulator {
    fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
        self.core.panic_if_due(now);
        if frame.extended || frame.id != request_id(self.node) {
            return Vec::new();
        }
        self.core.advance_to(now);
        let request = match SdoRequest::decode(frame.data()) {
            Ok(r) => r,
            Err(_) => {
                // A node aborts what it cannot read (CiA 301: command specifier not valid).
                let response = SdoResponse::Abort {
                    index: 0,
                    subindex: 0,
                    code: AbortCode::INVALID_COMMAND,
                };
                return self.send(&response, now).into_iter().collect();
            }
        };
        self.core.log_request((now, request.clone()));
        match self.answer(&request) {
            Some(response) => self.send(&response, now).into_iter().collect(),
            None => Vec::new(),
        }
    }

    fn reachable(&self, now: Duration) -> bool {
        self.core.faults.line_up(now)
    }
}

impl SimFront for Lenze9400Simulator {
    crate::sim_front_core!((Duration, SdoRequest));
    fn describe_drive(&self) -> String {
        format!(
            "simulated Lenze 9400 at CAN node {} (firmware {FIRMWARE_VERSION})",
            self.node
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hex::{parse_hex, to_hex};

    fn ask(sim: &mut Lenze9400Simulator, node_id: u32, hex: &str) -> Vec<String> {
        let data: [u8; 8] = parse_hex(hex).unwrap().try_into().unwrap();
        sim.receive(&CanFrame::standard8(node_id, data), Duration::ZERO)
            .into_iter()
            .map(|(_, f)| f.to_candump())
            .collect()
    }

    #[test]
    fn the_worked_examples_answered_by_the_simulated_node() {
        let mut sim = Lenze9400Simulator::new(12, SimConfig::default());
        assert_eq!(
            ask(&mut sim, 0x60C, "40 9c 5f 00 00 00 00 00"),
            ["58C#419C5F000B000000"]
        );
        assert_eq!(
            ask(&mut sim, 0x60C, "60 00 00 00 00 00 00 00"),
            ["58C#0030352E30302E31"]
        );
        assert_eq!(
            ask(&mut sim, 0x60C, "70 00 00 00 00 00 00 00"),
            ["58C#17322E3037000000"]
        );
        let mut node5 = Lenze9400Simulator::new(5, SimConfig::default());
        assert_eq!(
            ask(&mut node5, 0x605, "40 c2 5f 00 00 00 00 00"),
            ["585#43C25F002B000000"]
        );
        let mut node2 = Lenze9400Simulator::new(2, SimConfig::default());
        assert_eq!(
            ask(&mut node2, 0x602, "23 a7 5f 00 66 00 00 00"),
            ["582#60A75F0000000000"]
        );
        assert_eq!(node2.codes().rated_current, 102);
    }

    #[test]
    fn other_nodes_frames_are_not_answered_and_errors_are_aborts() {
        let mut sim = Lenze9400Simulator::new(12, SimConfig::default());
        assert!(ask(&mut sim, 0x60D, "40 9c 5f 00 00 00 00 00").is_empty());
        // C00999 does not exist.
        assert_eq!(
            ask(&mut sim, 0x60C, "40 18 5c 00 00 00 00 00"),
            ["58C#80185C0000000206"]
        );
        // A segment with the wrong toggle bit.
        ask(&mut sim, 0x60C, "40 9c 5f 00 00 00 00 00");
        assert_eq!(
            ask(&mut sim, 0x60C, "70 00 00 00 00 00 00 00"),
            ["58C#809C5F0000000305"]
        );
        // The heatsink temperature is read-only.
        let abort = ask(&mut sim, 0x60C, "23 c2 5f 00 01 00 00 00");
        assert_eq!(abort, ["58C#80C25F0002000106"]);
        let _ = to_hex(&[]);
    }
}
