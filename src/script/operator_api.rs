//! The operator steps as script functions, as a recipe has them: `instruct(text)`,
//! `confirm(text)` (true for yes; a "no" fails its check), `enter_value(text, #{ unit,
//! at_least, at_most, compared_with_last_pass })` (the number in the unit; compared with the
//! unit's last passed run as `expect_compared_with_last_pass` is) and `enter_text(text, #{
//! pattern, sets })` (the text), each with optional `name` and `timeout` in its map. Builds the prompt and
//! hands it to the session thread; also finds the prompts a script writes with a literal
//! question, for a run without a terminal. It must not ask anyone itself.

use super::bridge::{Bridge, RhaiResult};
use super::exchange::{Answer, Call};
use super::literal_calls::{Arg, LiteralCall};
use crate::diag::Source;
use crate::dictionary::{Quantity, Unit};
use crate::session::{
    default_answer_name, Accepted, Limits, Pattern, Prompt, PromptKind, StepOrigin, UNIT_FIELDS,
};
use rhai::{Dynamic, Engine, EvalAltResult, Map, NativeCallContext, Position};
use std::sync::Arc;

/// The operator functions, by the kind of prompt each asks.
pub const OPERATOR_FUNCTIONS: [&str; 4] = ["instruct", "confirm", "enter_value", "enter_text"];

fn error(text: impl Into<String>) -> Box<EvalAltResult> {
    Box::new(EvalAltResult::ErrorRuntime(text.into().into(), Position::NONE))
}

/// The map's `key` as text (a number is written as it reads).
fn text_of(map: &Map, key: &str) -> Option<String> {
    map.get(key).map(|v| v.to_string())
}

/// A limit in the prompt's unit: a number, or text with a unit (`"2.8 mm/s"`).
fn limit(map: &Map, key: &str, unit: Option<Unit>) -> RhaiResult<Option<f64>> {
    let Some(v) = map.get(key) else { return Ok(None) };
    if let Ok(f) = v.as_float() {
        return Ok(Some(f));
    }
    if let Ok(i) = v.as_int() {
        return Ok(Some(i as f64));
    }
    let text = v.to_string();
    let q = Quantity::parse_measured(&text).map_err(|e| error(format!("{key}: {e}")))?;
    match (q.unit, unit) {
        (None, _) => Ok(Some(q.value)),
        (Some(from), Some(to)) => from.convert(q.value, to).map(Some).ok_or_else(|| {
            error(format!(
                "{key}: {from} is not a unit of {} ({to})",
                to.dimension().name()
            ))
        }),
        (Some(from), None) => Err(error(format!(
            "{key}: `{text}` has a unit but the value has none; give `unit: \"{from}\"`"
        ))),
    }
}

/// The prompt of the function `word` asking `text` with the settings `map`.
fn prompt_of(word: &str, text: &str, map: &Map) -> RhaiResult<Prompt> {
    let allowed: &[&str] = match word {
        "enter_value" => &[
            "name",
            "timeout",
            "unit",
            "at_least",
            "at_most",
            "compared_with_last_pass",
        ],
        "enter_text" => &["name", "timeout", "pattern", "sets"],
        _ => &["name", "timeout"],
    };
    if let Some(k) = map.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(error(format!(
            "{word} has no setting `{k}`; its settings are: {}",
            allowed.join(", ")
        )));
    }
    if text.trim().is_empty() {
        return Err(error(format!("{word} needs a question or instruction")));
    }
    let kind = match word {
        "instruct" => PromptKind::Instruction,
        "confirm" => PromptKind::Confirm,
        "enter_value" => {
            let unit = match text_of(map, "unit") {
                Some(u) => Some(Unit::parse_measured(&u).map_err(|e| error(e.to_string()))?),
                None => None,
            };
            let last_pass = match map.get("compared_with_last_pass") {
                Some(v) => match v.read_lock::<Map>() {
                    Some(compared) => Some(super::last_pass_api::last_pass(word, &compared)?),
                    None => {
                        return Err(error(
                            "enter_value: `compared_with_last_pass` is a map: #{ at_most: \"10 %\", without_history: \"pass\" }",
                        ))
                    }
                },
                None => None,
            };
            PromptKind::Value {
                unit,
                limits: Limits::new(limit(map, "at_least", unit)?, limit(map, "at_most", unit)?),
                last_pass,
            }
        }
        _ => {
            let pattern = match text_of(map, "pattern") {
                Some(p) => Some(Pattern::new(&p).map_err(|e| error(format!("`{p}` is not a pattern: {e}")))?),
                None => None,
            };
            let sets =
                match text_of(map, "sets") {
                    Some(s) => Some(UNIT_FIELDS.into_iter().find(|f| *f == s).ok_or_else(|| {
                        error(format!("sets: `{s}` is none of {}", UNIT_FIELDS.join(", ")))
                    })?),
                    None => None,
                };
            PromptKind::Text { pattern, sets }
        }
    };
    let sets = match &kind {
        PromptKind::Text { sets, .. } => *sets,
        _ => None,
    };
    let timeout = match text_of(map, "timeout") {
        Some(t) => Some(super::resolve::duration(&t).map_err(|r| error(r.sentence()))?),
        None => None,
    };
    Ok(Prompt {
        name: text_of(map, "name").unwrap_or_else(|| default_answer_name(text, sets)),
        text: text.to_string(),
        kind,
        timeout,
    })
}

