//! Test support: run reports as the runner would hand them over, one that passed and one
//! that ended in a communication error, for the report writers' tests. Only for tests.

use crate::drive::device_control::DeviceState;
use crate::recipe::{CheckResult, RunReport, Series, StepOrigin, StepRecord, Verdict};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

pub fn origin(line: usize) -> StepOrigin {
    StepOrigin {
        path: "recipes/run-in.yaml".into(),
        line,
        column: 5,
    }
}

pub fn step(
    number: &str,
    label: &str,
    ok: bool,
    detail: &str,
    started_ms: u64,
    phase: &'static str,
) -> StepRecord {
    StepRecord {
        number: number.into(),
        label: label.into(),
        // Step n is written on line 10 + n.
        origin: origin(10 + number.parse::<usize>().unwrap_or(0)),
        ok,
        detail: detail.into(),
        started: Duration::from_millis(started_ms),
        duration: Duration::from_millis(250),
        phase,
    }
}

pub fn speed_check(name: &str, measured: f64, passed: bool) -> CheckResult {
    CheckResult {
        name: name.into(),
        passed,
        measured: Some(measured),
        measured_text: None,
        unit: Some("rpm".into()),
        low: Some(5970.0),
        high: Some(6030.0),
        object: Some("speed_actual".into()),
        statistic: Some("mean".into()),
        message: format!("mean {measured} rpm"),
        origin: origin(20),
        at: Duration::from_secs(65),
        duration: Duration::from_millis(1500),
    }
}

/// `Spindle <run-in> & "test"`, passed, two checks, one 601-point series of speed_actual.
pub fn passed_report() -> RunReport {
    let points = (0..=600)
        .map(|i| {
            let t = 5.0 + f64::from(i) * 0.1;
            (t, 6000.0 + if i % 2 == 0 { 1.5 } else { -1.25 })
        })
        .collect();
    RunReport {
        recipe: "Spindle <run-in> & \"test\"".into(),
        recipe_path: "recipes/run-in.yaml".into(),
        drive: "sd2 at /dev/ttyUSB0, address 2".into(),
        identity: Some("SD2S 0362150C".into()),
        params: vec![("speed".into(), "6000 rpm".into())],
        started_at: UNIX_EPOCH + Duration::from_secs(1_718_000_000),
        duration: Duration::from_millis(66_250),
        verdict: Verdict::Passed,
        steps: vec![
            step("1", "shutdown", true, "ready to switch on", 0, "steps"),
            step("2", "set speed_setpoint = 6000 rpm", true, "", 250, "steps"),
            step(
                "3",
                "sample speed_actual every 100 ms for 60 s",
                true,
                "mean 6000.1 rpm",
                5_000,
                "steps",
            ),
            step(
                "4",
                "expect speed_actual mean near 6000 rpm ± 0.5 %",
                true,
                "",
                65_000,
                "steps",
            ),
            step("1", "disable_operation", true, "switched on", 65_500, "finally"),
        ],
        checks: vec![
            speed_check("speed_actual mean near 6000 rpm ± 0.5 %", 6000.1, true),
            CheckResult {
                name: "wait until state operation_enabled".into(),
                passed: true,
                measured: None,
                measured_text: Some("operation enabled".into()),
                unit: None,
                low: None,
                high: None,
                object: None,
                statistic: None,
                message: "operation enabled after 0.2 s".into(),
                origin: origin(12),
                at: Duration::from_secs(1),
                duration: Duration::from_millis(200),
            },
        ],
        series: vec![Series {
            object: "speed_actual".into(),
            unit: Some("rpm".into()),
            step: "3".into(),
            points,
        }],
        final_state: Some(DeviceState::SwitchedOn),
        final_speed: Some(0.4),
        speed_unit: Some("rpm".into()),
        coasting: false,
        stop_confirmed: true,
        disobeyed: false,
        safe_stop: vec!["finally: disable_operation ran".into()],
    }
}

/// A run that failed one check and then lost the drive: verdict error.
pub fn error_report() -> RunReport {
    RunReport {
        recipe: "Acceptance".into(),
        recipe_path: "recipes/accept.yaml".into(),
        drive: "sd2 (simulated)".into(),
        identity: None,
        params: Vec::new(),
        started_at: SystemTime::UNIX_EPOCH + Duration::from_secs(1_718_000_000),
        duration: Duration::from_secs(9),
        verdict: Verdict::Error("no reply within 100 ms from drive 2 <port>".into()),
        steps: vec![
            step("1", "expect speed_actual", false, "mean 5800 rpm", 0, "steps"),
            step(
                "2",
                "dwell 10 s",
                false,
                "no reply within 100 ms from drive 2 <port>",
                2_000,
                "steps",
            ),
        ],
        checks: vec![CheckResult {
            // Written in step 1.
            origin: origin(11),
            ..speed_check("speed & <mean>", 5800.0, false)
        }],
        series: Vec::new(),
        final_state: None,
        final_speed: None,
        speed_unit: None,
        coasting: false,
        stop_confirmed: false,
        disobeyed: false,
        safe_stop: vec!["the safety net (disable voltage) could not be sent".into()],
    }
}
