//! The simulated drive's settings: its address on the bus, timing and the physical constants of the
//! motor model. Plain data with the documented defaults; it must not hold any state.

use super::motor::Response;
use std::time::Duration;

/// How the simulated drive is set up. `Default` gives a drive at bus address 2 with a
/// 230 V supply and a light spindle.
#[derive(Debug, Clone, PartialEq)]
pub struct SimConfig {
    /// The address the drive answers to, in its family's numbering.
    pub address: u8,
    /// Time from the last byte of a request to the reply. The manual promises at most
    /// 250 µs; 100 µs keeps the simulator well inside that.
    pub response_latency: Duration,
    /// Speed ramp in operation enabled.
    pub ramp_rpm_per_s: f64,
    /// Deceleration in quick stop active and fault reaction active.
    pub quick_stop_ramp_rpm_per_s: f64,
    /// Friction deceleration while the power stage is off (the motor coasts).
    pub coast_rpm_per_s: f64,
    /// The speed that the cyclic telegram's 0x3FFF (+100 %) stands for.
    pub velocity_scaling_rpm: f64,
    /// Largest speed setpoint the drive accepts (either sign).
    pub max_speed_rpm: f64,
    /// Peak of the noise on the actual speed.
    pub noise_rpm: f64,
    /// Seed of the noise generator; the same seed gives the same measurements.
    pub seed: u64,
    /// Parameter-set identification (object 22); at most 32 bytes are reported.
    pub ident: String,
    /// How operation enabled follows a setpoint step; `None`: it ramps at `ramp_rpm_per_s`.
    pub response: Option<Response>,
    /// The motor's temperature at rest and the start.
    pub ambient_c: f64,
    /// Steady temperature rise per ampere of steady motor current.
    pub heating_k_per_a: f64,
    /// How fast the motor temperature settles (63 % of the way in this time).
    pub thermal_time_constant: Duration,
    /// Emergency messages (a CANopen node's EMCY) sent at these clock times with these
    /// error codes, without a trip (see `FaultInjection::emergency_at`).
    pub emergencies: Vec<(Duration, u16)>,
    /// Trips at these clock times with these drive errors (see `FaultInjection::trip_at`).
    pub trips: Vec<(Duration, u16)>,
    /// The drive answers nothing from the first time until the second (see
    /// `FaultInjection::silent`).
    pub silent: Option<(Duration, Duration)>,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            address: 2,
            response_latency: Duration::from_micros(100),
            ramp_rpm_per_s: 2000.0,
            quick_stop_ramp_rpm_per_s: 10_000.0,
            coast_rpm_per_s: 300.0,
            velocity_scaling_rpm: 24_000.0,
            max_speed_rpm: 60_000.0,
            noise_rpm: 0.5,
            seed: 0,
            ident: "Test Motor".to_string(),
            response: None,
            ambient_c: 25.0,
            heating_k_per_a: 25.0,
            thermal_time_constant: Duration::from_secs(10 * 60),
            emergencies: Vec::new(),
            trips: Vec::new(),
            silent: None,
        }
    }
}
