//! The spindle's speed and current, in closed form over time: speed moves in straight lines
//! toward a target at a given rate (a ramp, braking, coasting against friction), or follows
//! a setpoint step as a speed controller does ([`Response`]: first order with a time
//! constant, or second order with a given overshoot). It must not loop over time steps (a
//! two-hour run-in is one subtraction per poll) and knows nothing about states, objects or
//! bytes.

use std::time::Duration;

/// Load and friction current at 10 000 rpm.
const LOAD_A_PER_10K_RPM: f64 = 0.8;
/// Extra current per rpm/s of commanded acceleration (the inertia being accelerated).
const A_PER_RPM_PER_S: f64 = 0.0005;

/// How the speed follows a setpoint step under closed-loop control. With `overshoot` 0 it
/// is first order, `v = target − e₀·exp(−t/τ)`: 10 % → 90 % in τ·ln 9. With an overshoot
/// it is second order with natural frequency 1/τ and the damping ζ that gives exactly that
/// first peak: ζ = −ln(os) / √(π² + ln²(os)), the peak at π / (ω·√(1−ζ²)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Response {
    /// τ in seconds.
    pub time_constant_s: f64,
    /// The first peak beyond the target as a fraction of the step (0.1 = 10 %), below 1.
    pub overshoot: f64,
}

impl Response {
    /// (σ = ζω, ω_d = ω√(1−ζ²)) of the second-order form; `None` for first order.
    fn oscillation(&self) -> Option<(f64, f64)> {
        if self.overshoot <= 0.0 {
            return None;
        }
        let l = self.overshoot.min(0.99).ln();
        let zeta = -l / (std::f64::consts::PI.powi(2) + l * l).sqrt();
        let w = 1.0 / self.time_constant_s;
        Some((zeta * w, w * (1.0 - zeta * zeta).sqrt()))
    }

    /// The error `e` and its rate of change `de/dt` after `t` seconds from `e0`, `d0`.
    fn error_after(&self, e0: f64, d0: f64, t: f64) -> (f64, f64) {
        match self.oscillation() {
            None => {
                let k = (-t / self.time_constant_s).exp();
                (e0 * k, -e0 * k / self.time_constant_s)
            }
            Some((sigma, wd)) => {
                let (a, b) = (e0, (d0 + sigma * e0) / wd);
                let (sin, cos) = (wd * t).sin_cos();
                let k = (-sigma * t).exp();
                (
                    k * (a * cos + b * sin),
                    k * ((-sigma * a + wd * b) * cos + (-sigma * b - wd * a) * sin),
                )
            }
        }
    }
}

/// How the current segment moves the speed.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Law {
    /// A straight line at `rate` rpm/s until the target.
    Ramp { rate: f64 },
    /// Closed-loop response from `origin_rate` rpm/s at the origin.
    Follow { response: Response, origin_rate: f64 },
}

/// One segment: from `origin_speed` at `origin`, toward `target` by `law`. Each change of
/// target or law starts a new segment, so the speed at any time is exact, with no rounding
/// piling up over thousands of polls.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Motor {
    origin: Duration,
    origin_speed: f64,
    target: f64,
    law: Law,
}

impl Motor {
    pub(crate) fn at_rest() -> Motor {
        Motor {
            origin: Duration::ZERO,
            origin_speed: 0.0,
            target: 0.0,
            law: Law::Ramp { rate: 0.0 },
        }
    }

    /// Speed in rpm at `t` (not before the segment start).
    pub(crate) fn speed_at(&self, t: Duration) -> f64 {
        let dt = t.saturating_sub(self.origin).as_secs_f64();
        match self.law {
            Law::Ramp { rate } => {
                let step = rate * dt;
                let gap = self.target - self.origin_speed;
                if gap.abs() <= step {
                    self.target
                } else {
                    self.origin_speed + step.copysign(gap)
                }
            }
            Law::Follow {
                response,
                origin_rate,
            } => {
                let (e, _) = response.error_after(self.origin_speed - self.target, origin_rate, dt);
                self.target + e
            }
        }
    }

