//! The `//!` lines at the top of a script: `drive`, `drives`, `name`, `link`, and the
//! choices a recipe makes with its top-level keys `leave_enabled` and `safe_stop`, in the
//! same spelling and checked with the same rules and messages. Every problem is located
//! (unknown keys with did-you-mean). Prose belongs in `//` comments: a `//!` line whose
//! key is a single word is a header key. It must not load dictionaries or run anything.

use super::literal_calls::LineIndex;
use crate::diag::{did_you_mean, suggestion_text, Diagnostic, Diagnostics, Reader, Source, Span};
use crate::dictionary::{read_dimensioned, Dimension};
use crate::recipe::{DriveDecl, SafeStopChoice};
use std::sync::Arc;

/// The keys a script's header may give.
pub const HEADER_KEYS: &[&str] = &["drive", "drives", "name", "link", "leave_enabled", "safe_stop"];
/// The settings of `//! safe_stop:`, as a recipe's `safe_stop:` has them.
const SAFE_STOP_KEYS: &[&str] = &["timeout", "standstill", "brake_to_standstill"];
const SAFE_STOP_EXAMPLE: &str = "//! safe_stop: timeout=2 min, standstill=20 rpm";

/// `//! drive: sd2`, `//! name: Speed sweep`, `//! link: channel=cyclic, …`,
/// `//! drives: left = sd2 @ dnc:2, right = sd2 @ dnc:3`, `//! leave_enabled: true`,
/// `//! safe_stop: timeout=2 min, standstill=20 rpm`.
pub struct Header {
    pub drive: Option<(String, Span)>,
    pub name: Option<String>,
    pub link: Vec<(String, String)>,
    pub drives: Vec<DriveDecl>,
    /// Where each of `drives` is written.
    pub drive_spans: Vec<Span>,
    /// After a successful run, leave the drive as the script left it (as a recipe's
    /// `leave_enabled: true`).
    pub leave_enabled: bool,
    pub safe_stop: SafeStopChoice,
    pub problems: Diagnostics,
}

/// One `//!` line's key and value, with where each is written.
struct Entry<'t> {
    key: &'t str,
    key_at: usize,
    value: &'t str,
    value_at: usize,
}

impl Header {
    pub fn read(source: &Arc<Source>) -> Header {
        let mut header = Header {
            drive: None,
            name: None,
            link: Vec::new(),
            drives: Vec::new(),
            drive_spans: Vec::new(),
            leave_enabled: false,
            safe_stop: SafeStopChoice::default(),
            problems: Diagnostics::new(),
        };
        let index = LineIndex::new(source.text());
        let span = |at: usize, len: usize| index.span(source, at, len);
        let mut seen: Vec<&str> = Vec::new();
        let mut offset = 0;
        for line in source.text().split_inclusive('\n') {
            let Some(rest) = line.trim_start().strip_prefix("//!") else {
                break;
            };
            let rest_at = offset + line.len() - rest.len();
            let entry = rest.split_once(':').map(|(key, value)| {
                let key_at = rest_at + (key.len() - key.trim_start().len());
                let value_at = rest_at + key.len() + 1 + (value.len() - value.trim_start().len());
                Entry {
                    key: key.trim(),
                    key_at,
                    value: value.trim(),
                    value_at,
                }
            });
            offset += line.len();
            let Some(e) = entry.filter(|e| is_word(e.key)) else {
                continue;
            };
            let key_span = span(e.key_at, e.key.len());
            let value_span = span(e.value_at, e.value.len());
            if !HEADER_KEYS.contains(&e.key) {
                let keys = format!(
                    "the keys of a script's header are: {}; write other notes as `//` comments",
                    HEADER_KEYS.join(", ")
                );
                let unknown = unknown_key(&key_span, e.key, HEADER_KEYS, "this script's header", keys);
                header.problems.push(unknown);
                continue;
            }
            // `link:` may take several lines; any other key is given once.
            if e.key != "link" && seen.contains(&e.key) {
                header.problems.push(Diagnostic::at(
                    &key_span,
                    format!("`{}` is given twice in this script's header", e.key),
                    "again here",
                ));
                continue;
            }
            seen.push(e.key);
            match e.key {
                "drive" => header.drive = Some((e.value.to_string(), value_span)),
                "name" => header.name = Some(e.value.to_string()),
                // The family checks names and values before the port opens.
                "link" => header.link.extend(
                    settings(e.value, e.value_at)
                        .into_iter()
                        .filter_map(|s| Some((s.key.to_string(), s.value?.0.to_string()))),
                ),
                "drives" => {
                    for entry in e.value.split(',').filter(|e| !e.trim().is_empty()) {
                        let (name, rest) = entry.split_once('=').unwrap_or((entry, ""));
                        let (drive, address) = match rest.split_once('@') {
                            Some((d, a)) => (d.trim(), Some(a.trim().to_string())),
                            None => (rest.trim(), None),
                        };
                        header.drives.push(DriveDecl {
                            name: name.trim().to_string(),
                            drive: drive.to_string(),
                            address,
                            port: None,
                            tcp: None,
                            can: None,
                        });
                        header.drive_spans.push(value_span.clone());
                    }
                }
                "leave_enabled" => match e.value {
                    "true" | "True" | "TRUE" => header.leave_enabled = true,
                    "false" | "False" | "FALSE" => header.leave_enabled = false,
                    other => header.problems.push(
                        Diagnostic::at(
                            &value_span,
                            format!("`leave_enabled` must be true or false, found `{other}`"),
                            "expected true or false",
                        )
                        .with_help("write `//! leave_enabled: true`"),
                    ),
                },
                _ => header.safe_stop = safe_stop(&e, &span, &mut header.problems),
            }
        }
        header
    }
}

