//! Run reports as the runner hands them over, for the report writers' tests: one that
//! passed and one that ended in a communication error. A run report starts as the library
//! starts one ([`report`]); steps and checks are written out field by field in exactly one
//! function each ([`step`], [`check`]), so a new field is one edit.

use drivescript::drive::DeviceState;
use drivescript::session::{
    CheckResult, EndState, Limits, RunReport, Series, StepOrigin, StepRecord, Verdict,
};
use std::time::{Duration, UNIX_EPOCH};

pub fn origin(line: usize) -> StepOrigin {
    StepOrigin {
        path: "recipes/run-in.yaml".into(),
        line,
        column: 5,
    }
}

/// A step that took 250 ms; step n is written on line 10 + n.
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
        id: number.into(),
        label: label.into(),
        origin: origin(10 + number.parse::<usize>().unwrap_or(0)),
        ok,
        detail: detail.into(),
        started: Duration::from_millis(started_ms),
        duration: Duration::from_millis(250),
        phase,
    }
}

/// The key the session gives a check named `name`: the name without its limits.
pub fn key_of(name: &str) -> String {
    drivescript::session::key_of_name(name).unwrap_or_else(|| name.to_string())
}

/// A check with nothing measured and no limits, written on line 12, done after 1 s in 0.2 s.
pub fn check(name: &str, passed: bool, message: &str) -> CheckResult {
    CheckResult {
        key: key_of(name),
        message: message.into(),
        origin: origin(12),
        step: "2".into(),
        at: Duration::from_secs(1),
        duration: Duration::from_millis(200),
        ..CheckResult::named(name, passed)
    }
}

/// The mean of speed_actual within 5970 .. 6030 rpm, written on line 20.
pub fn speed_check(name: &str, measured: f64, passed: bool) -> CheckResult {
    CheckResult {
        measured: Some(measured),
        unit: Some("rpm".into()),
        limits: Limits::new(Some(5970.0), Some(6030.0)),
        object: Some("speed_actual".into()),
        statistic: Some("mean".into()),
        origin: origin(20),
        step: "4".into(),
        window: Some("3".into()),
        at: Duration::from_secs(65),
        duration: Duration::from_millis(1500),
        ..check(name, passed, &format!("mean {measured} rpm"))
    }
}

/// A run of `recipe` from `recipe_path` on `drive`, started 2024-06-10 06:13:20 UTC, that
/// ended with `verdict` and ran nothing: no steps, checks, series or notes, the drive's
/// state not read and the safe stop not confirmed.
pub fn report(recipe: &str, recipe_path: &str, drive: &str, verdict: Verdict) -> RunReport {
    RunReport {
        verdict,
        ..RunReport::started(
            recipe.into(),
            recipe_path.into(),
            drive.into(),
            Vec::new(),
            UNIX_EPOCH + Duration::from_secs(1_718_000_000),
        )
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
        identity: Some("SD2S 0362150C".into()),
        params: vec![("speed".into(), "6000 rpm".into())],
        duration: Duration::from_millis(66_250),
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
                measured_text: Some("operation enabled".into()),
                ..check(
                    "wait until state operation_enabled",
                    true,
                    "operation enabled after 0.2 s",
                )
            },
        ],
        series: vec![Series {
            object: "speed_actual".into(),
            unit: Some("rpm".into()),
            step: "3".into(),
            points,
            samples: None,
            marks: None,
        }],
        end: EndState {
            final_state: Some(DeviceState::SwitchedOn),
            final_speed: Some(0.4),
            speed_unit: Some("rpm".into()),
            stop_confirmed: true,
            ..EndState::default()
        },
        safe_stop: vec!["finally: disable_operation ran".into()],
        ..report(
            "Spindle <run-in> & \"test\"",
            "recipes/run-in.yaml",
            "sd2 at /dev/ttyUSB0, address 2",
            Verdict::Passed,
        )
    }
}

/// A run that failed one check and then lost the drive: verdict error.
pub fn error_report() -> RunReport {
    RunReport {
        duration: Duration::from_secs(9),
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
        safe_stop: vec!["the safety net (disable voltage) could not be sent".into()],
        ..report(
            "Acceptance",
            "recipes/accept.yaml",
            "sd2 (simulated)",
            Verdict::Error("no reply within 100 ms from drive 2 <port>".into()),
        )
    }
}