    /// From `t` on, head for `target` at `rate` rpm/s. Steering to what is already being
    /// steered to keeps the segment, so repeating it cannot introduce rounding.
    pub(crate) fn steer(&mut self, t: Duration, target: f64, rate: f64) {
        let law = Law::Ramp { rate: rate.max(0.0) };
        if target == self.target && law == self.law {
            return;
        }
        self.origin_speed = self.speed_at(t);
        self.origin = t;
        self.target = target;
        self.law = law;
    }

    /// From `t` on, follow a step to `target` with `response`, starting from the speed and
    /// acceleration the motor has at `t` (a new setpoint mid-response continues smoothly).
    pub(crate) fn follow(&mut self, t: Duration, target: f64, response: Response) {
        if target == self.target && matches!(self.law, Law::Follow { response: r, .. } if r == response) {
            return;
        }
        let rate = self.acceleration_at(t);
        self.origin_speed = self.speed_at(t);
        self.origin = t;
        self.target = target;
        self.law = Law::Follow {
            response,
            origin_rate: rate,
        };
    }

    /// Acceleration at `t` in rpm/s: ±rate while ramping, 0 once at the target; the
    /// response's own while following.
    pub(crate) fn acceleration_at(&self, t: Duration) -> f64 {
        match self.law {
            Law::Ramp { rate } => {
                let v = self.speed_at(t);
                if v == self.target {
                    0.0
                } else {
                    rate.copysign(self.target - v)
                }
            }
            Law::Follow {
                response,
                origin_rate,
            } => {
                let dt = t.saturating_sub(self.origin).as_secs_f64();
                response
                    .error_after(self.origin_speed - self.target, origin_rate, dt)
                    .1
            }
        }
    }

    /// The current at the target speed once there: what heats the motor in steady state.
    pub(crate) fn steady_current(&self) -> f64 {
        LOAD_A_PER_10K_RPM * self.target.abs() / 10_000.0
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

    /// A motor at rest told at `at` to follow to `target` rpm with time constant `tau_s` and
    /// `overshoot`; the response, to follow again with.
    fn following(tau_s: f64, overshoot: f64, at: Duration, target: f64) -> (Motor, Response) {
        let response = Response {
            time_constant_s: tau_s,
            overshoot,
        };
        let mut m = Motor::at_rest();
        m.follow(at, target, response);
        (m, response)
    }

    #[test]
    fn a_first_order_response_rises_from_10_to_90_percent_in_tau_ln_9() {
        let (m, _) = following(0.2, 0.0, s(1.0), 6000.0);
        let t10 = 1.0 + 0.2 * (10.0f64 / 9.0).ln();
        let t90 = 1.0 + 0.2 * 10f64.ln();
        // Times are whole nanoseconds: within 1 ns at up to 30 000 rpm/s.
        assert!((m.speed_at(s(t10)) - 600.0).abs() < 1e-3);
        assert!((m.speed_at(s(t90)) - 5400.0).abs() < 1e-3);
        assert!(((t90 - t10) - 0.2 * 9f64.ln()).abs() < 1e-12);
        assert!((m.speed_at(s(100.0)) - 6000.0).abs() < 1e-9);
        assert!(m.acceleration_at(s(1.0)) > 0.0);
    }

    #[test]
    fn a_second_order_response_peaks_at_the_configured_overshoot() {
        let (mut m, response) = following(0.05, 0.1, Duration::ZERO, 1000.0);
        let (sigma, wd) = response.oscillation().unwrap();
        let peak = std::f64::consts::PI / wd;
        assert!(
            (m.speed_at(s(peak)) - 1100.0).abs() < 1e-3,
            "{}",
            m.speed_at(s(peak))
        );
        assert!(
            m.acceleration_at(s(peak)).abs() < 1e-2,
            "{}",
            m.acceleration_at(s(peak))
        );
        assert!(sigma > 0.0);
        // Retargeting mid-flight continues from the speed and acceleration reached.
        let (v, a) = (m.speed_at(s(0.05)), m.acceleration_at(s(0.05)));
        m.follow(s(0.05), 0.0, response);
        assert!((m.speed_at(s(0.05)) - v).abs() < 1e-9);
        assert!((m.acceleration_at(s(0.05)) - a).abs() < 1e-6);
    }

    #[test]
    fn zero_rate_holds_the_speed() {
        let mut m = Motor::at_rest();
        m.steer(Duration::ZERO, 5000.0, 0.0);
        assert_eq!(m.speed_at(s(1000.0)), 0.0);
    }
}
