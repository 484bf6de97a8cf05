//! The SDO server every simulated CANopen node shares: decodes each request on
//! 0x600 + node, serves expedited and segmented uploads and downloads with the toggle bit
//! (aborting a broken sequence as a real node does) against the node's [`ObjectStore`], and
//! encodes every response with the injected faults applied. No shortcuts around the codec,
//! and no clock of its own: time is the `now` it is given.
//!
//! Injected faults on CAN: a dropped or late response as on a serial line; a "corrupt"
//! response goes out with a block-transfer command byte the client must refuse (CAN's own
//! CRC means a damaged frame never reaches the host, so this stands for a confused node);
//! a "wrong address" response comes from the next node's identifier.

use crate::bus::CanFrame;
use crate::family::canopen::codec::{
    request_id, response_id, AbortCode, SdoRequest, SdoResponse, Segment, MAX_TRANSFER,
};
use crate::sim::SimCore;
use std::time::Duration;

/// An object's place: (index, subindex).
pub type Place = (u16, u8);

/// What a simulated node logs per request: the time it arrived and the request.
pub type SdoLogged = (Duration, SdoRequest);

/// A node's objects as SDO sees them: value bytes out, value bytes in, or the abort code.
pub trait ObjectStore {
    fn read(&mut self, core: &mut SimCore<SdoLogged>, place: Place) -> Result<Vec<u8>, AbortCode>;
    fn write(&mut self, core: &mut SimCore<SdoLogged>, place: Place, bytes: &[u8]) -> Result<(), AbortCode>;
}

#[derive(Debug, Clone, Default)]
enum Transfer {
    #[default]
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

/// One node's SDO server: the transfer under way.
#[derive(Debug, Default)]
pub struct SdoServer {
    transfer: Transfer,
}

impl SdoServer {
    /// The frames `node` sends back for `frame` (none for other identifiers), with their
    /// time on the bus.
    pub fn receive(
        &mut self,
        frame: &CanFrame,
        now: Duration,
        node: u8,
        core: &mut SimCore<SdoLogged>,
        store: &mut dyn ObjectStore,
    ) -> Vec<(Duration, CanFrame)> {
        if frame.extended || frame.id != request_id(node) {
            return Vec::new();
        }
        core.advance_to(now);
        let request = match SdoRequest::decode(frame.data()) {
            Ok(r) => r,
            Err(_) => {
                // A node aborts what it cannot read (CiA 301: command specifier not valid).
                let response = SdoResponse::Abort {
                    index: 0,
                    subindex: 0,
                    code: AbortCode::INVALID_COMMAND,
                };
                return send(core, node, &response, now).into_iter().collect();
            }
        };
        core.log_request((now, request.clone()));
        match self.answer(&request, core, store) {
            Some(response) => send(core, node, &response, now).into_iter().collect(),
            None => Vec::new(),
        }
    }

    fn answer(
        &mut self,
        request: &SdoRequest,
        core: &mut SimCore<SdoLogged>,
        store: &mut dyn ObjectStore,
    ) -> Option<SdoResponse> {
        let abort = |place: Place, code: AbortCode| SdoResponse::Abort {
            index: place.0,
            subindex: place.1,
            code,
        };
        let transfer = std::mem::take(&mut self.transfer);
        Some(match (request, transfer) {
            (SdoRequest::Abort { .. }, _) => return None,
            (&SdoRequest::UploadInitiate { index, subindex }, _) => {
                let place = (index, subindex);
                match store.read(core, place) {
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
                SdoResponse::UploadSegment(Segment {
                    toggle,
                    data: part,
                    last,
                })
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
                match store.write(core, (index, subindex), &data[..n]) {
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
                SdoRequest::DownloadSegment(Segment { toggle, data, last }),
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
                    if let Err(code) = store.write(core, place, &so_far) {
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
}

/// The response as a frame, with the injected faults: `None` when it is dropped.
fn send(
    core: &mut SimCore<SdoLogged>,
    node: u8,
    response: &SdoResponse,
    now: Duration,
) -> Option<(Duration, CanFrame)> {
    let fate = core.faults.next_reply(now);
    if fate.dropped {
        return None;
    }
    let mut data = response.encode();
    if fate.corrupt_checksum {
        data[0] = 0xC0;
    }
    fate.garble_frame(&mut data);
    let id = if fate.wrong_address {
        response_id(node.wrapping_add(1))
    } else {
        response_id(node)
    };
    let at = now + core.model.config().response_latency + fate.extra_delay;
    Some((at, CanFrame::standard8(id, data)))
}
