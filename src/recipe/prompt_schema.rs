//! The JSON Schema of the operator steps (`instruct`, `confirm`, `enter_value`,
//! `enter_text`), for the recipe schema to list with the other steps. Only the schema; the
//! steps are read by the loader.

use super::schema::any_case;
use super::schema_dynamics::last_pass_schema;
use crate::dictionary::Unit;
use crate::session::UNIT_FIELDS;
use serde_json::{json, Value};

/// Each operator step as (key, schema of its value, what it does).
pub(super) fn prompt_steps() -> Vec<(&'static str, Value, &'static str)> {
    let units: Vec<&str> = Unit::symbols().chain(Unit::MEASURED.map(Unit::symbol)).collect();
    // A change of a typed value: in % or in any unit (`check` holds it to the value's own).
    let changes = std::iter::once("%".to_string())
        .chain(units.iter().map(|u| any_case(u)))
        .collect::<Vec<_>>()
        .join("|");
    vec![
        (
            "instruct",
            prompt(json!({})),
            "An instruction the operator reads and acknowledges with Enter: `instruct: Fit the balancing adapter and close the guard`",
        ),
        (
            "confirm",
            prompt(json!({})),
            "A yes/no question that is a check: \"no\" fails it (exit code 1); Enter alone never confirms: `confirm: Is the spindle running quietly?`",
        ),
        (
            "enter_value",
            prompt(json!({
                "unit": { "type": "string", "enum": units },
                "at_least": { "$ref": "#/$defs/value_any" }, "at_most": { "$ref": "#/$defs/value_any" },
                "between": { "type": "array", "items": { "$ref": "#/$defs/value_any" }, "minItems": 2, "maxItems": 2 },
                "compared_with_last_pass": last_pass_schema(&changes)
            })),
            "A measured value the operator types in, with its unit and limits, then a check: `enter_value: { prompt: Vibration on the hand-held meter, unit: mm/s, at_most: 2.8 mm/s }`; a typo is asked again",
        ),
        (
            "enter_text",
            prompt(json!({
                "pattern": { "type": "string", "description": "a regular expression the whole answer must match" },
                "sets": { "type": "string", "enum": UNIT_FIELDS }
            })),
            "A text the operator types or scans, optionally matching a `pattern`; `sets: serial` (part, operator, station) makes it the unit's identity in the reports",
        ),
    ]
}

/// An operator step: the question alone, or `prompt:` with `timeout` and `extra` keys.
fn prompt(extra: Value) -> Value {
    let mut props = json!({ "prompt": { "type": "string" }, "timeout": { "$ref": "#/$defs/duration",
        "description": "a duration (`5 min`): how long the operator has to answer before the step fails (default: no limit, the step waits as long as it takes)" } });
    if let (Some(p), Some(e)) = (props.as_object_mut(), extra.as_object()) {
        p.extend(e.clone());
    }
    json!({ "oneOf": [
        { "type": "string" },
        { "type": "object", "properties": props, "required": ["prompt"], "additionalProperties": false }
    ] })
}
