//! The parts of the recipe JSON Schema for the checks on how the drive moves: the measures
//! of a step response and the slope as statistics, `slope` as a `wait_until` condition,
//! the `attempts` and `coast_down` steps, `on_failure`, and a check's `compared_with_last_pass`. Their limits are in their own units (s, %, K
//! for a difference of °C, K/min), which `check` validates; the schema gives their shape.

use super::loader::{COAST_DOWN_EVERY, COAST_DOWN_TIMEOUT};
use super::schema::spaced;
use super::schema::{units_of, NUMBER, PARAM};
use crate::dictionary::Dimension;
use crate::session::{DEFAULT_WATCH_EVERY, MIN_WATCH_EVERY};
use serde_json::{json, Map, Value};

/// The statistics besides mean, min, max, ripple and std, each with what it measures.
pub(super) const STEP_STATISTICS: [(&str, &str); 5] = [
    (
        "rise_time",
        "10 % → 90 % of the step the sample step declares: `{ below: 500 ms }`",
    ),
    (
        "overshoot",
        "the furthest excursion beyond the step's target in % of the step: `{ below: 10 % }`",
    ),
    (
        "settling_time",
        "from the window's start until the value stays within the step's band: `{ below: 2 s }`",
    ),
    (
        "steady_state_error",
        "the mean of the window's last tenth minus the step's target: `{ near: 0 rpm, within: 5 rpm }`",
    ),
    (
        "slope",
        "the least-squares slope over the window's last stretch: `{ below: 0.5 K/min, over: 10 min }`",
    ),
];

/// Exactly one statistic: each as its own `required`.
pub(super) fn one_statistic() -> Vec<Value> {
    ["mean", "min", "max", "ripple", "std"]
        .into_iter()
        .chain(STEP_STATISTICS.iter().map(|(s, _)| *s))
        .map(|s| json!({ "required": [s] }))
        .collect()
}

/// A condition's properties and shapes with `slope` (a wait until the value is stable)
/// besides the predicates.
pub(super) fn with_slope(predicates: &Value, one_predicate: &Value) -> (Map<String, Value>, Vec<Value>) {
    let mut props = predicates.as_object().cloned().unwrap_or_default();
    props.insert(
        "slope".into(),
        json!({ "type": "object", "description": "wait until stable: `{ below: 0.5 K/min, over: 10 min }`" }),
    );
    let mut shapes = one_predicate.as_array().cloned().unwrap_or_default();
    shapes.push(json!({ "required": ["slope"], "maxProperties": 1 }));
    (props, shapes)
}

/// The `attempts` and `coast_down` steps: (key, body, what it does).
pub(super) fn dynamics_steps(steps_ref: &Value) -> impl Iterator<Item = (&'static str, Value, String)> {
    [
        (
            "attempts",
            json!({
                "type": "object",
                "properties": { "times": { "type": "integer", "minimum": 1, "maximum": 100 }, "steps": steps_ref, "on_failure": on_failure_schema("in this block"), "watch": watch_schema("this block") },
                "required": ["times", "steps"], "additionalProperties": false
            }),
            "Try nested `steps` up to `times` times until their checks pass (after re-homing, say); every attempt stays in the reports, the verdict is the last one's".to_string(),
        ),
        (
            "coast_down",
            json!({
                "type": "object",
                "properties": {
                    "from": { "$ref": "#/$defs/value_any" }, "below": { "$ref": "#/$defs/value_any" },
                    "expect": {
                        "type": "object",
                        "description": "a condition on the time in seconds: `{ near: 20 s, within: 1 s }`, with `warn:` and `compared_with_last_pass:` beside it",
                        "properties": { "compared_with_last_pass": last_pass_schema(&format!("%|{}", units_of(Dimension::Time))) }
                    },
                    "timeout": { "$ref": "#/$defs/duration" }, "every": { "$ref": "#/$defs/duration" }
                },
                "required": ["from", "below", "expect"], "additionalProperties": false
            }),
            format!("Switch the power stage off and let the spindle coast by design: the time from `from` down past `below` (actual speed, interpolated) is checked by `expect`; polls `every` (default {}) for at most `timeout` (default {})", super::schema::spaced(COAST_DOWN_EVERY), super::schema::spaced(COAST_DOWN_TIMEOUT)),
        ),
    ]
    .into_iter()
}

/// `compared_with_last_pass` on a check (an `expect` condition, a coast-down's `expect`, an
/// `enter_value`); `units` is the regex alternative of the units one end may be written in
/// (`%` and those of a difference of the check's values).
pub(super) fn last_pass_schema(units: &str) -> Value {
    let change = format!(r"^\s*(\+?({NUMBER})\s*({units})?|{PARAM})\s*$");
    let end = |doc: &str| {
        json!({
            "type": ["string", "number"],
            "description": doc,
            "pattern": change,
            "patternErrorMessage": "expected a change in % (of the last pass's value) or in the check's unit, e.g. 10 % or -0.5 A"
        })
    };
    json!({
        "type": "object",
        "description": "compare with the same check in the unit's last passed run of this recipe (same serial, simulated with simulated): how far the value may move, in % of that value or in the check's unit, both ends included; `without_history`: what a run with no earlier pass does. Example: `{ at_most: 10 %, at_least: -5 %, without_history: pass }`",
        "properties": {
            "at_most": end("the largest change allowed: `10 %` (of the last pass's value) or `0.5 A`"),
            "at_least": end("the smallest change allowed (negative: a fall): `-5 %` or `-0.5 A`"),
            "without_history": {
                "enum": ["pass", "fail"],
                "description": "with no earlier passed run of the unit (its first run): `pass` lets it through, `fail` insists on one"
            }
        },
        "required": ["without_history"],
        "anyOf": [ { "required": ["at_most"] }, { "required": ["at_least"] } ],
        "additionalProperties": false
    })
}

/// `on_failure: stop | continue` of the recipe or of a block (`where` it applies).
pub(super) fn on_failure_schema(scope: &str) -> Value {
    json!({ "type": "string", "enum": crate::recipe::OnFailure::WORDS, "default": "continue",
            "description": format!("`stop`: the first failed check {scope} ends the run through the safe stop, the steps after it reported as not run (inside `attempts`, once the attempts are used up); `continue`: the run goes on. `run -x` stops everywhere") })
}

/// `watch:` of the recipe or of a repeat or attempts block (`scope`: what it holds for).
pub(super) fn watch_schema(scope: &str) -> Value {
    json!({
        "type": "object",
        "description": format!("Limits that hold for {scope}, one object each (`motor_temperature: {{ below: 80 °C }}`, `current_actual: {{ below: 12 A, for: 2 s }}`: beyond the limit that long before it counts), read `every` interval (default {}, at least {}) during the steps; one crossed ends the run at once through the safe stop (FAILED)", spaced(DEFAULT_WATCH_EVERY), spaced(MIN_WATCH_EVERY)),
        "properties": { "every": { "$ref": "#/$defs/duration", "default": spaced(DEFAULT_WATCH_EVERY) } },
        "additionalProperties": { "type": "object" }
    })
}
