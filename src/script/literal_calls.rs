//! The calls of a script whose arguments are written as literals (`d.read("speed_actual")`,
//! `d.set("speed_setpoint", 6000.0, "rpm")`, `dwell("2 s")`), found by a small scan of
//! the text with each literal's place, so `check` can test names, units, states and
//! durations against the dictionary before anything runs. It only finds; it must not judge
//! what it finds (that is `static_check`'s job), and it never runs the script.

use crate::diag::{Source, Span};
use std::sync::Arc;

/// One argument of a call, as written.
#[derive(Debug, Clone)]
pub enum Arg {
    Text(String),
    Number(f64),
    /// `["speed_actual", "current_actual"]`: a list of text literals only.
    TextList(Vec<(String, Span)>),
    /// `|v| v > limit`: the names its body uses (variables and functions, not methods or
    /// its own parameters), each where it is written.
    Closure(Vec<(String, Span)>),
    /// `#{ below: "80 °C", for: "2 s" }`: each key with its value (text, a number, or
    /// [`Arg::Other`]) and the value's place.
    Map(Vec<(String, Arg, Span)>),
    /// Anything else (a variable, an expression).
    Other,
}

/// A call with its arguments; `method` for `x.name(...)`.
#[derive(Debug, Clone)]
pub struct LiteralCall {
    pub name: String,
    pub method: bool,
    pub span: Span,
    pub args: Vec<(Arg, Span)>,
    /// `d.state() == "fault"`: the text a call's result is compared with (`==`, `!=`).
    pub compared_with: Option<(String, Span)>,
    /// `d` of `d.read(…)`: the variable a method is called on.
    pub receiver: Option<String>,
    /// `d` of `let d = drive();`: the variable the call's result is given to.
    pub assigned_to: Option<String>,
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Ident(String),
    Text(String),
    Number(f64),
    Punct(char),
}

#[derive(Debug, Clone)]
struct Token {
    kind: Kind,
    offset: usize,
    len: usize,
}

/// Every call in `source` (outside comments and strings), in text order.
pub fn literal_calls(source: &Arc<Source>) -> Vec<LiteralCall> {
    let tokens = tokens(source.text());
    let lines = LineIndex::new(source.text());
    let span = |offset: usize, len: usize| lines.span(source, offset, len);
    let mut calls = Vec::new();
    for i in 0..tokens.len() {
        let Kind::Ident(name) = &tokens[i].kind else {
            continue;
        };
        if tokens.get(i + 1).map(|t| &t.kind) != Some(&Kind::Punct('(')) {
            continue;
        }
        let method = i > 0 && tokens[i - 1].kind == Kind::Punct('.');
        let raw = arguments(&tokens[i + 2..]);
        let args = raw
            .into_iter()
            .map(|arg| {
                let first = arg.first().map_or(tokens[i].offset, |t| t.offset);
                let end = arg.last().map_or(first, |t| t.offset + t.len);
                (classify(arg, &span), span(first, end - first))
            })
            .collect();
        let compared_with = comparison(&tokens[i + 2..]).map(|t| (t.0.clone(), span(t.1, t.2)));
        let ident_at = |k: Option<usize>| match k.and_then(|k| tokens.get(k)).map(|t| &t.kind) {
            Some(Kind::Ident(v)) => Some(v.clone()),
            _ => None,
        };
        let receiver = method.then(|| ident_at(i.checked_sub(2))).flatten();
        let assigned = i >= 2 && tokens[i - 1].kind == Kind::Punct('=');
        let assigned_to = assigned.then(|| ident_at(i.checked_sub(2))).flatten();
        calls.push(LiteralCall {
            name: name.clone(),
            method,
            span: span(tokens[i].offset, tokens[i].len),
            args,
            compared_with,
            receiver,
            assigned_to,
        });
    }
    calls
}

