//! Rhai's errors (syntax, and run-time errors including those raised inside drive calls)
//! as the one diagnostic type: the script's file, line and column, the word there
//! underlined, and the functions the error passed through. It must not decide what an
//! error means for the run (that is the runner's job).

use super::drive_in_condition::data_race;
use super::literal_calls::LineIndex;
use crate::diag::{Diagnostic, Source, Span};
use rhai::{EvalAltResult, ParseError, Position};
use std::sync::Arc;

/// The span of the word (a name, a string literal, an operator) at a Rhai position.
pub fn span_at(source: &Arc<Source>, pos: Position) -> Option<Span> {
    let (line, column) = (pos.line()?, pos.position().unwrap_or(1));
    let text = source.text();
    let index = LineIndex::new(text);
    let offset = index.offset(text, line, column)?;
    let rest = &text[offset..];
    let len = match rest.chars().next() {
        Some(q @ ('"' | '`')) => rest[1..].find(q).map_or(1, |end| end + 2),
        Some(c) if c.is_alphanumeric() || c == '_' => rest
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(rest.len()),
        Some(c) => c.len_utf8(),
        None => 0,
    };
    Some(Span::new(source, offset, len, line, column))
}

fn at(source: &Arc<Source>, pos: Position, message: String, label: &str) -> Diagnostic {
    match span_at(source, pos) {
        Some(span) => Diagnostic::at(&span, message, label),
        None => Diagnostic::unlocated(source.path(), message),
    }
}

/// A syntax error.
pub fn parse_error(source: &Arc<Source>, e: &ParseError) -> Diagnostic {
    let message = format!("syntax error: {}", e.err_type());
    let help = match e.err_type().to_string() {
        t if t.contains("eval") => Some("`eval` is disabled in drivescript's sandbox".to_string()),
        t if t.contains("import") || t.contains("export") => Some(
            "modules are disabled in drivescript's sandbox; write the functions in the script".to_string(),
        ),
        _ => None,
    };
    at(source, e.position(), message, "here").with_optional_help(help)
}

/// A run-time error, at the innermost place it happened; the calls of script functions
/// it passed through are named in the help.
pub fn eval_error(source: &Arc<Source>, e: &EvalAltResult) -> Diagnostic {
    let mut inner = e;
    let mut through = Vec::new();
    while let EvalAltResult::ErrorInFunctionCall(name, _, next, pos) = inner {
        through.push((name.clone(), *pos));
        inner = next;
    }
    let message = match inner {
        EvalAltResult::ErrorRuntime(v, _) => v.to_string(),
        other => {
            let text = other.to_string();
            let place = format!(" ({})", other.position());
            text.strip_suffix(&place).unwrap_or(&text).to_string()
        }
    };
    let mut d = match inner {
        // Rhai gives this refusal no place: the text shows where it comes from.
        EvalAltResult::ErrorDataRace(what, pos)
            if what.contains("'wait_until'") && span_at(source, *pos).is_none() =>
        {
            data_race(source)
        }
        _ => at(source, inner.position(), message, "raised here"),
    };
    if let EvalAltResult::ErrorDataRace(what, _) = inner {
        if !what.contains("'wait_until'") {
            d = d.with_help(
            "a value is used twice at once; a wait_until condition, for example, must not use the drive: it judges the value it is given",
        );
        }
    }
    if let EvalAltResult::ErrorFunctionNotFound(..) = inner {
        d = d.with_help(
            "scripts have no file, process or module access; the drive API is listed in the README (Rhai scripts)",
        );
    }
    for (name, pos) in through {
        if let Some(span) = span_at(source, pos) {
            // Rhai names a closure `anon$…`.
            let called = match name.starts_with("anon$") {
                true => "in a closure, called here".to_string(),
                false => format!("in `{name}`, called here"),
            };
            d = d.also_at(&span, called);
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_position_underlines_the_word_there() {
        let source = Source::new("s.rhai", "let d = drive();\nd.read(\"speed\");\n");
        let span = span_at(&source, Position::new(2, 3)).expect("a span");
        assert_eq!((span.written(), span.line(), span.column()), ("read", 2, 3));
        let span = span_at(&source, Position::new(2, 8)).expect("a span");
        assert_eq!(span.written(), "\"speed\"");
        assert!(span_at(&source, Position::NONE).is_none());
    }

    #[test]
    fn rhais_data_race_in_wait_until_is_placed_at_the_wait() {
        let source = Source::new(
            "s.rhai",
            "let d = drive();\nlet c = [|v| v > d.read(\"x\")];\nd.wait_until(\"speed_actual\", c[0], \"1 s\");\n",
        );
        let race =
            EvalAltResult::ErrorDataRace("argument #2 of function 'wait_until'".into(), Position::NONE);
        let d = eval_error(&source, &race);
        assert!(
            d.located()
                .starts_with("s.rhai:3:3: the wait_until condition holds the drive"),
            "{}",
            d.located()
        );
        // Another data race keeps Rhai's words and gets the general help.
        let other =
            EvalAltResult::ErrorDataRace("argument #1 of function 'push'".into(), Position::new(2, 9));
        let d = eval_error(&source, &other);
        assert!(
            d.located().starts_with("s.rhai:2:9: Data race detected"),
            "{}",
            d.located()
        );
        assert!(d.help().is_some_and(|h| h.contains("used twice at once")));
    }
}
