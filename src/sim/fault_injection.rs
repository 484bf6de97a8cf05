//! Faults a test can inject into the simulated drive between telegrams: lost, corrupt, late,
//! misaddressed or garbled replies (from a chosen time on, so that they can fall inside the
//! safe stop), a drive fault at a chosen time, an emergency message without a trip, a fault
//! that will not reset, a drive that acknowledges stop commands but does not obey them, a
//! line that goes down for a while, a drive that falls silent for a while (a CANopen node's
//! heartbeat too), and a panic inside the request handling (to prove the engine's panic path).
//! It only decides what happens to replies and when things fire; it must not build bytes or
//! touch the drive model itself.

use crate::drive::device_control::DeviceCommand;
use std::time::Duration;

/// Pending injections. Each reply-shaping injection affects the next `n` replies the drive
/// produces and counts down by one per reply, independently of the others (a reply can be
/// both late and corrupt; a dropped reply still uses up the other injections it overlaps).
/// Calling a setter again replaces its count. The request behind a dropped or damaged reply
/// is still executed, as on a real drive whose answer is lost on the wire.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FaultInjection {
    drop: u32,
    corrupt: u32,
    delay: u32,
    delay_by: Duration,
    wrong_address: u32,
    garbage: u32,
    /// The reply injections above start with the first reply at or after this time.
    replies_from: Duration,
    /// The drive sends nothing from the first time until the second (no reply, no
    /// heartbeat), while the line itself stays up.
    silent: Option<(Duration, Duration)>,
    /// Sorted by time; equal times keep the order they were scheduled in.
    trips: Vec<(Duration, u16)>,
    /// Emergency messages sent without a trip, sorted by time.
    emergencies: Vec<(Duration, u16)>,
    reset_blocked: bool,
    /// Commands acknowledged on the wire but not carried out.
    ignored: Vec<DeviceCommand>,
    /// The line is down from the first time until the second.
    line_down: Option<(Duration, Duration)>,
    /// The simulator panics while handling the first request at or after this time.
    panic_at: Option<Duration>,
}

/// What happens to one reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct ReplyFate {
    pub(crate) dropped: bool,
    pub(crate) corrupt_checksum: bool,
    pub(crate) extra_delay: Duration,
    pub(crate) wrong_address: bool,
    /// Line noise arrives before the reply (a byte line) or in its place (a CAN frame).
    pub(crate) garbage: bool,
}

/// The noise a garbled reply carries: no protocol's start byte pattern in a row, bytes a
/// line picks up when a contactor switches.
const NOISE: [u8; 7] = [0x00, 0xFF, 0x7E, 0x81, 0x13, 0xFE, 0x3C];

impl ReplyFate {
    /// A byte line's reply as it reaches the master: `bytes` sent at `at`, later by the
    /// injected delay, with the injected noise in front.
    pub(crate) fn reply(&self, bytes: Vec<u8>, at: Duration) -> crate::bus::PeerReply {
        crate::bus::PeerReply {
            at: at + self.extra_delay,
            bytes: self.noisy(bytes),
        }
    }

    /// [`ReplyFate::reply`] of a reply whose last byte is its check byte (every byte family
    /// that has one puts it there): `spoil`ed when the checksum is to be corrupted.
    pub(crate) fn checked_reply(
        &self,
        mut bytes: Vec<u8>,
        spoil: impl FnOnce(u8) -> u8,
        at: Duration,
    ) -> crate::bus::PeerReply {
        if let (true, Some(last)) = (self.corrupt_checksum, bytes.last_mut()) {
            *last = spoil(*last);
        }
        self.reply(bytes, at)
    }

    /// `bytes` with line noise in front when the reply is garbled.
    pub(crate) fn noisy(&self, bytes: Vec<u8>) -> Vec<u8> {
        match self.garbage {
            true => NOISE.iter().copied().chain(bytes).collect(),
            false => bytes,
        }
    }

    /// A CAN frame's 8 data bytes overwritten with noise when the reply is garbled.
    pub(crate) fn garble_frame(&self, data: &mut [u8; 8]) {
        if self.garbage {
            for (d, n) in data.iter_mut().zip(NOISE.iter().cycle().skip(1)) {
                *d ^= n;
            }
        }
    }
}

fn count_down(n: &mut u32) -> bool {
    let active = *n > 0;
    *n = n.saturating_sub(1);
    active
}

impl FaultInjection {
    /// The next `n` replies are not sent.
    pub fn drop_replies(&mut self, n: u32) -> &mut Self {
        self.drop = n;
        self
    }

    /// The next `n` replies go out with their check byte inverted.
    pub fn corrupt_checksum(&mut self, n: u32) -> &mut Self {
        self.corrupt = n;
        self
    }

    /// The next `n` replies are sent `by` later than the normal response latency.
    pub fn delay_replies(&mut self, n: u32, by: Duration) -> &mut Self {
        self.delay = n;
        self.delay_by = by;
        self
    }

