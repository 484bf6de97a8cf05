//! The response of one sampled value to a setpoint step, measured as the samples arrive in
//! constant memory: rise time (10 % → 90 % of the step, the first crossing of each,
//! interpolated between samples), overshoot (the furthest excursion beyond the target, in %
//! of the step), settling time (from the window's start until the value stays within the
//! band around the target, interpolated) and steady-state error (the mean of the last
//! tenth of the window minus the target). Pure arithmetic; it must not read a drive.

/// The step a window is measured against, in the object's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSpec {
    /// Where the step starts; `None`: the window's first sample.
    pub from: Option<f64>,
    pub to: f64,
    /// Half-width of the settling band, in % of the step's size.
    pub band_percent: f64,
}

/// The default settling band: ± 2 % of the step, the usual definition.
pub const DEFAULT_BAND_PERCENT: f64 = 2.0;

/// Where in the window each measure was taken, for the plot's markers (seconds since the
/// run's start).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ResponseMarks {
    pub rise_start: Option<f64>,
    pub rise_end: Option<f64>,
    pub peak: Option<(f64, f64)>,
    pub settled: Option<f64>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct StepResponse {
    spec: StepSpec,
    start: f64,
    /// From when on samples count for the steady state (the last tenth of the window).
    steady_from: f64,
    from: Option<f64>,
    previous: Option<(f64, f64)>,
    marks: ResponseMarks,
    /// The furthest excursion beyond the target in the step's direction (≥ 0 when beyond).
    beyond: f64,
    /// The time the value last entered the band (`None` while outside).
    entered_band: Option<f64>,
    steady_sum: f64,
    steady_count: u64,
}

impl StepResponse {
    /// A response measured over a window that starts at `start` and lasts `duration`
    /// seconds (the step is taken to happen at `start`).
    pub fn new(spec: StepSpec, start: f64, duration: f64) -> StepResponse {
        StepResponse {
            spec,
            start,
            steady_from: start + 0.9 * duration,
            from: spec.from,
            previous: None,
            marks: ResponseMarks::default(),
            beyond: f64::NEG_INFINITY,
            entered_band: None,
            steady_sum: 0.0,
            steady_count: 0,
        }
    }

    pub fn spec(&self) -> StepSpec {
        self.spec
    }

    fn size(&self) -> f64 {
        self.spec.to - self.from.unwrap_or(self.spec.to)
    }

    /// The value as a fraction of the way from `from` to `to` (1 at the target).
    fn progress(&self, v: f64) -> f64 {
        let size = self.size();
        if size == 0.0 {
            1.0
        } else {
            (v - self.from.unwrap_or(v)) / size
        }
    }

    /// Takes the sample `v` at `t` seconds.
    pub fn push(&mut self, t: f64, v: f64) {
        if self.from.is_none() {
            self.from = Some(v);
        }
        let p = self.progress(v);
        if let Some((t0, v0)) = self.previous {
            let p0 = self.progress(v0);
            let cross = |level: f64| -> Option<f64> {
                (p0 < level && p >= level).then(|| t0 + (t - t0) * (level - p0) / (p - p0))
            };
            if self.marks.rise_start.is_none() {
                self.marks.rise_start = cross(0.1);
            }
            if self.marks.rise_end.is_none() && self.marks.rise_start.is_some() {
                self.marks.rise_end = cross(0.9);
            }
        } else if p >= 0.1 {
            // Already past 10 % at the first sample: the rise started before the window.
            self.marks.rise_start = Some(t);
            if p >= 0.9 {
                self.marks.rise_end = Some(t);
            }
        }
        let excess = (p - 1.0) * self.size().abs();
        if excess > self.beyond {
            self.beyond = excess;
            self.marks.peak = Some((t, v));
        }
        let band = self.spec.band_percent / 100.0;
        let inside = (p - 1.0).abs() <= band;
        match (inside, self.entered_band, self.previous) {
            (true, None, Some((t0, v0))) => {
                // Interpolated to where the value crossed into the band.
                let e0 = (self.progress(v0) - 1.0).abs();
                let e1 = (p - 1.0).abs();
                let at = if e0 > e1 {
                    t0 + (t - t0) * (e0 - band) / (e0 - e1)
                } else {
                    t
                };
                self.entered_band = Some(at);
            }
            (true, None, None) => self.entered_band = Some(t),
            (false, Some(_), _) => self.entered_band = None,
            _ => {}
        }
        if t >= self.steady_from {
            self.steady_sum += v;
            self.steady_count += 1;
        }
        self.previous = Some((t, v));
    }

    /// 10 % → 90 % of the step in seconds; `None` when the value never got there.
    pub fn rise_time(&self) -> Option<f64> {
        Some(self.marks.rise_end? - self.marks.rise_start?)
    }

