//! A capture standing in for the drive it was recorded from: each request is answered
//! with what the captured drive answered to the same bytes, at the captured latency.
//!
//! Requests are matched, not merely sequenced. A cursor marks the last exchange answered,
//! and an offset maps the replay's clock onto the capture's (re-aligned when the cursor
//! moves). A request gets:
//! - its latest occurrence after the cursor that the capture had made by now: a status
//!   polled less often than in the capture gets the state the capture was in then;
//! - while its next occurrence lies still ahead, the answer the capture last gave to it,
//!   if that is nearer in capture time and the replay has been asking it lately (polled
//!   more often: the state has not changed yet); never an earlier answer to a command
//!   sent again, or to a stop the capture does not hold;
//! - else its next occurrence: the replay catches up.
//!
//! The cursor does not pass a command the replay has still to send (a request outside its
//! recent polling cycle) unless the capture made it over a second ago (the replay polls
//! less than the capture did). After a refusal the next occurrence counts. A request whose
//! meaning depends on the one before (a CANopen segment request) gets the answer that
//! followed the exchange last answered. A request the capture never made there is
//! refused, naming it and what the capture had (decoded by the family's explainer). The
//! capture is streamed through a bounded window: it must never be read whole.

use super::{CaptureError, CaptureReader, Classifier, Exchange, ExchangeReader};
use crate::bus::{CanFrame, FramePeer, Peer, PeerReply, TransportError};
use crate::link::{Direction, TelegramExplainer};
use std::collections::{HashMap, VecDeque};
use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// How many exchanges the replay reads ahead at most to find a request.
pub const WINDOW: usize = 50_000;
/// How far the replay may lag behind the capture before it passes what it did not send.
const LATE: i128 = 1_000_000_000;
/// How many of the last requests make up the replay's polling cycle.
const RECENT: usize = 8;
/// How many distinct requests' last answers are kept.
const LAST_SEEN: usize = 4096;

/// Called with each refusal when nobody is there to receive it (a served replay).
pub type RefusalSink = Box<dyn FnMut(&TransportError) + Send>;

pub struct CapturedDrive {
    source: ExchangeReader<Box<dyn BufRead + Send>>,
    file: PathBuf,
    /// Exchanges read ahead, after the cursor; `window[0]` is exchange number `base`.
    window: VecDeque<Exchange>,
    base: u64,
    /// Where each request occurs in the window (exchange numbers, ascending).
    index: HashMap<Vec<u8>, VecDeque<u64>>,
    /// The last exchange with replies for each request the cursor has passed.
    last_seen: HashMap<Vec<u8>, Exchange>,
    /// Each passed exchange with replies by the line of the exchange before it: a request
    /// whose meaning depends on the one before (a CANopen segment request) gets the
    /// answer that followed the exchange the replay last answered with.
    followed: HashMap<u64, Exchange>,
    /// The line of the last exchange the cursor passed or answered.
    passed: u64,
    /// The line of the exchange the last answer came from.
    answered: u64,
    /// Capture time minus replay time, in nanoseconds; `None` before the first answer.
    offset: Option<i128>,
    /// The line of the last exchange answered.
    cursor_line: Option<u64>,
    ended: bool,
    /// A request was refused since the cursor last moved: the replay has left the
    /// capture's course, so its clock says nothing about where the capture is.
    diverged: bool,
    /// A read error met while reading ahead, said with the next refusal.
    broken: Option<CaptureError>,
    explainer: Box<dyn TelegramExplainer>,
    /// The last requests answered, newest last.
    recent: VecDeque<Vec<u8>>,
    /// Bytes of a request that arrived in pieces (a served replay).
    pending: Vec<u8>,
    refusals: Option<RefusalSink>,
    high_water: usize,
}

