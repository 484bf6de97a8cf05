//! The SDO link against scripted and simulated nodes: transfers, retries, the bound on a
//! transfer's length, aborts, and what the link hears on the bus besides.

use super::*;
use crate::bus::{FramePeer, MemoryFrameBus};
use crate::clock::{Clock, VirtualClock};
use crate::family::lenze_9400::sim::Lenze9400Simulator;
use crate::hex::parse_hex;
use crate::sim::{SimConfig, SimulatedDrive};
use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::Mutex;

const FAST: Duration = Duration::from_micros(200);

/// Answers each request with the next scripted frames (id, hex); an empty entry is silence.
struct Scripted {
    replies: VecDeque<Vec<(u32, &'static str)>>,
    received: Vec<String>,
}

impl FramePeer for Scripted {
    fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
        self.received.push(frame.to_candump());
        self.replies
            .pop_front()
            .unwrap_or_default()
            .into_iter()
            .map(|(id, hex)| {
                let data: [u8; 8] = parse_hex(hex).unwrap().try_into().unwrap();
                (now + FAST, CanFrame::standard8(id, data))
            })
            .collect()
    }
}

fn scripted(node: u8, replies: Vec<Vec<(u32, &'static str)>>) -> (SdoLink, Arc<Mutex<Scripted>>) {
    let clock = Arc::new(VirtualClock::new());
    let peer = Arc::new(Mutex::new(Scripted {
        replies: replies.into(),
        received: vec![],
    }));
    let bus = MemoryFrameBus::new("scripted", peer.clone(), clock.clone());
    let link = SdoLink::new(
        SharedFrameBus::new(Box::new(bus)),
        clock,
        node,
        SdoLinkConfig {
            notation: crate::family::lenze_9400::LENZE_NOTATION,
            ..SdoLinkConfig::default()
        },
    );
    (link, peer)
}

/// Node 12's replies to the upload of 0x5F9C:0, "05.00.12.07": the initiate response
/// (11 bytes to come), then the two segments.
fn firmware_upload() -> Vec<Vec<(u32, &'static str)>> {
    vec![
        vec![(0x58C, "41 9c 5f 00 0b 00 00 00")],
        vec![(0x58C, "00 30 35 2e 30 30 2e 31")],
        vec![(0x58C, "17 32 2e 30 37 00 00 00")],
    ]
}

/// The upload of 0x5F9C:0 whose first attempt gets `first_attempt`: the link's third frame
/// must be the abort `abort` (`why`), and the retry must read "05.00.12.07". The link, for
/// its counts.
#[track_caller]
fn upload_retried_after(first_attempt: Vec<Vec<(u32, &'static str)>>, abort: &str, why: &str) -> SdoLink {
    let (mut link, peer) = scripted(12, [first_attempt, firmware_upload()].concat());
    assert_eq!(link.upload(0x5F9C, 0).unwrap().data, b"05.00.12.07");
    let sent = peer.lock().unwrap().received.clone();
    assert_eq!(sent[2], abort, "abort with {why}");
    link
}

fn simulated(node: u8) -> (SdoLink, Arc<Mutex<Lenze9400Simulator>>, Arc<VirtualClock>) {
    let clock = Arc::new(VirtualClock::new());
    let sim = Arc::new(Mutex::new(Lenze9400Simulator::new(node, SimConfig::default())));
    let bus = MemoryFrameBus::new("memory", sim.clone(), clock.clone());
    let link = SdoLink::new(
        SharedFrameBus::new(Box::new(bus)),
        clock.clone(),
        node,
        SdoLinkConfig {
            notation: crate::family::lenze_9400::LENZE_NOTATION,
            ..SdoLinkConfig::default()
        },
    );
    (link, sim, clock)
}

#[test]
fn segmented_upload_of_eleven_characters_in_two_segments() {
    let (mut link, peer) = scripted(12, firmware_upload());
    let value = link.upload(0x5F9C, 0).unwrap();
    assert_eq!(value.data, b"05.00.12.07");
    assert_eq!(
        peer.lock().unwrap().received,
        [
            "60C#409C5F0000000000",
            "60C#6000000000000000",
            "60C#7000000000000000"
        ]
    );
}

#[test]
fn the_simulated_node_answers_the_worked_examples() {
    let (mut link, _, _) = simulated(12);
    assert_eq!(link.upload(0x5F9C, 0).unwrap().data, b"05.00.12.07");
    let (mut link, _, _) = simulated(5);
    assert_eq!(link.upload(0x5FC2, 0).unwrap().data, [0x2b, 0, 0, 0]);
    let (mut link, sim, _) = simulated(2);
    link.download(0x5FA7, 0, &102i32.to_le_bytes()).unwrap();
    assert_eq!(sim.lock().unwrap().codes().rated_current, 102);
}

#[test]
fn an_abort_names_the_code_and_the_abort_text() {
    let (mut link, _, _) = simulated(12);
    let e = link.upload(0x5FFF - 999, 0).unwrap_err();
    assert!(
        matches!(
            e,
            AccessError::Refused {
                code: 0x0602_0000,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "drive node 12 on memory refused to read object C00999 (index 0x5C18, subindex 0): \
         SDO abort 0x06020000 object does not exist in the object dictionary"
    );
    let (mut link, _) = scripted(12, vec![vec![(0x58C, "80 9c 5f 00 41 00 04 06")]]);
    let e = link.upload(0x5F9C, 0).unwrap_err().to_string();
    assert!(
        e.contains("C00099") && e.contains("0x06040041 object cannot be mapped to the PDO"),
        "{e}"
    );
}

#[test]
fn only_frames_from_0x580_plus_node_are_responses() {
    // Another node's response and our own request echoed come first.
    let (mut link, _) = scripted(
        5,
        vec![vec![
            (0x586, "43 c2 5f 00 99 00 00 00"),
            (0x605, "40 c2 5f 00 00 00 00 00"),
            (0x585, "43 c2 5f 00 2b 00 00 00"),
        ]],
    );
    assert_eq!(link.upload(0x5FC2, 0).unwrap().data, [0x2b, 0, 0, 0]);
    assert_eq!(link.stats().retries, 0);
}

#[test]
fn a_wrong_toggle_bit_is_aborted_and_the_transfer_retried() {
    let first_attempt = vec![
        vec![(0x58C, "41 9c 5f 00 0b 00 00 00")],
        vec![(0x58C, "10 30 35 2e 30 30 2e 31")],
        vec![], // the abort is not answered
    ];
    let link = upload_retried_after(first_attempt, "60C#809C5F0000000305", "0x05030000 toggle bit");
    assert_eq!(link.stats().retries, 1);
}

/// A value longer than a transfer takes is the node's answer, not noise: the transfer
/// is aborted once and refused, never tried again (the node would send the same).
#[test]
fn a_value_longer_than_a_transfer_takes_is_aborted_and_not_retried() {
    let (mut link, peer) = scripted(12, vec![vec![(0x58C, "41 9c 5f 00 00 10 00 00")], vec![]]);
    let e = link.upload(0x5F9C, 0).unwrap_err();
    assert!(matches!(e, AccessError::UnexpectedReply { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("the node announces 4096 bytes; drivescript takes at most 256"),
        "{text}"
    );
    assert!(!text.contains("noise") && !text.contains("attempt"), "{text}");
    assert_eq!(link.stats().retries, 0);
    let sent = peer.lock().unwrap().received.clone();
    assert_eq!(sent.len(), 2, "the request and one abort: {sent:?}");
    assert!(sent[1].starts_with("60C#809C5F00"), "{sent:?}");
    // Segments beyond the bound without a size announced say so.
    let mut segments = vec![vec![(0x58C, "40 9c 5f 00 00 00 00 00")]];
    for k in 0..40u8 {
        let toggle = if k % 2 == 0 { "00" } else { "10" };
        segments.push(vec![(
            0x58C,
            format!("{toggle} 41 41 41 41 41 41 41").leak() as &str,
        )]);
    }
    let (mut link, _) = scripted(12, segments);
    let text = link.upload(0x5F9C, 0).unwrap_err().to_string();
    assert!(
        text.contains("the node sends more than the 256 bytes drivescript takes (it announced no size)"),
        "{text}"
    );
    assert_eq!(link.stats().retries, 0);
}

#[test]
fn every_attempt_broken_reports_the_last_response_and_the_problem() {
    let bad = vec![(0x58C, "c1 9c 5f 00 0b 00 00 00")];
    let (mut link, _) = scripted(12, vec![bad.clone(), vec![], bad.clone(), vec![], bad, vec![]]);
    let e = link.upload(0x5F9C, 0).unwrap_err();
    assert!(matches!(e, AccessError::BadReply { attempts: 3, .. }), "{e}");
    let text = e.to_string();
    assert!(text.contains("58C#C19C5F000B000000"), "{text}");
    assert!(text.contains("block transfers"), "{text}");
}

#[test]
fn a_node_silent_mid_transfer_is_aborted_with_the_timeout_code_then_retried() {
    // The initiate response arrives, the first segment's is lost.
    let first_attempt = vec![vec![(0x58C, "41 9c 5f 00 0b 00 00 00")], vec![], vec![]];
    let l2 = upload_retried_after(first_attempt, "60C#809C5F0000000405", "0x05040000 SDO timeout");
    assert_eq!(l2.stats().timeouts, 1);
    // Every attempt lost: a clear no-reply error after three attempts of 1 s.
    let (mut link, sim, clock) = simulated(12);
    sim.lock().unwrap().faults().drop_replies(10);
    let e = link.upload(0x5FC2, 0).unwrap_err();
    assert!(e.is_no_reply());
    let text = e.to_string();
    assert!(text.contains("no reply from drive node 12 on memory"), "{text}");
    assert!(text.contains("`60C#40C25F0000000000` (read C00061"), "{text}");
    assert!(clock.now() >= Duration::from_secs(3));
}

/// A bus whose adapter is unplugged after `sends` frames.
struct Unplugged {
    inner: MemoryFrameBus,
    sends: usize,
}

impl FrameBus for Unplugged {
    fn name(&self) -> &str {
        "slcan /dev/ttyACM0"
    }
    fn send(&mut self, frame: &CanFrame) -> Result<(), TransportError> {
        if self.sends == 0 {
            return Err(TransportError::Io {
                port: "slcan /dev/ttyACM0".into(),
                detail: "the device was unplugged".into(),
            });
        }
        self.sends -= 1;
        self.inner.send(frame)
    }
    fn receive(&mut self, timeout: Duration) -> Result<CanFrame, TransportError> {
        self.inner.receive(timeout)
    }
    fn reopen(&mut self) -> Result<(), TransportError> {
        Err(TransportError::PortNotFound {
            port: "/dev/ttyACM0".into(),
        })
    }
}

#[test]
fn a_lost_adapter_mid_transfer_ends_it_at_once_with_the_adapters_error() {
    let clock = Arc::new(VirtualClock::new());
    let sim = Arc::new(Mutex::new(Lenze9400Simulator::new(12, SimConfig::default())));
    let bus = Unplugged {
        inner: MemoryFrameBus::new("memory", sim, clock.clone()),
        sends: 2,
    };
    let mut link = SdoLink::new(
        SharedFrameBus::new(Box::new(bus)),
        clock.clone(),
        12,
        SdoLinkConfig {
            notation: crate::family::lenze_9400::LENZE_NOTATION,
            ..SdoLinkConfig::default()
        },
    );
    let e = link.upload(0x5F9C, 0).unwrap_err();
    assert!(e.is_transport(), "{e}");
    assert_eq!(
        e.to_string(),
        "I/O error on slcan /dev/ttyACM0: the device was unplugged"
    );
    // No retry and no reply timeout was waited for.
    assert!(clock.now() < Duration::from_millis(10), "{:?}", clock.now());
    assert!(link.reopen().unwrap_err().to_string().contains("does not exist"));
}

/// Answers every upload 1.5 s after it came (a node slower than the 1 s timeout), with a
/// count of the requests it has had: each request's own answer is told by its number.
struct Slow {
    requests: u32,
}

impl FramePeer for Slow {
    fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
        self.requests += 1;
        let mut data = [
            0x43,
            frame.data()[1],
            frame.data()[2],
            frame.data()[3],
            0,
            0,
            0,
            0,
        ];
        data[4..].copy_from_slice(&self.requests.to_le_bytes());
        vec![(
            now + Duration::from_millis(1500),
            CanFrame::standard8(0x581, data),
        )]
    }
}

#[test]
fn a_node_slower_than_the_timeout_never_gives_a_read_the_answer_to_an_earlier_one() {
    let clock = Arc::new(VirtualClock::new());
    let peer = Arc::new(Mutex::new(Slow { requests: 0 }));
    let bus = MemoryFrameBus::new("slow", peer.clone(), clock.clone());
    let mut link = SdoLink::new(
        SharedFrameBus::new(Box::new(bus)),
        clock,
        1,
        SdoLinkConfig::default(),
    );
    let value = |u: Uploaded| u32::from_le_bytes(u.data[..4].try_into().unwrap());
    // The first read's first request (1) is answered during its retry (request 2).
    assert_eq!(value(link.upload(0x6041, 0).unwrap()), 1);
    // The retry's answer (2) comes during the second read: it answers the first read, so
    // the second read waits for it, drops it, and gets an answer to a request of its own.
    let second = value(link.upload(0x6041, 0).unwrap());
    assert!(
        second >= 3,
        "the second read got the answer to request {second}, the first read's"
    );
}

#[test]
fn the_wait_for_owed_responses_survives_time_passing_between_its_readings() {
    // Readings that many steps apart: one lands just short of the end of the wait.
    for tick in 1..=20 {
        let clock = Arc::new(crate::clock::TickingClock::new(Duration::from_micros(tick * 300)));
        // A node that never answers: each read owes the responses of its attempts to the
        // next one, which waits for them until their time is over.
        let peer = Arc::new(Mutex::new(Scripted {
            replies: VecDeque::new(),
            received: vec![],
        }));
        let bus = MemoryFrameBus::new("silent", peer, clock.clone());
        let mut link = SdoLink::new(
            SharedFrameBus::new(Box::new(bus)),
            clock,
            1,
            SdoLinkConfig::default(),
        );
        link.set_stop_requests(Arc::new(crate::stop_request::StopRequests::new()));
        for _ in 0..3 {
            assert!(link.upload(0x6041, 0).is_err());
        }
    }
}
