//! The campaign's invariants, judged on one finished scenario: exit 0 only with every
//! check passed and the simulated drive really stopped; exit code, console verdict line,
//! JUnit, HTML and the stored verdict saying the same; no state change after the stop
//! began that moves the drive up its state machine; a run ended at its first failed check
//! (`on_failure: stop`) never passing; the stop ending within its timeout
//! and a bounded margin. Reads what the run left; changes nothing.

use drivescript::drive::device_control::DeviceState;
use drivescript::session::RunReport;
use std::time::Duration;

/// Speeds within this count as standstill (the safe stop's default).
const STANDSTILL_RPM: f64 = 10.0;

/// What a finished scenario left to judge.
pub struct Ended<'a> {
    pub exit: i32,
    pub report: Option<&'a RunReport>,
    pub console: &'a str,
    pub junit: Option<String>,
    pub html: Option<String>,
    /// The verdict the store holds for the run, or why none could be read.
    pub stored: Result<String, String>,
    /// The drive's real end: its state (for a drive with a device-control profile) and
    /// speed at the end of the run.
    pub state: Option<DeviceState>,
    pub speed_rpm: f64,
    /// State changes control words made, as (time, from, to).
    pub changes: Vec<(Duration, DeviceState, DeviceState)>,
    /// When the safe stop began, and the clock at the end of the run.
    pub stop_start: Duration,
    pub end: Duration,
    /// How long the whole stop may take: its timeouts and a margin.
    pub stop_bound: Duration,
}

/// The verdict word an exit code stands for; `None` for a run that never started.
pub fn word_of(exit: i32) -> Option<&'static str> {
    match exit {
        0 => Some("PASSED"),
        1 => Some("FAILED"),
        3 => Some("ERROR"),
        101 => Some("PANIC"),
        129..=159 => Some("INTERRUPTED"),
        _ => None,
    }
}

/// How far up the state machine a state is: the power stage on, turning, ranks highest.
fn rank(s: DeviceState) -> u8 {
    match s {
        DeviceState::NotReadyToSwitchOn => 0,
        DeviceState::SwitchOnDisabled | DeviceState::Fault => 1,
        DeviceState::ReadyToSwitchOn => 2,
        DeviceState::SwitchedOn => 3,
        DeviceState::QuickStopActive | DeviceState::FaultReactionActive => 4,
        DeviceState::OperationEnabled => 5,
    }
}

/// The states a confirmed safe stop may leave the drive in: power stage off, no fault
/// (switched on where a dictionary's stop commands go no lower, as an inverter's stop).
fn stopped_state(s: DeviceState) -> bool {
    !s.is_powered() && s != DeviceState::Fault
}

/// The console's verdict line: its word and the exit code it states.
fn console_verdict(console: &str) -> Option<(String, Option<i32>)> {
    console.lines().rev().find_map(|line| {
        let word = line.split_whitespace().next()?.trim_end_matches(':');
        if !matches!(word, "PASSED" | "FAILED" | "ERROR" | "INTERRUPTED" | "PANIC") {
            return None;
        }
        let code = line.rsplit_once("exit code ").and_then(|(_, n)| {
            n.chars()
                .take_while(char::is_ascii_digit)
                .collect::<String>()
                .parse()
                .ok()
        });
        Some((word.to_string(), code))
    })
}

/// The verdict a JUnit file says: the run's own case, else whether anything failed.
fn junit_verdict(xml: &str) -> &'static str {
    for (mark, word) in [
        ("message=\"ERROR", "ERROR"),
        ("message=\"INTERRUPTED", "INTERRUPTED"),
        ("message=\"PANIC", "PANIC"),
    ] {
        if xml.contains(mark) {
            return word;
        }
    }
    if xml.contains("<failure") || xml.contains("<error") {
        "FAILED"
    } else {
        "PASSED"
    }
}

/// The verdict an HTML report shows at its top.
fn html_verdict(html: &str) -> Option<String> {
    let (_, rest) = html.split_once("id=\"verdict\">")?;
    rest.split_whitespace()
        .nth(1)
        .map(|w| w.trim_end_matches("</p>").to_string())
}