/// The closures a script gives to a variable (`let ready = |v| v > limit;`): the variable,
/// and the names the closure's body uses as [`Arg::Closure`] has them.
pub fn assigned_closures(source: &Arc<Source>) -> Vec<(String, Vec<(String, Span)>)> {
    let tokens = tokens(source.text());
    let lines = LineIndex::new(source.text());
    let span = |offset: usize, len: usize| lines.span(source, offset, len);
    let mut out = Vec::new();
    for i in 2..tokens.len() {
        let (Kind::Ident(name), Kind::Punct('='), Kind::Punct('|')) =
            (&tokens[i - 2].kind, &tokens[i - 1].kind, &tokens[i].kind)
        else {
            continue;
        };
        // The closure ends at the `;` (or the bracket that closes around it).
        let mut depth = 0usize;
        let mut end = tokens.len();
        for (k, t) in tokens.iter().enumerate().skip(i) {
            match t.kind {
                Kind::Punct('(' | '[' | '{') => depth += 1,
                Kind::Punct(')' | ']' | '}') if depth == 0 => {
                    end = k;
                    break;
                }
                Kind::Punct(')' | ']' | '}') => depth -= 1,
                Kind::Punct(';') if depth == 0 => {
                    end = k;
                    break;
                }
                _ => {}
            }
        }
        if let Some(words) = closure_words(&tokens[i..end], &span) {
            out.push((name.clone(), words));
        }
    }
    out
}

/// The names a closure's body uses (not methods, not its parameters); `None` when `arg`
/// is not a closure.
fn closure_words(arg: &[Token], span: &dyn Fn(usize, usize) -> Span) -> Option<Vec<(String, Span)>> {
    if arg.first()?.kind != Kind::Punct('|') {
        return None;
    }
    let close = 1 + arg[1..].iter().position(|t| t.kind == Kind::Punct('|'))?;
    let params: Vec<&str> = arg[1..close]
        .iter()
        .filter_map(|t| match &t.kind {
            Kind::Ident(p) => Some(p.as_str()),
            _ => None,
        })
        .collect();
    let body = &arg[close + 1..];
    let words = body
        .iter()
        .enumerate()
        .filter_map(|(k, t)| match &t.kind {
            Kind::Ident(w)
                if !params.contains(&w.as_str()) && (k == 0 || body[k - 1].kind != Kind::Punct('.')) =>
            {
                Some((w.clone(), span(t.offset, t.len)))
            }
            _ => None,
        })
        .collect();
    Some(words)
}

/// After a call without arguments (`tokens` start after its `(`): the text literal it is
/// compared with, with its offset and length.
fn comparison(tokens: &[Token]) -> Option<(&String, usize, usize)> {
    match tokens {
        [Token {
            kind: Kind::Punct(')'),
            ..
        }, Token {
            kind: Kind::Punct('=' | '!'),
            ..
        }, Token {
            kind: Kind::Punct('='),
            ..
        }, Token {
            kind: Kind::Text(t),
            offset,
            len,
        }, ..] => Some((t, *offset, *len)),
        _ => None,
    }
}

