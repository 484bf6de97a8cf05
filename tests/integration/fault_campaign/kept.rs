//! Every scenario the campaign ever failed, kept as a recipe case under
//! `tests/cases/<outcome>/campaign_<family>_<seed>/` (the recipe, and `case.yaml` with the
//! fault in the cases' own terms and the ending the run must have), so that the recipe
//! cases hold it with its exit code and lines, and the campaign replays its seed with all
//! of its invariants. A store that goes away is not a case setting: its case says so and
//! only the replayed seed covers it.

use super::fault::Kind;
use super::{cases_root, Outcome, RECONNECT_TIMEOUT, STOP_TIMEOUT};
use std::fmt::Write;

/// The seeds of the kept cases.
pub fn seeds() -> Vec<u64> {
    let mut out = Vec::new();
    for group in std::fs::read_dir(cases_root()).into_iter().flatten().flatten() {
        for case in std::fs::read_dir(group.path()).into_iter().flatten().flatten() {
            let name = case.file_name().to_string_lossy().into_owned();
            if let Some(seed) = name
                .strip_prefix("campaign_")
                .and_then(|rest| rest.rsplit('_').next())
                .and_then(|s| s.parse().ok())
            {
                out.push(seed);
            }
        }
    }
    out.sort_unstable();
    out
}

fn group_of(exit: i32) -> &'static str {
    match exit {
        0 => "ok",
        1 => "failed",
        2 => "invalid",
        129..=159 => "interrupted",
        _ => "error",
    }
}

/// A time as the case reads it, exact to the nanosecond: a fault a millisecond off can
/// fall on another telegram.
fn ms(d: std::time::Duration) -> String {
    match d.subsec_nanos() % 1_000_000 {
        0 => format!("{} ms", d.as_millis()),
        _ => format!("{} ns", d.as_nanos()),
    }
}

/// `line` up to a speed (`… at 1494 rpm`) or its summary (` — 7 step(s) …`): the state,
/// not the speed, whose last digit moves with any change of timing.
fn without_speed(line: &str) -> &str {
    let line = line.split(" — ").next().unwrap_or(line);
    let speed = line
        .match_indices(" at ")
        .find(|(i, _)| line[i + 4..].starts_with(|c: char| c.is_ascii_digit() || c == '-'));
    match speed {
        Some((i, _)) => &line[..i],
        None => line,
    }
}

/// Writes `o` as a case, with the ending it had: kept after the fix, when that ending is
/// the true one.
pub fn write(o: &Outcome) {
    let Some(fault) = o.fault else { return };
    let dir = cases_root()
        .join(group_of(o.exit))
        .join(format!("campaign_{}_{}", o.target, o.seed));
    std::fs::create_dir_all(&dir).expect("case folder");
    std::fs::write(dir.join("recipe.yaml"), &o.recipe).expect("recipe");
    let at = ms(fault.at);
    let mut c = format!(
        "# Kept by the fault campaign (tests/integration/fault_campaign): seed {}, {}.\n# Replays with all the campaign's invariants: {}\nexit: {}\nsafe_stop: {{ stop_timeout: {}, reconnect_timeout: {} }}\n",
        o.seed,
        fault.describe(),
        super::replay_command(o.seed),
        o.exit,
        ms(STOP_TIMEOUT),
        ms(RECONNECT_TIMEOUT)
    );
    let sim = match fault.kind {
        Kind::Trip(code) => format!("trip_at: {at}, drive_error: {code}"),
        Kind::LineLost(d) => format!("line_down: [{at}, {}]", ms(fault.at + d)),
        Kind::Silent(d) => format!("silent: [{at}, {}]", ms(fault.at + d)),
        Kind::HeartbeatLoss => format!("silent: [{at}, 86400 s]"),
        Kind::LateReplies(n, by) => format!("replies_from: {at}, delay_replies: {n}, delay_by: {}", ms(by)),
        Kind::Garbage(n) => format!("replies_from: {at}, garbage: {n}"),
        Kind::Corrupt(n) => format!("replies_from: {at}, corrupt_checksum: {n}"),
        Kind::Emcy(code) => format!("emergency_at: {at}, drive_error: {code}"),
        Kind::Panic => format!("panic_at: {at}"),
        Kind::Disobeys(commands) => format!(
            "ignore_commands: [{}]",
            commands.iter().map(|c| c.id()).collect::<Vec<_>>().join(", ")
        ),
        Kind::Signal(s) => {
            let _ = writeln!(c, "interrupt_at: {at}\nsignal: {}", &s.name[3..]);
            String::new()
        }
        Kind::SecondSignal(s, _, after) => {
            let _ = writeln!(
                c,
                "interrupt_at: {at}\nsecond_interrupt_at: {}\nsignal: {}",
                ms(fault.at + after),
                &s.name[3..]
            );
            String::new()
        }
        Kind::StoreGone(after) => {
            let _ = writeln!(
                c,
                "# The results store is locked from finished step {after} on: only the replayed seed has it."
            );
            String::new()
        }
        Kind::None => String::new(),
    };
    if !sim.is_empty() {
        let _ = writeln!(c, "sim: {{ {sim} }}");
    }
    let wanted: Vec<&str> = o
        .console
        .lines()
        .filter(|l| {
            l.starts_with("drive left")
                || l.starts_with("drive state")
                || super::judge::word_of(o.exit).is_some_and(|w| l.starts_with(w))
        })
        .map(without_speed)
        .collect();
    c.push_str("output: |\n");
    for line in wanted {
        let _ = writeln!(c, "  {line}");
    }
    std::fs::write(dir.join("case.yaml"), c).expect("case.yaml");
}