fn ask(b: &Bridge, pos: Position, word: &str, text: &str, map: &Map) -> RhaiResult<Accepted> {
    let prompt = prompt_of(word, text, map)?;
    let label = prompt.to_string();
    match b.call(pos, Call::Ask(Box::new(prompt)), label)? {
        Answer::Asked(accepted) => Ok(accepted),
        _ => Err(super::drive_api::unexpected_answer()),
    }
}

/// Adds the operator functions to `engine`, every call going through `bridge`.
pub fn register_operator(engine: &mut Engine, bridge: &Arc<Bridge>) {
    for word in OPERATOR_FUNCTIONS {
        let b = bridge.clone();
        let with_map = move |ctx: NativeCallContext, text: &str, map: Map| -> RhaiResult<Dynamic> {
            let a = ask(&b, ctx.call_position(), word, text, &map)?;
            Ok(result_of(word, a))
        };
        let b = bridge.clone();
        let alone = move |ctx: NativeCallContext, text: &str| -> RhaiResult<Dynamic> {
            let a = ask(&b, ctx.call_position(), word, text, &Map::new())?;
            Ok(result_of(word, a))
        };
        engine.register_fn(word, alone);
        engine.register_fn(word, with_map);
    }
}

/// What the function returns: nothing, yes as true, the number, the text.
fn result_of(word: &str, a: Accepted) -> Dynamic {
    match word {
        "instruct" => Dynamic::UNIT,
        "confirm" => Dynamic::from_bool(a.passed),
        "enter_value" => Dynamic::from_float(a.number.unwrap_or(f64::NAN)),
        _ => Dynamic::from(a.text),
    }
}

/// The operator calls in `calls` written with a literal question, each with the answer
/// name it will have (the map's literal `name:` or `sets:`, else from the question) and
/// its place.
pub fn literal_prompts(calls: &[LiteralCall], source: &Source) -> Vec<(Prompt, StepOrigin)> {
    calls
        .iter()
        .filter(|c| !c.method && OPERATOR_FUNCTIONS.contains(&c.name.as_str()))
        .filter_map(|c| {
            let Some((Arg::Text(text), _)) = c.args.first() else {
                return None;
            };
            let settings = c
                .args
                .get(1)
                .and_then(|(_, span)| source.text().get(span.offset()..span.offset() + span.len()))
                .unwrap_or_default();
            let named = |key: &str| {
                let re = regex::Regex::new(&format!(r#"\b{key}\s*:\s*"([^"]*)""#)).ok()?;
                re.captures(settings).map(|m| m[1].to_string())
            };
            let sets = named("sets");
            let kind = match c.name.as_str() {
                "instruct" => PromptKind::Instruction,
                "confirm" => PromptKind::Confirm,
                "enter_value" => PromptKind::Value {
                    unit: None,
                    limits: Limits::default(),
                    last_pass: None,
                },
                _ => PromptKind::Text {
                    pattern: None,
                    sets: UNIT_FIELDS.into_iter().find(|f| Some(*f) == sets.as_deref()),
                },
            };
            let name = named("name").unwrap_or_else(|| default_answer_name(text, sets.as_deref()));
            let origin = StepOrigin {
                path: source.path().to_string(),
                line: c.span.line(),
                column: c.span.column(),
            };
            Some((
                Prompt {
                    name,
                    text: text.clone(),
                    kind,
                    timeout: None,
                },
                origin,
            ))
        })
        .collect()
}