impl CapturedDrive {
    /// Opens the capture at `path`. `classify` tells requests from replies where the
    /// capture does not say (a candump log); `explainer` decodes telegrams for refusals.
    pub fn open(
        path: &Path,
        classify: Classifier,
        explainer: Box<dyn TelegramExplainer>,
    ) -> Result<Self, CaptureError> {
        let file = std::fs::File::open(path).map_err(|e| CaptureError::Unreadable {
            file: path.to_path_buf(),
            detail: e.to_string(),
        })?;
        let input: Box<dyn BufRead + Send> = Box::new(std::io::BufReader::with_capacity(1 << 16, file));
        Self::from_reader(input, path, classify, explainer)
    }

    /// A capture from any reader; `path` names it in messages.
    pub fn from_reader(
        input: Box<dyn BufRead + Send>,
        path: &Path,
        classify: Classifier,
        explainer: Box<dyn TelegramExplainer>,
    ) -> Result<Self, CaptureError> {
        let mut drive = CapturedDrive {
            source: ExchangeReader::new(CaptureReader::new(input, path), classify),
            file: path.to_path_buf(),
            window: VecDeque::new(),
            base: 0,
            index: HashMap::new(),
            last_seen: HashMap::new(),
            followed: HashMap::new(),
            passed: 0,
            answered: 0,
            offset: None,
            cursor_line: None,
            ended: false,
            diverged: false,
            broken: None,
            explainer,
            recent: VecDeque::new(),
            pending: Vec::new(),
            refusals: None,
            high_water: 0,
        };
        drive.read_one();
        if let Some(e) = drive.broken.take() {
            return Err(e);
        }
        if drive.window.is_empty() {
            return Err(CaptureError::NoRequest {
                file: path.to_path_buf(),
            });
        }
        Ok(drive)
    }

    /// Where refusals go when the replay is served and nobody reads its errors.
    pub fn on_refusal(&mut self, sink: RefusalSink) {
        self.refusals = Some(sink);
    }

    /// The most exchanges the replay ever held read ahead (memory stays bounded).
    pub fn high_water(&self) -> usize {
        self.high_water
    }

    /// Whether the capture is of CAN frames (so far read).
    pub fn is_frames(&self) -> bool {
        self.source.is_frames()
    }

    /// The replies to `request` sent at replay time `now`, each at its replay time.
    pub fn answer(&mut self, request: &[u8], now: Duration) -> Result<Vec<PeerReply>, TransportError> {
        let t = now.as_nanos() as i128;
        let tau = self.offset.map(|o| t + o);
        while self.index.get(request).is_none_or(|q| q.is_empty()) && self.read_one() {}
        let next = self.index.get(request).and_then(|q| q.front().copied());
        // The last answer counts while it is nearer in capture time than the next one.
        let last_nearer = |next_at: Option<Duration>, last: Option<&Exchange>| match (tau, next_at, last) {
            (_, _, None) => false,
            (_, None, Some(_)) | (None, _, Some(_)) => true,
            (Some(tau), Some(next_at), Some(last)) => tau - nanos(last.at) <= nanos(next_at) - tau,
        };
        let next_at = next.map(|j| self.at(j));
        let last = self.last_answer(request).is_some();
        // Moving on past a command the replay has still to send would lose it; unless the
        // capture made this request long before now: then the replay polls less than the
        // capture did (no status beside the speed), and must not stay behind for good.
        let long_ago = |d: &Self, j: u64| tau.is_some_and(|tau| nanos(d.at(j)) + LATE <= tau);
        let passing = next.is_some_and(|j| !self.diverged && last && !self.clear_path(request, j));
        let may_move = next.is_some_and(|j| !passing || long_ago(self, j));
        let chosen = match (next, tau) {
            (Some(j), Some(tau)) if may_move && nanos(self.at(j)) <= tau => {
                while self.window.back().is_some_and(|e| nanos(e.at) <= tau) && self.read_one() {}
                let k = self.latest_by(request, j, tau);
                Some(self.advance_to(k).ok_or_else(|| self.refusal(request))?)
            }
            // After a refusal the clocks no longer agree: the next occurrence it is.
            (Some(j), _)
                if may_move && (self.diverged || !last_nearer(next_at, self.last_answer(request))) =>
            {
                Some(self.advance_to(j).ok_or_else(|| self.refusal(request))?)
            }
            _ if last => None,
            (Some(j), _) => Some(self.advance_to(j).ok_or_else(|| self.refusal(request))?),
            (None, _) => return Err(self.refusal(request)),
        };
        let (asked_at, captured, line) = match &chosen {
            Some((_, e)) => (e.at, e.replies.clone(), e.line),
            None => match self.last_answer(request) {
                Some(e) => (e.at, e.replies.clone(), e.line),
                None => return Err(self.refusal(request)),
            },
        };
        self.answered = line;
        if let Some((_, e)) = &chosen {
            self.diverged = false;
            // Re-aligned on the exchange answered; not back when it passed what it did not
            // send, or a replay that polls less than the capture would fall further behind.
            let aligned = nanos(e.at) - t;
            self.offset = Some(match self.offset {
                Some(old) if passing => aligned.max(old),
                _ => aligned,
            });
            self.cursor_line = Some(e.line);
        }
        let replies = captured
            .into_iter()
            .map(|(at, bytes)| PeerReply {
                at: now.saturating_add(at.saturating_sub(asked_at)),
                bytes,
            })
            .collect();
        if let Some((before, e)) = chosen {
            self.remember(before, e);
        }
        if self.recent.len() >= RECENT {
            self.recent.pop_front();
        }
        self.recent.push_back(request.to_vec());
        Ok(replies)
    }

