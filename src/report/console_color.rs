//! Colour for the console lines of a run: PASS/ok green, a question to the operator
//! yellow, FAIL and the words that need a
//! human (CHECK THE DRIVE BY HAND, STILL COASTING) red, the verdict in its colour. Applied
//! to finished lines, so the plain text (logs, tests, `NO_COLOR`) is the same without it.

const GREEN: &str = "\x1b[32m";
const RED: &str = "\x1b[1;31m";
const YELLOW: &str = "\x1b[33m";
const RESET: &str = "\x1b[0m";

/// Whether to colour: `--color always|never`, else on a terminal unless `NO_COLOR` is set
/// to anything non-empty (<https://no-color.org>).
pub fn color_wanted(choice: Option<bool>, terminal: bool) -> bool {
    choice.unwrap_or_else(|| terminal && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty()))
}

/// `line` with its marks coloured.
pub fn paint(line: &str) -> String {
    let mut out = line.to_string();
    for (word, color) in [
        ("  ok    ", GREEN),
        ("  PASS  ", GREEN),
        ("  MARGINAL  ", YELLOW),
        ("  FAIL  ", RED),
        // A question to the operator.
        ("  ?     ", YELLOW),
        ("CHECK THE DRIVE BY HAND", RED),
        ("STILL COASTING", RED),
    ] {
        if let Some(at) = out.find(word) {
            let trimmed = word.trim();
            let start = at + word.find(trimmed).unwrap_or(0);
            out.replace_range(start..start + trimmed.len(), &format!("{color}{trimmed}{RESET}"));
            break;
        }
    }
    for (verdict, color) in [
        ("PASSED", GREEN),
        ("FAILED", RED),
        ("ERROR", RED),
        ("PANIC", RED),
        ("INTERRUPTED", YELLOW),
    ] {
        if out.starts_with(verdict) {
            out.replace_range(..verdict.len(), &format!("{color}{verdict}{RESET}"));
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marks_and_verdicts_get_colour_and_nothing_else_changes() {
        assert_eq!(
            paint("     3  ok    switch_on"),
            format!("     3  {GREEN}ok{RESET}    switch_on")
        );
        assert_eq!(
            paint("        FAIL  x: y"),
            format!("        {RED}FAIL{RESET}  x: y")
        );
        assert_eq!(
            paint("PASSED — 9 step(s)"),
            format!("{GREEN}PASSED{RESET} — 9 step(s)")
        );
        assert_eq!(paint("params  a = 1"), "params  a = 1");
        assert!(color_wanted(Some(true), false));
        assert!(!color_wanted(Some(false), true));
        assert!(!color_wanted(None, false));
    }
}