/// A header key: one word (`leave_enabled`), not a sentence that happens to hold a colon.
fn is_word(key: &str) -> bool {
    !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// One `NAME=VALUE` of a comma-separated list, with where each part is written; `value`
/// is `None` when the `=` is missing.
struct Setting<'t> {
    key: &'t str,
    key_at: usize,
    value: Option<(&'t str, usize)>,
}

fn settings(text: &str, at: usize) -> Vec<Setting<'_>> {
    let mut out = Vec::new();
    let mut start = 0;
    for part in text.split(',') {
        let part_at = at + start;
        start += part.len() + 1;
        if part.trim().is_empty() {
            continue;
        }
        let lead = part.len() - part.trim_start().len();
        let (key, value) = match part.split_once('=') {
            Some((k, v)) => {
                let v_lead = v.len() - v.trim_start().len();
                (k, Some((v.trim(), part_at + k.len() + 1 + v_lead)))
            }
            None => (part, None),
        };
        out.push(Setting {
            key: key.trim(),
            key_at: part_at + lead,
            value,
        });
    }
    out
}

/// `//! safe_stop: timeout=2 min, standstill=20 rpm`, read as a recipe's `safe_stop:`.
fn safe_stop(e: &Entry, span: &dyn Fn(usize, usize) -> Span, problems: &mut Diagnostics) -> SafeStopChoice {
    let mut choice = SafeStopChoice::default();
    let all = settings(e.value, e.value_at);
    if all.is_empty() {
        problems.push(
            Diagnostic::at(
                &span(e.key_at, e.key.len()),
                "`safe_stop` gives no settings",
                "empty",
            )
            .with_help(format!("e.g. `{SAFE_STOP_EXAMPLE}`")),
        );
    }
    let mut seen: Vec<&str> = Vec::new();
    for s in all {
        let key_span = span(s.key_at, s.key.len());
        if !SAFE_STOP_KEYS.contains(&s.key) {
            let keys = format!("the keys of this safe_stop are: {}", SAFE_STOP_KEYS.join(", "));
            problems.push(unknown_key(
                &key_span,
                s.key,
                SAFE_STOP_KEYS,
                "this safe_stop",
                keys,
            ));
            continue;
        }
        if seen.contains(&s.key) {
            problems.push(Diagnostic::at(
                &key_span,
                format!("`{}` is given twice in this safe_stop", s.key),
                "again here",
            ));
            continue;
        }
        seen.push(s.key);
        let Some((value, value_at)) = s.value else {
            problems.push(
                Diagnostic::at(&key_span, format!("`{}` has no value", s.key), "NAME=VALUE").with_help(
                    format!("write each setting as NAME=VALUE, e.g. `{SAFE_STOP_EXAMPLE}`"),
                ),
            );
            continue;
        };
        let value_span = span(value_at, value.len());
        if s.key == "brake_to_standstill" {
            match value {
                "true" | "True" | "TRUE" => {}
                "false" | "False" | "FALSE" => {
                    choice.no_brake_at = Some((value_span.line(), value_span.column()))
                }
                other => problems.push(
                    Diagnostic::at(
                        &value_span,
                        format!("`brake_to_standstill` must be true or false, found `{other}`"),
                        "true or false",
                    )
                    .with_help("write `brake_to_standstill=false` to disable a turning drive without braking it first"),
                ),
            }
        } else if s.key == "timeout" {
            match super::resolve::duration(value) {
                Ok(d) => choice.timeout = Some(d),
                Err(r) => problems.push(
                    Diagnostic::at(&value_span, format!("safe_stop timeout: {}", r.message), r.label)
                        .with_optional_help(r.help),
                ),
            }
        } else {
            let mut reader = Reader::new(problems);
            choice.standstill = read_dimensioned(
                &mut reader,
                &value_span,
                "standstill",
                value,
                Dimension::Speed,
                "standstill=20 rpm",
            )
            .map(|(q, _)| q);
        }
    }
    choice
}