    /// The next `n` replies carry source address + 1 (another drive answering).
    pub fn wrong_address(&mut self, n: u32) -> &mut Self {
        self.wrong_address = n;
        self
    }

    /// The next `n` replies are garbled: line noise before them on a byte line, their data
    /// bytes scrambled on CAN.
    pub fn garbage(&mut self, n: u32) -> &mut Self {
        self.garbage = n;
        self
    }

    /// The reply injections (drop, corrupt, delay, wrong address, garbage) wait for the
    /// first reply at or after `at`, then count down as usual: a fault a test places
    /// inside the safe stop, whose telegrams it cannot count beforehand.
    pub fn replies_from(&mut self, at: Duration) -> &mut Self {
        self.replies_from = at;
        self
    }

    /// The drive falls silent at `from` until `until`: it takes requests (and carries them
    /// out) but answers none, and a CANopen node sends no heartbeat, while the line (the
    /// adapter, the port) stays up — a drive whose communication died.
    pub fn silent(&mut self, from: Duration, until: Duration) -> &mut Self {
        self.silent = Some((from, until));
        self
    }

    /// Whether the drive is silent at `now`.
    pub fn is_silent(&self, now: Duration) -> bool {
        matches!(self.silent, Some((from, until)) if from <= now && now < until)
    }

    /// At clock time `at` the drive trips: fault reaction active (braking at the quick-stop
    /// ramp), then fault at standstill; the drive error object shows `drive_error` until a
    /// fault reset. A time already past fires with the next telegram.
    pub fn trip_at(&mut self, at: Duration, drive_error: u16) -> &mut Self {
        let i = self.trips.partition_point(|(t, _)| *t <= at);
        self.trips.insert(i, (at, drive_error));
        self
    }

    /// At clock time `at` a drive that sends emergency messages on its own (a CANopen
    /// node's EMCY) sends one with `error_code` and goes on as it was: nothing trips (a
    /// drive that reports a fault it does not react to). Families without such messages
    /// ignore it.
    pub fn emergency_at(&mut self, at: Duration, error_code: u16) -> &mut Self {
        let i = self.emergencies.partition_point(|(t, _)| *t <= at);
        self.emergencies.insert(i, (at, error_code));
        self
    }

    /// Removes and returns the earliest emergency message due at or before `until`.
    pub fn take_emergency_due(&mut self, until: Duration) -> Option<(Duration, u16)> {
        match self.emergencies.first() {
            Some(&(at, _)) if at <= until => Some(self.emergencies.remove(0)),
            _ => None,
        }
    }

    /// While `blocked`, the fault cause persists: a fault reset leaves the drive in fault.
    pub fn fault_reset_blocked(&mut self, blocked: bool) -> &mut Self {
        self.reset_blocked = blocked;
        self
    }

    pub fn is_fault_reset_blocked(&self) -> bool {
        self.reset_blocked
    }

    /// While enabled (operation enabled, quick stop active), the drive answers these
    /// commands as written but does not carry them out (a drive whose control channel is
    /// not the serial line, or a broken one). Replaces the list.
    pub fn ignore_commands(&mut self, commands: &[DeviceCommand]) -> &mut Self {
        self.ignored = commands.to_vec();
        self
    }

    pub fn ignores(&self, command: DeviceCommand) -> bool {
        self.ignored.contains(&command)
    }

    /// The line goes down at `from` and comes back at `until`: no telegram passes, as
    /// when a USB adapter is pulled out and put back. The drive itself keeps running.
    pub fn line_down(&mut self, from: Duration, until: Duration) -> &mut Self {
        self.line_down = Some((from, until));
        self
    }

    /// Whether the line is up at `now`.
    pub fn line_up(&self, now: Duration) -> bool {
        !matches!(self.line_down, Some((from, until)) if from <= now && now < until)
    }

    /// Until when the line, up at `now`, stays up: the start of the lost link ahead, or
    /// for ever. `now` when it is down.
    pub fn line_up_until(&self, now: Duration) -> Duration {
        match self.line_down {
            Some((from, until)) if now < until => {
                if now < from {
                    from
                } else {
                    now
                }
            }
            _ => Duration::MAX,
        }
    }

    /// The simulator panics while handling the first request at or after `at`, once,
    /// before the request changes anything.
    pub fn panic_at(&mut self, at: Duration) -> &mut Self {
        self.panic_at = Some(at);
        self
    }

    /// True (once) when the panic is due at `now`.
    pub(crate) fn take_panic_due(&mut self, now: Duration) -> bool {
        let due = self.panic_at.is_some_and(|at| at <= now);
        if due {
            self.panic_at = None;
        }
        due
    }

    /// True when no reply injection is pending and no trip is scheduled.
    pub fn is_idle(&self) -> bool {
        self.drop == 0
            && self.corrupt == 0
            && self.delay == 0
            && self.wrong_address == 0
            && self.garbage == 0
            && self.trips.is_empty()
            && self.emergencies.is_empty()
            && self.panic_at.is_none()
    }

