//! A `wait_until` condition that uses the drive. A condition that holds the drive the wait
//! is called on makes Rhai refuse the call as a "data race", with no place; one that calls
//! another drive handle is refused by the session. Conditions judge the value they are
//! given, so both are found here in the script's text: for `check`, and for the place of
//! the run-time error when the text did not show it. It only reads the text.

use super::literal_calls::{assigned_closures, literal_calls, Arg, LiteralCall};
use crate::diag::{Diagnostic, Source};
use std::sync::Arc;

/// Every `wait_until` whose condition (written in the call, or given to a variable first)
/// uses a drive: the variable the wait is called on, one that holds `drive(…)`, or a call
/// of `drive(…)` itself.
pub fn conditions_using_the_drive(source: &Arc<Source>) -> Vec<Diagnostic> {
    let calls = literal_calls(source);
    let drives: Vec<&str> = calls
        .iter()
        .filter(|c| c.name == "drive" && !c.method)
        .filter_map(|c| c.assigned_to.as_deref())
        .collect();
    let assigned = assigned_closures(source);
    let mut problems = Vec::new();
    for wait in waits(&calls) {
        let words = match wait.args.get(1) {
            Some((Arg::Closure(words), _)) => words,
            Some((Arg::Other, span)) => {
                // The closure given to a variable before the call: the latest such.
                let Some((_, words)) = assigned.iter().rfind(|(name, words)| {
                    name == span.written()
                        && words.first().is_none_or(|(_, s)| s.offset() < wait.span.offset())
                }) else {
                    continue;
                };
                words
            }
            _ => continue,
        };
        let used = words.iter().find(|(w, _)| {
            wait.receiver.as_deref() == Some(w.as_str()) || drives.contains(&w.as_str()) || w == "drive"
        });
        if let Some((word, span)) = used {
            let message = if word == "drive" {
                "a wait_until condition must not call the drive: `drive()` is called inside the condition"
                    .to_string()
            } else {
                format!(
                    "a wait_until condition must not use the drive: `{word}` is used inside the condition"
                )
            };
            problems.push(
                Diagnostic::at(span, message, "the drive, inside the condition")
                    .also_at(&wait.span, "in this wait_until")
                    .with_help(help(wait)),
            );
        }
    }
    problems
}

/// The place of Rhai's "data race" refusal of a `wait_until` (which has none): the waits
/// whose condition the text does not show (a closure kept in an array, returned by a
/// function), or failing that every wait.
pub fn data_race(source: &Arc<Source>) -> Diagnostic {
    if let Some(d) = conditions_using_the_drive(source).into_iter().next() {
        return d;
    }
    let calls = literal_calls(source);
    let all: Vec<&LiteralCall> = waits(&calls).collect();
    let unseen: Vec<&LiteralCall> = all
        .iter()
        .copied()
        .filter(|w| !matches!(w.args.get(1), Some((Arg::Closure(_), _))))
        .collect();
    let candidates = if unseen.is_empty() { all } else { unseen };
    let message = "the wait_until condition holds the drive the wait is called on, so the call was refused (Rhai: data race); a condition must not use the drive";
    match candidates.split_first() {
        Some((first, others)) => {
            let mut d =
                Diagnostic::at(&first.span, message, "its condition uses the drive").with_help(help(first));
            for other in others {
                d = d.also_at(&other.span, "or this one");
            }
            d
        }
        None => Diagnostic::unlocated(source.path(), message).with_help(help_text("the object")),
    }
}

fn waits(calls: &[LiteralCall]) -> impl Iterator<Item = &LiteralCall> {
    calls.iter().filter(|c| c.name == "wait_until" && c.method)
}

fn help(wait: &LiteralCall) -> String {
    match wait.args.first() {
        Some((Arg::Text(object), _)) => help_text(&format!("`{object}`")),
        _ => help_text("the object"),
    }
}

fn help_text(object: &str) -> String {
    format!(
        "the condition is given the value of {object} that wait_until names (`|v| v > 5900.0`); read any other value before the wait, e.g. `let target = d.read(\"speed_setpoint\");` then `|v| v > target - 10.0`, or wait on that object itself"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Span;

    fn found(text: &str) -> Vec<String> {
        conditions_using_the_drive(&Source::new("t.rhai", text))
            .iter()
            .map(|d| d.located())
            .collect()
    }

    #[test]
    fn a_condition_that_uses_the_drive_is_found_where_it_uses_it() {
        let text = "let d = drive();\nd.wait_until(\"speed_actual\", |v| v > d.read(\"speed_setpoint\") - 10.0, \"10 s\");\n";
        assert_eq!(
            found(text),
            ["t.rhai:2:38: a wait_until condition must not use the drive: `d` is used inside the condition"]
        );
        let d = conditions_using_the_drive(&Source::new("t.rhai", text)).remove(0);
        assert!(
            d.help().is_some_and(|h| h.contains("`speed_actual`")),
            "{:?}",
            d.help()
        );
        assert_eq!(d.span().map(Span::written), Some("d"));
    }

    #[test]
    fn other_drives_a_call_of_drive_and_closures_kept_in_variables_are_found_too() {
        let text = "let left = drive(\"left\");\nlet right = drive(\"right\");\n\
                    left.wait_until(\"speed_actual\", |v| v > right.read(\"speed_actual\"), \"1 s\");\n\
                    left.wait_until(\"speed_actual\", |v| v > drive(\"right\").read(\"speed_actual\"), \"1 s\");\n\
                    let ready = |v| v > left.read(\"speed_setpoint\");\n\
                    left.wait_until(\"speed_actual\", ready, \"1 s\");\n";
        let p = found(text);
        assert_eq!(p.len(), 3, "{p:#?}");
        assert!(p[0].starts_with("t.rhai:3:41: a wait_until condition must not use the drive: `right`"));
        assert!(p[1].starts_with("t.rhai:4:41: a wait_until condition must not call the drive"));
        assert!(p[2].starts_with("t.rhai:5:21: a wait_until condition must not use the drive: `left`"));
    }

    #[test]
    fn a_condition_that_judges_its_value_is_fine() {
        assert!(found(
            "let d = drive();\nlet target = d.read(\"speed_setpoint\");\nd.wait_until(\"speed_actual\", |v| v > target - 10.0, \"10 s\");\n\
             fn finally(d) { d.wait_until(\"speed_actual\", |v| v.abs() < 5.0, \"30 s\"); }\n"
        )
        .is_empty());
    }

    #[test]
    fn a_data_race_the_text_does_not_show_is_placed_at_the_waits_it_can_come_from() {
        let text = "let d = drive();\nd.wait_until(\"speed_actual\", |v| v > 1.0, \"1 s\");\n\
                    let conditions = [|v| v > d.read(\"speed_setpoint\")];\n\
                    d.wait_until(\"speed_actual\", conditions[0], \"1 s\");\n";
        let d = data_race(&Source::new("t.rhai", text));
        assert!(
            d.located()
                .starts_with("t.rhai:4:3: the wait_until condition holds the drive"),
            "{}",
            d.located()
        );
    }
}