/// `key` is none of `keys` of `what`: the help is the nearest key, else `listing`.
fn unknown_key(span: &Span, key: &str, keys: &[&str], what: &str, listing: String) -> Diagnostic {
    let help = suggestion_text(&did_you_mean(key, keys.iter().copied())).unwrap_or(listing);
    Diagnostic::at(span, format!("unknown key `{key}` in {what}"), "unknown key").with_help(help)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn read(text: &str) -> Header {
        Header::read(&Source::new("t.rhai", text))
    }

    fn problems(text: &str) -> Vec<String> {
        read(text).problems.iter().map(|d| d.located()).collect()
    }

    #[test]
    fn leave_enabled_and_safe_stop_read_as_a_recipes() {
        let h = read(
            "//! drive: sd2\n//! leave_enabled: true\n//! safe_stop: timeout=2 min, standstill = 20 rpm\nlet d = drive();\n",
        );
        assert!(h.problems.is_empty(), "{}", h.problems.render(false));
        assert!(h.leave_enabled);
        assert_eq!(h.safe_stop.timeout, Some(Duration::from_secs(120)));
        let standstill = h.safe_stop.standstill.expect("a standstill");
        assert_eq!(standstill.value, 20.0);
        assert_eq!(standstill.unit, Some(crate::dictionary::Unit::Rpm));
        let plain = read("//! drive: sd2\nlet d = drive();\n");
        assert!(!plain.leave_enabled);
        assert_eq!(plain.safe_stop, SafeStopChoice::default());
    }

    #[test]
    fn brake_to_standstill_false_is_an_opt_out_with_its_place() {
        let h = read("//! drive: sd2\n//! safe_stop: timeout=2 s, brake_to_standstill=false\n");
        assert!(h.problems.is_empty(), "{}", h.problems.render(false));
        assert_eq!(h.safe_stop.no_brake_at, Some((2, 49)));
        let on = read("//! drive: sd2\n//! safe_stop: brake_to_standstill=true\n");
        assert_eq!(on.safe_stop.no_brake_at, None);
        let p: Vec<String> = read("//! safe_stop: brake_to_standstill=no\n")
            .problems
            .iter()
            .map(|d| d.located())
            .collect();
        assert_eq!(
            p,
            ["t.rhai:1:36: `brake_to_standstill` must be true or false, found `no`"]
        );
    }

    #[test]
    fn the_header_ends_at_the_first_other_line() {
        let h = read("//! drive: sd2\n// prose: here\n//! leave_enabled: maybe\n");
        assert!(h.problems.is_empty());
        assert!(!h.leave_enabled);
    }

    #[test]
    fn wrong_keys_and_values_are_located_with_suggestions() {
        let p = read(
            "//! leave_enable: true\n//! leave_enabled: yes\n//! safe_stop: tmeout=1 s, timeout=0 s, standstill=fast\n//! safe_stop: timeout=1 s\n//! Sweeps the spindle: slowly\n",
        );
        let located: Vec<String> = p.problems.iter().map(|d| d.located()).collect();
        assert_eq!(
            located,
            [
                "t.rhai:1:5: unknown key `leave_enable` in this script's header",
                "t.rhai:2:20: `leave_enabled` must be true or false, found `yes`",
                "t.rhai:3:16: unknown key `tmeout` in this safe_stop",
                "t.rhai:3:36: safe_stop timeout: a duration must be longer than zero",
                "t.rhai:3:52: `standstill`: `fast` is not a number: write a number with an optional unit, e.g. `6000 rpm`, `1.5 A`, `250 ms`, `0x0F`",
                "t.rhai:4:5: `safe_stop` is given twice in this script's header",
            ],
            "{}",
            p.problems.render(false)
        );
        let helps: Vec<Option<&str>> = p.problems.iter().map(|d| d.help()).collect();
        assert_eq!(helps[0], Some("did you mean `leave_enabled`?"));
        assert_eq!(helps[2], Some("did you mean `timeout`?"));
    }

    #[test]
    fn a_standstill_must_be_a_speed_and_a_timeout_a_duration() {
        let p = problems("//! safe_stop: timeout=5, standstill=2 A\n");
        assert_eq!(p.len(), 2, "{p:#?}");
        assert!(
            p[0].starts_with("t.rhai:1:24: safe_stop timeout: `5` is not a duration"),
            "{p:#?}"
        );
        assert!(p[1].starts_with("t.rhai:1:38: `standstill` is a speed"), "{p:#?}");
        let p = problems("//! safe_stop: timeout\n//! safe_stop:\n");
        assert_eq!(p[0], "t.rhai:1:16: `timeout` has no value");
    }
}