/// Every invariant the scenario broke, in words.
pub fn problems(e: &Ended) -> Vec<String> {
    let mut out = Vec::new();
    let Some(word) = word_of(e.exit) else {
        if e.exit != 2 {
            out.push(format!("exit code {} is none of the documented ones", e.exit));
        }
        return out;
    };
    match console_verdict(e.console) {
        Some((w, code)) if w == word && code.is_none_or(|c| c == e.exit) => {}
        other => out.push(format!("console verdict {other:?} for exit code {}", e.exit)),
    }
    if let Some(r) = e.report {
        // A run ended at its first failed check (`on_failure: stop`) never passes.
        if r.stopped_on_failure.is_some() && e.exit == 0 {
            out.push("the run stopped on a failed check, yet exit code 0".into());
        }
        if r.verdict.exit_code() != e.exit {
            out.push(format!(
                "the report's verdict {:?} is not exit code {}",
                r.verdict, e.exit
            ));
        }
    }
    match &e.junit {
        Some(xml) if junit_verdict(xml) == word => {}
        Some(xml) => out.push(format!(
            "JUnit says {} for exit code {}",
            junit_verdict(xml),
            e.exit
        )),
        None => out.push("no JUnit file".into()),
    }
    match e.html.as_deref().map(html_verdict) {
        Some(Some(w)) if w == word => {}
        other => out.push(format!("HTML verdict {other:?} for exit code {}", e.exit)),
    }
    match &e.stored {
        Ok(v) if v.eq_ignore_ascii_case(word) => {}
        Ok(v) => out.push(format!("the store holds verdict {v} for exit code {}", e.exit)),
        Err(why) => out.push(format!("no stored verdict: {why}")),
    }
    if e.exit == 0 {
        if let Some(r) = e.report {
            let failed = r.checks.iter().filter(|c| !c.passed).count();
            if failed > 0 {
                out.push(format!("exit 0 with {failed} failed check(s)"));
            }
        }
        if e.speed_rpm.abs() >= STANDSTILL_RPM {
            out.push(format!(
                "exit 0 but the drive still turns at {:.0} rpm",
                e.speed_rpm
            ));
        }
        if let Some(s) = e.state.filter(|s| !stopped_state(*s)) {
            out.push(format!("exit 0 but the drive was left in {s:?}"));
        }
    }
    for (at, from, to) in &e.changes {
        if *at >= e.stop_start && rank(*to) > rank(*from) {
            out.push(format!(
                "at {at:?}, after the stop began at {:?}, a control word moved the drive up from {from:?} to {to:?}",
                e.stop_start
            ));
        }
    }
    if e.end > e.stop_start + e.stop_bound {
        out.push(format!(
            "the stop began at {:?} and the run ended at {:?}: longer than {:?}",
            e.stop_start, e.end, e.stop_bound
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_are_read_from_each_report() {
        let console = "  1  ok  x\nERROR: drive fault — 2 step(s), exit code 3\noutputs j.xml\n";
        assert_eq!(console_verdict(console), Some(("ERROR".into(), Some(3))));
        assert_eq!(
            console_verdict("PASSED — 1 step(s), exit code 0"),
            Some(("PASSED".into(), Some(0)))
        );
        assert_eq!(
            junit_verdict("<testcase name=\"run\"><error type=\"error\" message=\"ERROR: x\""),
            "ERROR"
        );
        assert_eq!(
            junit_verdict("<testcase name=\"safe stop\"><failure type=\"safe_stop\""),
            "FAILED"
        );
        assert_eq!(junit_verdict("<testcase name=\"a\"/>"), "PASSED");
        assert_eq!(
            html_verdict("<p class=\"verdict passed\" id=\"verdict\">✔ PASSED</p>"),
            Some("PASSED".into())
        );
        assert!(rank(DeviceState::SwitchedOn) > rank(DeviceState::ReadyToSwitchOn));
        assert!(rank(DeviceState::SwitchOnDisabled) == rank(DeviceState::Fault));
    }
}