    /// Whether every exchange before number `j` is of `request` or of the replay's polling
    /// cycle.
    fn clear_path(&self, request: &[u8], j: u64) -> bool {
        let before = usize::try_from(j - self.base).unwrap_or(usize::MAX);
        self.window
            .iter()
            .take(before)
            .all(|e| e.request == request || self.recent.iter().any(|r| *r == e.request))
    }

    /// The last occurrence of `request` from exchange `j` on that the capture had made by
    /// capture time `tau`, passing only exchanges of what the replay has been asking lately
    /// (its polling cycle) or made long ago: a replay that runs late must not skip a command
    /// it has still to send (the capture's next setpoint, its stop).
    fn latest_by(&self, request: &[u8], j: u64, tau: i128) -> u64 {
        let mut k = j;
        let start = usize::try_from(j + 1 - self.base).unwrap_or(usize::MAX);
        for (offset, e) in self.window.iter().enumerate().skip(start) {
            if nanos(e.at) > tau {
                break;
            }
            if e.request == request {
                k = self.base + offset as u64;
            } else if nanos(e.at) + LATE > tau && !self.recent.iter().any(|r| *r == e.request) {
                break;
            }
        }
        k
    }

    /// Capture time of exchange number `i` (in the window).
    fn at(&self, i: u64) -> Duration {
        self.window
            .get(usize::try_from(i - self.base).unwrap_or(usize::MAX))
            .map_or(Duration::MAX, |e| e.at)
    }

    /// Moves the cursor onto exchange `k`: the exchanges before it are passed (their
    /// answers kept as the latest known), `k` is taken out of the window and returned
    /// (`None` only if the window no longer holds it).
    fn advance_to(&mut self, k: u64) -> Option<(u64, Exchange)> {
        loop {
            let e = self.window.pop_front()?;
            let number = self.base;
            self.base += 1;
            if let Some(q) = self.index.get_mut(&e.request) {
                q.pop_front();
                if q.is_empty() {
                    self.index.remove(&e.request);
                }
            }
            let before = std::mem::replace(&mut self.passed, e.line);
            if number == k {
                return Some((before, e));
            }
            self.remember(before, e);
        }
    }