/// The tokens of each argument up to the closing parenthesis.
fn arguments(tokens: &[Token]) -> Vec<&[Token]> {
    let mut args = Vec::new();
    let mut depth = 0usize;
    let mut start = 0;
    for (i, t) in tokens.iter().enumerate() {
        match t.kind {
            Kind::Punct('(' | '[' | '{') => depth += 1,
            Kind::Punct(')' | ']' | '}') if depth == 0 => {
                if i > start {
                    args.push(&tokens[start..i]);
                }
                return args;
            }
            Kind::Punct(')' | ']' | '}') => depth -= 1,
            Kind::Punct(',') if depth == 0 => {
                args.push(&tokens[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    args
}

fn classify(arg: &[Token], span: &dyn Fn(usize, usize) -> Span) -> Arg {
    if let Some(words) = closure_words(arg, span) {
        return Arg::Closure(words);
    }
    match arg {
        [Token {
            kind: Kind::Text(t), ..
        }] => Arg::Text(t.clone()),
        [Token {
            kind: Kind::Number(n),
            ..
        }] => Arg::Number(*n),
        [Token {
            kind: Kind::Punct('-'),
            ..
        }, Token {
            kind: Kind::Number(n),
            ..
        }] => Arg::Number(-n),
        [Token {
            kind: Kind::Punct('['),
            ..
        }, inner @ .., Token {
            kind: Kind::Punct(']'),
            ..
        }] => {
            let mut items = Vec::new();
            for (k, t) in inner.iter().enumerate() {
                match (&t.kind, k % 2) {
                    (Kind::Text(s), 0) => items.push((s.clone(), span(t.offset, t.len))),
                    (Kind::Punct(','), 1) => {}
                    _ => return Arg::Other,
                }
            }
            Arg::TextList(items)
        }
        [Token {
            kind: Kind::Punct('#'),
            ..
        }, Token {
            kind: Kind::Punct('{'),
            ..
        }, inner @ .., Token {
            kind: Kind::Punct('}'),
            ..
        }] => map_entries(inner, span).map_or(Arg::Other, Arg::Map),
        _ => Arg::Other,
    }
}

/// The entries of an object map `key: value, ...` (between its braces); `None` when it is
/// not a plain list of keys and values.
fn map_entries(inner: &[Token], span: &dyn Fn(usize, usize) -> Span) -> Option<Vec<(String, Arg, Span)>> {
    let mut out = Vec::new();
    let mut rest = inner;
    while !rest.is_empty() {
        let key = match &rest.first()?.kind {
            Kind::Ident(k) | Kind::Text(k) => k.clone(),
            _ => return None,
        };
        if rest.get(1)?.kind != Kind::Punct(':') {
            return None;
        }
        let value = &rest[2..];
        let end = arguments_end(value);
        let arg = &value[..end];
        let (first, last) = (arg.first()?, arg.last()?);
        let place = span(first.offset, last.offset + last.len - first.offset);
        let classified = match classify(arg, span) {
            a @ (Arg::Text(_) | Arg::Number(_)) => a,
            _ => Arg::Other,
        };
        out.push((key, classified, place));
        rest = value.get(end + 1..).unwrap_or_default();
    }
    Some(out)
}

/// Where the first argument of `tokens` ends: at a `,` outside brackets, or the end.
fn arguments_end(tokens: &[Token]) -> usize {
    let mut depth = 0usize;
    for (i, t) in tokens.iter().enumerate() {
        match t.kind {
            Kind::Punct('(' | '[' | '{') => depth += 1,
            Kind::Punct(')' | ']' | '}') => depth = depth.saturating_sub(1),
            Kind::Punct(',') if depth == 0 => return i,
            _ => {}
        }
    }
    tokens.len()
}

fn tokens(text: &str) -> Vec<Token> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let start = i;
        if c.is_ascii_whitespace() {
            i += 1;
        } else if text[i..].starts_with("//") {
            i = text[i..].find('\n').map_or(bytes.len(), |n| i + n);
        } else if text[i..].starts_with("/*") {
            i = skip_block_comment(bytes, i);
        } else if c == b'"' || c == b'`' || c == b'\'' {
            let (end, value) = string(text, i, c);
            i = end;
            if c == b'"' {
                if let Some(v) = value {
                    out.push(Token {
                        kind: Kind::Text(v),
                        offset: start,
                        len: i - start,
                    });
                    continue;
                }
            }
            out.push(Token {
                kind: Kind::Punct('?'),
                offset: start,
                len: i - start,
            });
        } else if c.is_ascii_digit() {
            while i < bytes.len()
                && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_' || bytes[i] == b'.')
            {
                // `1..10` is a range, not a number with two points.
                if bytes[i] == b'.' && bytes.get(i + 1) == Some(&b'.') {
                    break;
                }
                i += 1;
            }
            let written: String = text[start..i].chars().filter(|&c| c != '_').collect();
            let kind = match written.parse::<f64>() {
                Ok(n) => Kind::Number(n),
                Err(_) => Kind::Punct('?'),
            };
            out.push(Token {
                kind,
                offset: start,
                len: i - start,
            });
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            out.push(Token {
                kind: Kind::Ident(text[start..i].to_string()),
                offset: start,
                len: i - start,
            });
        } else {
            let ch = text[i..].chars().next().unwrap_or('?');
            i += ch.len_utf8();
            out.push(Token {
                kind: Kind::Punct(ch),
                offset: start,
                len: i - start,
            });
        }
    }
    out
}

fn skip_block_comment(bytes: &[u8], mut i: usize) -> usize {
    let mut depth = 0usize;
    while i < bytes.len() {
        if bytes[i..].starts_with(b"/*") {
            depth += 1;
            i += 2;
        } else if bytes[i..].starts_with(b"*/") {
            depth -= 1;
            i += 2;
            if depth == 0 {
                return i;
            }
        } else {
            i += 1;
        }
    }
    i
}

/// The end of the string starting at `start` (quote `q`), and its value when it has only
/// the simple escapes (a value with `${…}` or unknown escapes is not a literal).
fn string(text: &str, start: usize, q: u8) -> (usize, Option<String>) {
    let mut value = String::new();
    let mut plain = true;
    let mut chars = text[start + 1..].char_indices();
    while let Some((k, c)) = chars.next() {
        let at = start + 1 + k;
        if c as u32 == q as u32 {
            return (at + 1, plain.then_some(value));
        }
        match c {
            '\\' => match chars.next() {
                Some((_, 'n')) => value.push('\n'),
                Some((_, 't')) => value.push('\t'),
                Some((_, e @ ('"' | '\\' | '\''))) => value.push(e),
                Some(_) => plain = false,
                None => break,
            },
            '$' if q == b'`' => plain = false,
            _ => value.push(c),
        }
    }
    (text.len(), None)
}

/// Byte offsets of line starts, for 1-based lines and character columns.
pub struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    pub fn new(text: &str) -> Self {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { starts }
    }

    /// The span of `len` bytes at `offset`.
    pub fn span(&self, source: &Arc<Source>, offset: usize, len: usize) -> Span {
        let line = self.starts.partition_point(|&s| s <= offset).max(1);
        let line_start = self.starts[line - 1];
        let column = source
            .text()
            .get(line_start..offset)
            .map_or(1, |t| t.chars().count() + 1);
        Span::new(source, offset, len, line, column)
    }

    /// The byte offset of a 1-based line and character column (as Rhai reports places).
    pub fn offset(&self, text: &str, line: usize, column: usize) -> Option<usize> {
        let start = *self.starts.get(line.checked_sub(1)?)?;
        let rest = text.get(start..)?;
        let skip = column.saturating_sub(1);
        rest.char_indices()
            .nth(skip)
            .map(|(i, _)| start + i)
            .or_else(|| (rest.chars().count() == skip).then_some(start + rest.len()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_calls_with_their_literal_arguments_and_places() {
        let text = "// d.read(\"in_a_comment\")\nlet d = drive();\nlet v = d.read(\"speed_actual\");\n\
                    d.set(\"speed_setpoint\", 6_000.0, \"rpm\"); dwell(`2 s`);\n\
                    let s = d.sample([\"speed_actual\", \"current_actual\"], \"100 ms\", x);\n\
                    d.wait_until(\"speed_actual\", |v| v > -5.0, \"30 s\");\n";
        let source = Source::new("t.rhai", text);
        let calls = literal_calls(&source);
        let names: Vec<&str> = calls.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["drive", "read", "set", "dwell", "sample", "wait_until"]);
        let read = &calls[1];
        assert!(read.method);
        assert!(matches!(&read.args[0].0, Arg::Text(t) if t == "speed_actual"));
        assert_eq!((read.args[0].1.line(), read.args[0].1.column()), (3, 16));
        assert_eq!(read.args[0].1.written(), "\"speed_actual\"");
        assert!(matches!(calls[2].args[1].0, Arg::Number(n) if n == 6000.0));
        // A template string is not a literal.
        assert!(matches!(calls[3].args[0].0, Arg::Other));
        match &calls[4].args[0].0 {
            Arg::TextList(items) => {
                assert_eq!(items.len(), 2);
                assert_eq!(items[1].0, "current_actual");
                assert_eq!(items[1].1.line(), 5);
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(calls[4].args[2].0, Arg::Other));
        assert_eq!(calls[5].args.len(), 3);
        assert!(matches!(&calls[5].args[2].0, Arg::Text(t) if t == "30 s"));
        let source = Source::new(
            "t.rhai",
            "if d.state() == \"fault\" || d.state() != \"x\" || d.state() < \"y\" {}",
        );
        let compared: Vec<Option<String>> = literal_calls(&source)
            .into_iter()
            .map(|c| c.compared_with.map(|(t, _)| t))
            .collect();
        assert_eq!(compared, [Some("fault".into()), Some("x".into()), None]);
    }

    #[test]
    fn an_object_map_of_literals_keeps_each_key_with_its_value_and_place() {
        let text =
            "d.watch(\"motor_temperature\", #{ below: \"80 °C\", \"for\": \"2 s\", every: x, n: -3 });\n\
                    d.watch(\"speed_actual\", #{ below: f(1, 2) });\n";
        let calls = literal_calls(&Source::new("t.rhai", text));
        let Arg::Map(entries) = &calls[0].args[1].0 else {
            panic!("{:?}", calls[0].args[1]);
        };
        let keys: Vec<&str> = entries.iter().map(|(k, _, _)| k.as_str()).collect();
        assert_eq!(keys, ["below", "for", "every", "n"]);
        assert!(matches!(&entries[0].1, Arg::Text(t) if t == "80 °C"));
        assert_eq!(entries[1].2.written(), "\"2 s\"");
        assert!(matches!(entries[2].1, Arg::Other));
        assert!(matches!(entries[3].1, Arg::Number(n) if n == -3.0));
        // A call inside a value is left to the run, but the map still parses.
        let Arg::Map(entries) = &calls[1].args[1].0 else {
            panic!("{:?}", calls[1].args[1]);
        };
        assert!(matches!(entries[0].1, Arg::Other));
    }

    #[test]
    fn a_closure_argument_names_what_its_body_uses() {
        let text = "let d = drive();\nlet limit = 5.0;\nd.wait_until(\"speed_actual\", |v| v > limit + d.read(\"x\"), \"1 s\");\n\
                    let ready = || drive().state() == \"fault\";\n";
        let source = Source::new("t.rhai", text);
        let calls = literal_calls(&source);
        assert_eq!(calls[0].assigned_to.as_deref(), Some("d"));
        let wait = calls.iter().find(|c| c.name == "wait_until").expect("wait_until");
        assert_eq!(wait.receiver.as_deref(), Some("d"));
        match &wait.args[1].0 {
            Arg::Closure(words) => {
                let names: Vec<&str> = words.iter().map(|(w, _)| w.as_str()).collect();
                assert_eq!(names, ["limit", "d"]);
                assert_eq!((words[1].1.line(), words[1].1.column()), (3, 46));
            }
            other => panic!("{other:?}"),
        }
        let assigned = assigned_closures(&source);
        assert_eq!(assigned.len(), 1);
        assert_eq!(assigned[0].0, "ready");
        let names: Vec<&str> = assigned[0].1.iter().map(|(w, _)| w.as_str()).collect();
        assert_eq!(names, ["drive"]);
    }

    #[test]
    fn any_text_is_scanned_without_panicking() {
        for text in [
            "\"unterminated",
            "f(",
            "f(\"a\\",
            "/* open",
            "x.y(1..3)",
            "é(\"ü\")",
            "1e",
            "`${`",
        ] {
            let source = Source::new("t.rhai", text);
            let _ = literal_calls(&source);
            let _ = assigned_closures(&source);
        }
    }

    proptest::proptest! {
        #[test]
        fn any_text_scans_without_panicking_and_every_place_is_inside_it(text in "\\PC{0,200}") {
            let source = Source::new("t.rhai", text.as_str());
            let closures = assigned_closures(&source);
            let closure_spans = closures.iter().flat_map(|(_, words)| words.iter().map(|(_, s)| s.clone()));
            for span in closure_spans {
                proptest::prop_assert!(span.offset() + span.len() <= text.len());
                proptest::prop_assert!(text.is_char_boundary(span.offset()));
            }
            for call in literal_calls(&source) {
                for span in std::iter::once(&call.span).chain(call.args.iter().map(|(_, s)| s)) {
                    proptest::prop_assert!(span.offset() + span.len() <= text.len());
                    proptest::prop_assert!(text.is_char_boundary(span.offset()));
                    proptest::prop_assert!(span.line() >= 1);
                }
            }
        }

        #[test]
        fn call_like_text_scans_without_panicking(text in "[a-z.(),|=;{}\\[\\]\"`'/*\\\\ 0-9_-]{0,120}") {
            let source = Source::new("t.rhai", text.as_str());
            let _ = literal_calls(&source);
            let _ = assigned_closures(&source);
        }
    }

    #[test]
    fn rhai_places_map_to_offsets() {
        let text = "ab\nçd(x)\n";
        let index = LineIndex::new(text);
        assert_eq!(index.offset(text, 2, 2), Some(5));
        assert_eq!(index.offset(text, 1, 1), Some(0));
        assert_eq!(index.offset(text, 9, 1), None);
    }
}
