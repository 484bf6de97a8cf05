//! The spindle's speed and current, in closed form over time: speed moves in straight lines
//! toward a target at a given rate. It must not loop over time steps (a two-hour run-in is
//! one subtraction per poll) and knows nothing about states, objects or bytes.

use std::time::Duration;

/// Load and friction current at 10 000 rpm.
const LOAD_A_PER_10K_RPM: f64 = 0.8;
/// Extra current per rpm/s of commanded acceleration (the inertia being accelerated).
const A_PER_RPM_PER_S: f64 = 0.0005;

/// One straight ramp segment: from `origin_speed` at `origin`, toward `target` at `rate`.
/// Each change of target or rate starts a new segment, so the speed at any time is exact,
/// with no rounding piling up over thousands of polls.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Motor {
    origin: Duration,
    origin_speed: f64,
    target: f64,
    rate: f64,
}

impl Motor {
    pub(crate) fn at_rest() -> Motor {
        Motor {
            origin: Duration::ZERO,
            origin_speed: 0.0,
            target: 0.0,
            rate: 0.0,
        }
    }

    /// Speed in rpm at `t` (not before the segment start).
    pub(crate) fn speed_at(&self, t: Duration) -> f64 {
        let step = self.rate * t.saturating_sub(self.origin).as_secs_f64();
        let gap = self.target - self.origin_speed;
        if gap.abs() <= step {
            self.target
        } else {
            self.origin_speed + step.copysign(gap)
        }
    }

    /// From `t` on, head for `target` at `rate` rpm/s. Steering to what is already being
    /// steered to keeps the segment, so repeating it cannot introduce rounding.
    pub(crate) fn steer(&mut self, t: Duration, target: f64, rate: f64) {
        if target == self.target && rate == self.rate {
            return;
        }
        self.origin_speed = self.speed_at(t);
        self.origin = t;
        self.target = target;
        self.rate = rate.max(0.0);
    }

    /// Commanded acceleration at `t` in rpm/s: ±rate while ramping, 0 once at the target.
    pub(crate) fn acceleration_at(&self, t: Duration) -> f64 {
        let v = self.speed_at(t);
        if v == self.target {
            0.0
        } else {
            self.rate.copysign(self.target - v)
        }
    }

    /// Motor current in A at `t`, without noise, with the power stage on: load proportional
    /// to speed plus the current that accelerates the inertia. Signed with the direction
    /// of rotation (of acceleration at standstill).
    pub(crate) fn current_at(&self, t: Duration) -> f64 {
        let v = self.speed_at(t);
        let a = self.acceleration_at(t);
        let magnitude = LOAD_A_PER_10K_RPM * v.abs() / 10_000.0 + A_PER_RPM_PER_S * a.abs();
        let direction = if v != 0.0 { v } else { a };
        magnitude.copysign(if direction < 0.0 { -1.0 } else { 1.0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(secs: f64) -> Duration {
        Duration::from_secs_f64(secs)
    }

    #[test]
    fn ramp_reaches_the_target_exactly_on_time_not_before() {
        let mut m = Motor::at_rest();
        m.steer(s(1.0), 6000.0, 2000.0);
        assert_eq!(m.speed_at(s(1.0)), 0.0);
        assert_eq!(m.speed_at(s(2.5)), 3000.0);
        assert!(m.speed_at(s(3.999)) < 6000.0);
        assert_eq!(m.speed_at(s(4.0)), 6000.0);
        assert_eq!(m.speed_at(s(7200.0)), 6000.0);
    }

    #[test]
    fn steering_again_keeps_the_segment_and_retargeting_starts_from_the_current_speed() {
        let mut m = Motor::at_rest();
        m.steer(Duration::ZERO, 6000.0, 2000.0);
        let before = m.clone();
        m.steer(s(1.0), 6000.0, 2000.0);
        assert_eq!(m, before);
        m.steer(s(1.0), -1000.0, 1000.0);
        assert_eq!(m.speed_at(s(1.0)), 2000.0);
        assert_eq!(m.speed_at(s(3.0)), 0.0);
        assert_eq!(m.speed_at(s(4.0)), -1000.0);
        assert_eq!(m.speed_at(s(100.0)), -1000.0);
    }

    #[test]
    fn acceleration_and_current() {
        let mut m = Motor::at_rest();
        m.steer(Duration::ZERO, 10_000.0, 2000.0);
        assert_eq!(m.acceleration_at(s(1.0)), 2000.0);
        // 2000 rpm: 0.16 A load + 1 A acceleration.
        assert!((m.current_at(s(1.0)) - 1.16).abs() < 1e-9);
        assert_eq!(m.acceleration_at(s(5.0)), 0.0);
        assert!((m.current_at(s(5.0)) - 0.8).abs() < 1e-9);
        m.steer(s(5.0), 0.0, 10_000.0);
        assert_eq!(m.acceleration_at(s(5.5)), -10_000.0);
        assert!((m.current_at(s(5.5)) - (0.4 + 5.0)).abs() < 1e-9);
        assert_eq!(m.current_at(s(6.0)), 0.0);
        let mut r = Motor::at_rest();
        r.steer(Duration::ZERO, -3000.0, 1000.0);
        assert!(r.current_at(Duration::ZERO) < 0.0);
        assert!(r.current_at(s(1.0)) < 0.0);
    }

    #[test]
    fn zero_rate_holds_the_speed() {
        let mut m = Motor::at_rest();
        m.steer(Duration::ZERO, 5000.0, 0.0);
        assert_eq!(m.speed_at(s(1000.0)), 0.0);
    }
}