    /// The answer the capture last gave to `request`: the one that followed the exchange
    /// the replay last answered with, where that was `request`. Only for what the replay
    /// has been asking lately (a poll repeated): a command sent again later, a safe stop
    /// the capture does not hold, must not be answered from an earlier time.
    fn last_answer(&self, request: &[u8]) -> Option<&Exchange> {
        if !self.recent.iter().any(|r| r == request) {
            return None;
        }
        let after = self.followed.get(&self.answered).filter(|e| e.request == request);
        after.or_else(|| self.last_seen.get(request))
    }

    fn remember(&mut self, before: u64, e: Exchange) {
        if e.replies.is_empty() {
            return;
        }
        if self.last_seen.len() >= LAST_SEEN && !self.last_seen.contains_key(&e.request) {
            self.last_seen.clear();
        }
        if self.followed.len() >= LAST_SEEN {
            self.followed.clear();
        }
        self.followed.insert(before, e.clone());
        self.last_seen.insert(e.request.clone(), e);
    }

    /// Reads one more exchange into the window; `false` when none came (the end, a bad
    /// line, or the window is full).
    fn read_one(&mut self) -> bool {
        if self.ended || self.window.len() >= WINDOW {
            return false;
        }
        match self.source.next_exchange() {
            Ok(Some(e)) => {
                let number = self.base + self.window.len() as u64;
                self.index.entry(e.request.clone()).or_default().push_back(number);
                self.window.push_back(e);
                self.high_water = self.high_water.max(self.window.len());
                true
            }
            Ok(None) => {
                self.ended = true;
                false
            }
            Err(e) => {
                self.ended = true;
                self.broken = Some(e);
                false
            }
        }
    }

    /// The refusal of `request`: what it is and what the capture had at that point.
    fn refusal(&mut self, request: &[u8]) -> TransportError {
        self.diverged = true;
        let name = self.file.display().to_string();
        let asked = self.telegram(request);
        let after = match self.cursor_line {
            Some(line) => format!(" after {name}:{line}"),
            None => String::new(),
        };
        let had = match (self.window.front().cloned(), &self.broken) {
            (_, Some(e)) => format!("the capture cannot be read on: {e}"),
            (Some(e), None) => format!(
                "the capture had there {name}:{} ({:.6} s): {}",
                e.line,
                e.at.as_secs_f64(),
                self.telegram(&e.request)
            ),
            (None, None) => "the capture ends there".to_string(),
        };
        TransportError::NotInCapture {
            detail: format!(
                "replay: the capture {name} never answered {asked}{after}; {had}. Replay it with the recipe and drivescript that made the capture, or record it again"
            ),
        }
    }

    fn telegram(&mut self, bytes: &[u8]) -> String {
        let hex = if self.is_frames() {
            CanFrame::from_bytes(bytes).map_or_else(|| crate::hex::to_hex(bytes), |f| f.to_candump())
        } else {
            crate::hex::to_hex(bytes)
        };
        let meaning = self.explainer.summary(Direction::Sent, bytes);
        format!(
            "`{hex}` ({})",
            meaning.split_whitespace().collect::<Vec<_>>().join(" ")
        )
    }

    fn refused(&mut self, e: &TransportError) {
        if let Some(sink) = &mut self.refusals {
            sink(e);
        }
    }
}

fn nanos(d: Duration) -> i128 {
    d.as_nanos() as i128
}

impl Peer for CapturedDrive {
    /// Served on a byte line, where a request may arrive in pieces: bytes are gathered
    /// while they are the start of a request the capture holds.
    fn receive(&mut self, bytes: &[u8], now: Duration) -> Vec<PeerReply> {
        self.pending.extend_from_slice(bytes);
        let pending = self.pending.clone();
        let known = |k: &Vec<u8>| k.len() > pending.len() && k.starts_with(&pending);
        let whole = self.index.contains_key(&pending) || self.last_seen.contains_key(&pending);
        if !whole && (self.index.keys().any(known) || self.last_seen.keys().any(known)) {
            return Vec::new();
        }
        self.pending.clear();
        match self.answer(&pending, now) {
            Ok(replies) => replies,
            Err(e) => {
                self.refused(&e);
                Vec::new()
            }
        }
    }