    /// The fate of the reply about to be sent at `now`; counts every active injection down
    /// (from the time [`replies_from`](Self::replies_from) gives on).
    pub(crate) fn next_reply(&mut self, now: Duration) -> ReplyFate {
        let silent = self.is_silent(now);
        if now < self.replies_from {
            return ReplyFate {
                dropped: silent,
                ..ReplyFate::default()
            };
        }
        let delayed = count_down(&mut self.delay);
        ReplyFate {
            dropped: count_down(&mut self.drop) | silent,
            corrupt_checksum: count_down(&mut self.corrupt),
            extra_delay: if delayed { self.delay_by } else { Duration::ZERO },
            wrong_address: count_down(&mut self.wrong_address),
            garbage: count_down(&mut self.garbage),
        }
    }

    /// Removes and returns the earliest trip due at or before `until`.
    pub(crate) fn take_trip_due(&mut self, until: Duration) -> Option<(Duration, u16)> {
        match self.trips.first() {
            Some(&(at, _)) if at <= until => Some(self.trips.remove(0)),
            _ => None,
        }
    }

    /// The trips due at or before `until`, in firing order, without consuming them.
    pub(crate) fn trips_due(&self, until: Duration) -> impl Iterator<Item = (Duration, u16)> + '_ {
        self.trips.iter().copied().take_while(move |(at, _)| *at <= until)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_is_up_until_the_lost_link_starts_and_after_it_ends() {
        let ms = Duration::from_millis;
        let mut f = FaultInjection::default();
        assert_eq!(f.line_up_until(ms(7)), Duration::MAX);
        f.line_down(ms(10), ms(20));
        assert_eq!(f.line_up_until(ms(7)), ms(10));
        assert!(!f.line_up(ms(10)));
        assert_eq!(f.line_up_until(ms(15)), ms(15));
        assert!(f.line_up(ms(20)));
        assert_eq!(f.line_up_until(ms(20)), Duration::MAX);
    }

    #[test]
    fn injections_count_down_independently() {
        let mut f = FaultInjection::default();
        assert!(f.is_idle());
        f.drop_replies(1)
            .corrupt_checksum(2)
            .delay_replies(3, Duration::from_millis(5))
            .wrong_address(1);
        assert!(!f.is_idle());
        let first = f.next_reply(Duration::ZERO);
        assert_eq!(
            first,
            ReplyFate {
                dropped: true,
                corrupt_checksum: true,
                extra_delay: Duration::from_millis(5),
                wrong_address: true,
                garbage: false,
            }
        );
        let second = f.next_reply(Duration::ZERO);
        assert!(!second.dropped && second.corrupt_checksum && !second.wrong_address);
        let third = f.next_reply(Duration::ZERO);
        assert_eq!(third.extra_delay, Duration::from_millis(5));
        assert!(!third.corrupt_checksum);
        assert_eq!(f.next_reply(Duration::ZERO), ReplyFate::default());
        assert!(f.is_idle());
    }

    #[test]
    fn reply_injections_wait_for_their_time_and_silence_drops_replies() {
        let mut f = FaultInjection::default();
        let s = Duration::from_secs;
        f.garbage(1)
            .drop_replies(1)
            .replies_from(s(10))
            .silent(s(20), s(22));
        assert_eq!(f.next_reply(s(9)), ReplyFate::default());
        let at_ten = f.next_reply(s(10));
        assert!(at_ten.garbage && at_ten.dropped);
        assert_eq!(f.next_reply(s(11)), ReplyFate::default());
        assert!(f.next_reply(s(20)).dropped && f.is_silent(s(21)));
        assert!(!f.next_reply(s(22)).dropped && !f.is_silent(s(22)));
        let noisy = ReplyFate {
            garbage: true,
            ..ReplyFate::default()
        };
        assert_eq!(noisy.noisy(vec![1, 2]).len(), NOISE.len() + 2);
        assert_eq!(ReplyFate::default().noisy(vec![1, 2]), vec![1, 2]);
        let mut data = [0u8; 8];
        noisy.garble_frame(&mut data);
        assert_ne!(data, [0u8; 8]);
    }

    #[test]
    fn trips_fire_in_time_order() {
        let mut f = FaultInjection::default();
        let s = Duration::from_secs;
        f.trip_at(s(5), 2).trip_at(s(1), 1).trip_at(s(5), 3);
        assert_eq!(
            f.trips_due(s(5)).collect::<Vec<_>>(),
            vec![(s(1), 1), (s(5), 2), (s(5), 3)]
        );
        assert_eq!(f.take_trip_due(s(0)), None);
        assert_eq!(f.take_trip_due(s(2)), Some((s(1), 1)));
        assert_eq!(f.take_trip_due(s(2)), None);
        assert_eq!(f.take_trip_due(s(9)), Some((s(5), 2)));
        assert_eq!(f.take_trip_due(s(9)), Some((s(5), 3)));
        assert!(f.is_idle());
        f.fault_reset_blocked(true);
        assert!(f.is_fault_reset_blocked());
    }
}