    /// The furthest excursion beyond the target in % of the step (0 without one).
    pub fn overshoot_percent(&self) -> Option<f64> {
        let size = self.size().abs();
        if self.previous.is_none() || size == 0.0 {
            return None;
        }
        Some((self.beyond.max(0.0) / size) * 100.0)
    }

    /// Seconds from the window's start until the value stayed within the band; `None`
    /// when it was outside at the end.
    pub fn settling_time(&self) -> Option<f64> {
        self.entered_band.map(|t| (t - self.start).max(0.0))
    }

    /// The mean of the last tenth of the window minus the target.
    pub fn steady_state_error(&self) -> Option<f64> {
        (self.steady_count > 0).then(|| self.steady_sum / self.steady_count as f64 - self.spec.to)
    }

    pub fn marks(&self) -> ResponseMarks {
        ResponseMarks {
            settled: self.entered_band,
            ..self.marks
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(to: f64) -> StepSpec {
        StepSpec {
            from: Some(0.0),
            to,
            band_percent: 2.0,
        }
    }

    /// A first-order response to a step at t = 0, sampled every `dt` for `duration`.
    fn first_order(tau: f64, dt: f64, duration: f64) -> StepResponse {
        let mut r = StepResponse::new(spec(1000.0), 0.0, duration);
        let n = (duration / dt).round() as u32;
        for k in 0..=n {
            let t = f64::from(k) * dt;
            r.push(t, 1000.0 * (1.0 - (-t / tau).exp()));
        }
        r
    }

    #[test]
    fn a_first_order_response_rises_in_tau_ln_9_and_settles_in_tau_ln_50() {
        let r = first_order(0.2, 0.001, 3.0);
        let rise = r.rise_time().unwrap();
        assert!((rise - 0.2 * 9f64.ln()).abs() < 1e-3, "{rise}");
        let settle = r.settling_time().unwrap();
        assert!((settle - 0.2 * 50f64.ln()).abs() < 1e-3, "{settle}");
        assert_eq!(r.overshoot_percent(), Some(0.0));
        assert!(r.steady_state_error().unwrap().abs() < 1e-3);
    }

    #[test]
    fn overshoot_of_a_damped_oscillation_is_its_first_peak() {
        // Second order, ζ = 0.5: overshoot exp(-π ζ / √(1-ζ²)) = 16.3 %.
        let (zeta, wn) = (0.5f64, 10.0f64);
        let wd = wn * (1.0 - zeta * zeta).sqrt();
        let mut r = StepResponse::new(spec(100.0), 0.0, 5.0);
        for k in 0..=5000 {
            let t = f64::from(k) * 0.001;
            let e = (-zeta * wn * t).exp() * ((wd * t).cos() + zeta * wn / wd * (wd * t).sin());
            r.push(t, 100.0 * (1.0 - e));
        }
        let expected = (-std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt()).exp() * 100.0;
        assert!((r.overshoot_percent().unwrap() - expected).abs() < 0.01);
        let (peak_t, _) = r.marks().peak.unwrap();
        assert!((peak_t - std::f64::consts::PI / wd).abs() < 2e-3, "{peak_t}");
    }

    #[test]
    fn a_response_that_never_arrives_has_no_rise_or_settling_time() {
        let mut r = StepResponse::new(spec(1000.0), 0.0, 1.0);
        for k in 0..=10 {
            r.push(f64::from(k) * 0.1, 50.0 * f64::from(k));
        }
        assert!(r.rise_start_only());
        assert_eq!(r.rise_time(), None);
        assert_eq!(r.settling_time(), None);
        // The last tenth holds the samples at 0.9 s and 1.0 s: 450 and 500 rpm.
        assert!((r.steady_state_error().unwrap() - (475.0 - 1000.0)).abs() < 1e-9);
    }

    #[test]
    fn a_downward_step_is_measured_the_same_way() {
        let mut r = StepResponse::new(
            StepSpec {
                from: None,
                to: 0.0,
                band_percent: 5.0,
            },
            10.0,
            2.0,
        );
        for k in 0..=200 {
            let t = 10.0 + f64::from(k) * 0.01;
            r.push(t, 6000.0 * (-(t - 10.0) / 0.1).exp());
        }
        assert!((r.rise_time().unwrap() - 0.1 * 9f64.ln()).abs() < 2e-3);
        assert!((r.settling_time().unwrap() - 0.1 * 20f64.ln()).abs() < 2e-3);
    }

    impl StepResponse {
        fn rise_start_only(&self) -> bool {
            self.marks.rise_start.is_some() && self.marks.rise_end.is_none()
        }
    }
}