    fn exchange(&mut self, bytes: &[u8], now: Duration) -> Result<Vec<PeerReply>, TransportError> {
        self.answer(bytes, now)
    }
}

impl FramePeer for CapturedDrive {
    fn receive(&mut self, frame: &CanFrame, now: Duration) -> Vec<(Duration, CanFrame)> {
        match FramePeer::exchange(self, frame, now) {
            Ok(replies) => replies,
            Err(e) => {
                self.refused(&e);
                Vec::new()
            }
        }
    }

    fn exchange(
        &mut self,
        frame: &CanFrame,
        now: Duration,
    ) -> Result<Vec<(Duration, CanFrame)>, TransportError> {
        let replies = self.answer(&frame.to_bytes(), now)?;
        Ok(replies
            .into_iter()
            .filter_map(|r| Some((r.at, CanFrame::from_bytes(&r.bytes)?)))
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names a telegram by its first byte, as a family's explainer names its command.
    struct Named;
    impl TelegramExplainer for Named {
        fn summary(&mut self, _: Direction, bytes: &[u8]) -> String {
            format!("command {}", bytes.first().copied().unwrap_or(0))
        }
        fn explain(&mut self, _: &[u8]) -> Result<String, crate::link::ExplainError> {
            Err(String::from("not used").into())
        }
        fn json(&mut self, _: &[u8]) -> (serde_json::Value, bool) {
            (serde_json::Value::Null, false)
        }
    }

    fn drive(text: &str) -> CapturedDrive {
        let input: Box<dyn BufRead + Send> = Box::new(std::io::Cursor::new(text.as_bytes().to_vec()));
        CapturedDrive::from_reader(input, Path::new("cap.trace"), Box::new(|_| None), Box::new(Named))
            .unwrap()
    }

    fn ms(n: u64) -> Duration {
        Duration::from_millis(n)
    }

    /// The first reply's bytes to `request` at `at_ms`.
    fn ask(d: &mut CapturedDrive, request: u8, at_ms: u64) -> Vec<u8> {
        let replies = d.answer(&[request], ms(at_ms)).unwrap();
        replies.first().map(|r| r.bytes.clone()).unwrap_or_default()
    }

    /// Asks each `(request, at_ms, first reply byte)` in turn, naming the one that differs.
    fn asks(d: &mut CapturedDrive, expected: &[(u8, u64, u8)]) {
        for &(request, at_ms, byte) in expected {
            assert_eq!(
                ask(d, request, at_ms),
                vec![byte],
                "request {request} at {at_ms} ms"
            );
        }
    }

    /// Write 9, then the speed (request 1) polled every 100 ms ramps 10, 20, 30 and stays.
    const RAMP: &str = "\
    5.000 TX 09\n    5.001 RX 00\n\
    5.100 TX 01\n    5.101 RX 0a\n\
    5.200 TX 01\n    5.201 RX 14\n\
    5.300 TX 01\n    5.301 RX 1e\n\
    5.400 TX 02\n    5.401 RX 63\n";

    #[test]
    fn the_same_requests_get_the_captured_replies_at_the_captured_latency() {
        let mut d = drive(RAMP);
        let r = d.answer(&[9], ms(0)).unwrap();
        assert_eq!(
            r,
            vec![PeerReply {
                at: ms(1),
                bytes: vec![0]
            }]
        );
        asks(&mut d, &[(1, 100, 10), (1, 200, 20), (1, 300, 30), (2, 400, 99)]);
    }

    #[test]
    fn a_poll_more_often_gets_the_state_of_that_time() {
        let mut d = drive(RAMP);
        ask(&mut d, 9, 0);
        // The first poll comes before the capture's: it gets the capture's first answer,
        // and the clocks are aligned on it (the capture's 5.100 s is now 50 ms).
        let got: Vec<u8> = [50, 100, 150, 200, 250, 300, 350]
            .iter()
            .map(|&t| ask(&mut d, 1, t)[0])
            .collect();
        assert_eq!(got, vec![10, 10, 20, 20, 30, 30, 30]);
        assert_eq!(ask(&mut d, 2, 400), vec![99]);
    }

    #[test]
    fn a_poll_less_often_gets_the_state_of_that_time() {
        let mut d = drive(RAMP);
        ask(&mut d, 9, 0);
        asks(&mut d, &[(1, 200, 20), (1, 400, 30), (2, 410, 99)]);
    }

    #[test]
    fn a_request_the_capture_never_answered_is_refused_naming_it_and_what_was_there() {
        let mut d = drive(RAMP);
        ask(&mut d, 9, 0);
        let e = d.answer(&[7], ms(100)).unwrap_err().to_string();
        assert!(
            e.contains("never answered `07` (command 7) after cap.trace:1"),
            "{e}"
        );
        assert!(
            e.contains("the capture had there cap.trace:3 (5.100000 s): `01` (command 1)"),
            "{e}"
        );
        // The refusal does not spoil the rest.
        assert_eq!(ask(&mut d, 1, 100), vec![10]);
    }

    #[test]
    fn a_command_sent_again_much_later_takes_its_next_occurrence_not_its_old_answer() {
        // Command 6 early, state 1 polled, then at the end command 7, command 6 and the state.
        let mut d = drive(
            "    0.0 TX 06
    0.001 RX 60
    0.1 TX 01
    0.101 RX 11
    9.0 TX 07
    9.001 RX 70
    9.1 TX 06
    9.101 RX 61
    9.2 TX 01
    9.201 RX 12
",
        );
        asks(
            &mut d,
            &[
                (6, 0, 0x60),
                (1, 100, 0x11),
                (7, 150, 0x70),
                (6, 160, 0x61),
                (1, 170, 0x12),
            ],
        );
    }

    #[test]
    fn a_replay_running_late_does_not_skip_a_command_it_has_still_to_send() {
        // Polls of 1, then 2 read once (an expect), command 9, and polls of 1 again.
        let mut d = drive("    0.0 TX 01\n    0.001 RX 10\n    0.1 TX 01\n    0.101 RX 11\n    0.2 TX 02\n    0.201 RX 20\n    0.3 TX 09\n    0.301 RX 90\n    0.4 TX 01\n    0.401 RX 12\n");
        assert_eq!(ask(&mut d, 1, 0), vec![0x10]);
        // 450 ms late: the capture polled once more, then read 2 and sent 9 before then.
        asks(
            &mut d,
            &[(1, 550, 0x11), (2, 600, 0x20), (9, 650, 0x90), (1, 700, 0x12)],
        );
    }

    #[test]
    fn one_poll_more_than_the_capture_made_does_not_skip_the_next_command() {
        // Four polls of 1, then 2 read once and command 9, then polls of 1 again.
        let mut d = drive("    0.0 TX 01\n    0.001 RX 10\n    0.25 TX 01\n    0.251 RX 11\n    0.5 TX 01\n    0.501 RX 12\n    0.501 TX 02\n    0.502 RX 20\n    0.502 TX 09\n    0.503 RX 90\n    0.6 TX 01\n    0.601 RX 13\n");
        // The fourth poll comes nearer the capture's next poll than its last one.
        asks(
            &mut d,
            &[
                (1, 0, 0x10),
                (1, 250, 0x11),
                (1, 500, 0x12),
                (1, 580, 0x12),
                (2, 581, 0x20),
                (9, 582, 0x90),
                (1, 700, 0x13),
            ],
        );
    }

    #[test]
    fn a_replay_polling_less_than_the_capture_does_not_stay_behind() {
        // The capture polls 1 and 3 alternately; the replay asks only 1.
        let mut text = String::new();
        for i in 0..40u32 {
            let request = if i % 2 == 0 { 1 } else { 3 };
            text.push_str(&format!("    {}.0 TX 0{request}\n    {}.001 RX {i:02x}\n", i, i));
        }
        let mut d = drive(&text);
        assert_eq!(ask(&mut d, 1, 0), vec![0]);
        let answers: Vec<u8> = (1..30).map(|s| ask(&mut d, 1, s * 1000)[0]).collect();
        // At most a second (LATE) behind the capture's clock, however long it runs.
        assert!(answers.iter().zip(1..).all(|(&v, s)| v + 2 >= s), "{answers:?}");
    }

    proptest::proptest! {
        #[test]
        fn no_panic_on_any_capture_or_request(
            lines in proptest::collection::vec((0u64..u64::MAX, proptest::bool::ANY, proptest::collection::vec(0u8..4, 1..3)), 1..30),
            asked in proptest::collection::vec((proptest::collection::vec(0u8..4, 1..3), 0u64..u64::MAX), 0..30),
        ) {
            let text: String = lines
                .iter()
                .map(|(at, tx, bytes)| format!("{at}.5 {} {}\n", if *tx { "TX" } else { "RX" }, crate::hex::to_hex(bytes)))
                .collect();
            let input: Box<dyn BufRead + Send> = Box::new(std::io::Cursor::new(text.into_bytes()));
            if let Ok(mut d) = CapturedDrive::from_reader(input, Path::new("c"), Box::new(|_| None), Box::new(Named)) {
                for (request, at) in asked {
                    let _ = d.answer(&request, Duration::from_nanos(at));
                    let _ = Peer::receive(&mut d, &request, Duration::from_nanos(at));
                }
            }
        }
    }

    #[test]
    fn a_retry_after_a_lost_reply_gets_the_captured_retrys_reply() {
        let mut d = drive("    0.0 TX 05\n    0.0 -- no reply\n    1.02 TX 05\n    1.021 RX 55\n");
        assert_eq!(d.answer(&[5], ms(0)).unwrap(), vec![]);
        assert_eq!(ask(&mut d, 5, 1000), vec![0x55]);
    }

    #[test]
    fn served_bytes_in_pieces_are_gathered_into_the_request() {
        let mut d = drive("    0.0 TX 01 02 03\n    0.001 RX 04\n");
        assert!(Peer::receive(&mut d, &[1], ms(0)).is_empty());
        assert!(Peer::receive(&mut d, &[2], ms(0)).is_empty());
        assert_eq!(Peer::receive(&mut d, &[3], ms(0))[0].bytes, vec![4]);
        let refused = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let sink = refused.clone();
        d.on_refusal(Box::new(move |e| sink.lock().unwrap().push(e.to_string())));
        assert!(Peer::receive(&mut d, &[9], ms(5)).is_empty());
        assert_eq!(refused.lock().unwrap().len(), 1);
    }

    #[test]
    fn the_window_is_bounded_and_a_capture_without_requests_is_refused() {
        let mut text = String::new();
        for i in 0..(WINDOW + 10) {
            text.push_str(&format!("    {i}.0 TX 01\n    {i}.001 RX 02\n"));
        }
        let mut d = drive(&text);
        assert!(d.answer(&[3], ms(0)).is_err());
        assert!(d.high_water() <= WINDOW);
        let input: Box<dyn BufRead + Send> = Box::new(std::io::Cursor::new(b"# only\n".to_vec()));
        let e = CapturedDrive::from_reader(input, Path::new("c"), Box::new(|_| None), Box::new(Named));
        assert!(e.is_err());
    }
}
