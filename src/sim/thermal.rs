//! The motor winding's temperature in closed form: first order toward a steady temperature
//! set by the load (ambient + heating × steady current), with a time constant. Each change
//! of load starts a new segment from the temperature reached, so a day costs one
//! exponential per read. It must not loop over time steps and knows nothing of states.

use std::time::Duration;

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Thermal {
    origin: Duration,
    origin_c: f64,
    target_c: f64,
    tau_s: f64,
}

impl Thermal {
    /// At `ambient_c` from the start, heading nowhere.
    pub(crate) fn at(ambient_c: f64, tau: Duration) -> Thermal {
        Thermal {
            origin: Duration::ZERO,
            origin_c: ambient_c,
            target_c: ambient_c,
            tau_s: tau.as_secs_f64().max(1e-3),
        }
    }

    /// °C at `t` (not before the segment's start).
    pub(crate) fn temperature_at(&self, t: Duration) -> f64 {
        let x = t.saturating_sub(self.origin).as_secs_f64() / self.tau_s;
        self.target_c + (self.origin_c - self.target_c) * (-x).exp()
    }

    /// From `t` on, head for `target_c`; the same target keeps the segment.
    pub(crate) fn aim(&mut self, t: Duration, target_c: f64) {
        if target_c == self.target_c {
            return;
        }
        self.origin_c = self.temperature_at(t);
        self.origin = t;
        self.target_c = target_c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn min(m: f64) -> Duration {
        Duration::from_secs_f64(m * 60.0)
    }

    #[test]
    fn it_rises_toward_the_target_with_its_time_constant_and_cools_back() {
        let mut th = Thermal::at(25.0, min(10.0));
        th.aim(Duration::ZERO, 65.0);
        assert_eq!(th.temperature_at(Duration::ZERO), 25.0);
        let one_tau = th.temperature_at(min(10.0));
        assert!(
            (one_tau - (65.0 - 40.0 * (-1f64).exp())).abs() < 1e-9,
            "{one_tau}"
        );
        assert!((th.temperature_at(min(600.0)) - 65.0).abs() < 1e-9);
        th.aim(min(10.0), 25.0);
        assert!((th.temperature_at(min(10.0)) - one_tau).abs() < 1e-12);
        assert!((th.temperature_at(min(20.0)) - (25.0 + (one_tau - 25.0) * (-1f64).exp())).abs() < 1e-9);
    }
}
