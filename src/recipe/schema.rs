//! The JSON Schema of recipe files, for editor completion and checking as you type
//! (`# yaml-language-server: $schema=...`). Object names and states come from the
//! dictionary so editors complete them. Written by hand: the recipe language is externally
//! tagged YAML whose exact shape a derive could not express. Pure; no I/O.

use crate::dictionary::Dictionary;
use crate::drive::device_control::{DeviceCommand, DeviceState};
use serde_json::{json, Value};

/// The schema for recipes written against `dictionary`.
pub fn recipe_schema(dictionary: &Dictionary) -> Value {
    let mut names: Vec<String> = Vec::new();
    let mut writable: Vec<String> = Vec::new();
    for o in dictionary.objects() {
        names.push(o.name.clone());
        if o.writable() {
            writable.push(o.name.clone());
        }
    }
    // Only what the drive's profile has (a Control Techniques drive has no quick stop).
    let commands: Vec<&str> = match dictionary.profile() {
        Some(p) => p.command_ids(),
        None => DeviceCommand::ALL.iter().map(|c| c.id()).collect(),
    };
    let states: Vec<&str> = match dictionary.profile() {
        Some(p) => p.state_ids(),
        None => DeviceState::ALL.iter().map(|s| s.id()).collect(),
    };
    // A recipe names its drive by family (`sd2`) or by built-in dictionary (`ct-unidrive-sp`).
    let mut drives = vec![dictionary.family()];
    if let Some(name) = dictionary.name().filter(|n| *n != dictionary.family()) {
        drives.push(name);
    }
    let duration = json!({ "type": "string", "description": "a duration with its unit: 500 ms, 5 s, 10 min, 2 h", "pattern": "^\\s*(\\{\\{.*\\}\\}|[0-9.]+\\s*[a-zA-Zµ]+(\\s+[0-9.]+\\s*[a-zA-Zµ]+)*)\\s*$" });
    let value = json!({ "type": ["string", "number"], "description": "a value with its unit (6000 rpm, 1.5 A), a bare number in the object's unit, or {{param}}" });
    let condition = json!({
        "type": "object",
        "description": "exactly one of equals, above, below, between, near (with within)",
        "properties": {
            "equals": { "$ref": "#/$defs/value" },
            "above": { "$ref": "#/$defs/value" },
            "below": { "$ref": "#/$defs/value" },
            "between": { "type": "array", "items": { "$ref": "#/$defs/value" }, "minItems": 2, "maxItems": 2 },
            "near": { "$ref": "#/$defs/value" },
            "within": { "type": ["string", "number"], "description": "absolute (20 rpm) or percent (1 %)" }
        },
        "additionalProperties": false
    });
    let statistic_condition = json!({
        "type": "object",
        "description": "a condition on the object now, or on a statistic of the last sample window",
        "properties": {
            "mean": { "$ref": "#/$defs/condition" }, "min": { "$ref": "#/$defs/condition" },
            "max": { "$ref": "#/$defs/condition" }, "ripple": { "$ref": "#/$defs/condition" },
            "std": { "$ref": "#/$defs/condition" },
            "equals": { "$ref": "#/$defs/value" }, "above": { "$ref": "#/$defs/value" },
            "below": { "$ref": "#/$defs/value" },
            "between": { "type": "array", "items": { "$ref": "#/$defs/value" }, "minItems": 2, "maxItems": 2 },
            "near": { "$ref": "#/$defs/value" }, "within": { "type": ["string", "number"] }
        },
        "additionalProperties": false
    });
    let objects_map = |item: Value, only: &[String]| {
        let props: serde_json::Map<String, Value> = only.iter().map(|n| (n.clone(), item.clone())).collect();
        json!({ "type": "object", "properties": props, "additionalProperties": false })
    };
    let object_list = json!({
        "oneOf": [
            { "type": "string", "enum": names },
            { "type": "array", "items": { "type": "string", "enum": names } }
        ]
    });
    let mut wait_props = serde_json::Map::new();
    wait_props.insert("state".into(), json!({ "type": "string", "enum": states }));
    wait_props.insert("timeout".into(), json!({ "$ref": "#/$defs/duration" }));
    wait_props.insert("every".into(), json!({ "$ref": "#/$defs/duration" }));
    for n in &names {
        wait_props.insert(n.clone(), json!({ "$ref": "#/$defs/condition" }));
    }
    let keyed = |key: &str, body: Value, doc: &str| {
        json!({
            "type": "object",
            "description": doc,
            "properties": { key: body, "name": { "type": "string" } },
            "required": [key],
            "additionalProperties": false
        })
    };
    let steps_ref = json!({ "$ref": "#/$defs/steps" });
    let step_variants = vec![
        json!({ "type": "string", "enum": commands, "description": "a device command: writes the control word" }),
        keyed(
            "go_to",
            json!({ "oneOf": [
            { "type": "string", "enum": states },
            { "type": "object", "properties": { "state": { "type": "string", "enum": states }, "timeout": { "$ref": "#/$defs/duration" } }, "required": ["state"], "additionalProperties": false }
        ] }),
            "walk the state machine to a state",
        ),
        keyed(
            "set",
            objects_map(json!({ "$ref": "#/$defs/value" }), &writable),
            "write objects",
        ),
        keyed("read", object_list.clone(), "read objects and show their values"),
        keyed(
            "print",
            json!({ "oneOf": [ { "type": "string" }, object_list.clone() ] }),
            "show a message, or values",
        ),
        keyed(
            "wait_until",
            json!({ "type": "object", "properties": wait_props, "additionalProperties": false }),
            "poll until a state or a condition holds; fails after timeout",
        ),
        keyed(
            "dwell",
            json!({ "$ref": "#/$defs/duration" }),
            "wait, watching for drive faults",
        ),
        keyed(
            "sample",
            json!({
                "type": "object",
                "properties": {
                    "objects": { "type": "array", "items": { "type": "string", "enum": names } },
                    "every": { "$ref": "#/$defs/duration" }, "for": { "$ref": "#/$defs/duration" },
                    "csv": { "type": "string" }
                },
                "required": ["objects", "every", "for"], "additionalProperties": false
            }),
            "read objects periodically, keep statistics, optionally to CSV",
        ),
        keyed(
            "expect",
            objects_map(statistic_condition, &names),
            "named pass/fail checks",
        ),
        keyed(
            "ramp",
            json!({
                "type": "object",
                "properties": {
                    "object": { "type": "string", "enum": writable }, "from": { "$ref": "#/$defs/value" },
                    "to": { "$ref": "#/$defs/value" }, "step": { "$ref": "#/$defs/value" },
                    "rate": { "type": "string", "description": "e.g. 1000 rpm/s" }, "every": { "$ref": "#/$defs/duration" }
                },
                "required": ["object", "from", "to"], "additionalProperties": false
            }),
            "write an object in steps from one value to another",
        ),
        keyed(
            "repeat",
            json!({
                "type": "object",
                "properties": { "times": { "type": "integer", "minimum": 1 }, "for": { "$ref": "#/$defs/duration" }, "steps": steps_ref },
                "required": ["steps"], "additionalProperties": false
            }),
            "run nested steps a number of times or for a duration",
        ),
        keyed(
            "include",
            json!({ "oneOf": [
            { "type": "string" },
            { "type": "object", "properties": { "file": { "type": "string" }, "params": { "type": "object" } }, "required": ["file"], "additionalProperties": false }
        ] }),
            "the steps of another recipe file",
        ),
        keyed(
            "expect_parameters",
            json!({ "type": "string", "description": "a file written by `drivescript backup`, relative to this recipe" }),
            "check that the drive holds a backup's parameters, one check per object",
        ),
    ];
    json!({
        "$schema": "http://json-schema.org/draft-07/schema#",
        "title": format!("drivescript recipe ({})", dictionary.title()),
        "type": "object",
        "required": ["name", "steps"],
        "additionalProperties": false,
        "properties": {
            "name": { "type": "string" },
            "description": { "type": "string" },
            "drive": { "type": "string", "enum": drives },
            "params": { "type": "object", "additionalProperties": { "type": ["string", "number"] } },
            "steps": { "$ref": "#/$defs/steps" },
            "finally": { "$ref": "#/$defs/steps" },
            "on_fault": { "$ref": "#/$defs/steps" },
            "leave_enabled": { "type": "boolean" },
            "link": {
                "type": "object",
                "description": "Settings of the drive family's link, as --link-option NAME=VALUE gives them (SD2: channel: cyclic, velocity_scaling: 24000 rpm, heartbeat: on, cycle: 20 ms); the command line wins",
                "additionalProperties": { "type": ["string", "number", "boolean"] }
            },
            "safe_stop": {
                "type": "object",
                "description": "The default safe stop: how long to wait for standstill (setpoint 0) before disabling, and what counts as standstill",
                "additionalProperties": false,
                "properties": {
                    "timeout": { "$ref": "#/$defs/duration" },
                    "standstill": { "type": "string", "examples": ["10 rpm"] }
                }
            }
        },
        "$defs": {
            "duration": duration,
            "value": value,
            "condition": condition,
            "step": { "oneOf": step_variants },
            "steps": { "type": "array", "items": { "$ref": "#/$defs/step" } }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_objects_states_and_commands() {
        let d = crate::family::Registry::builtin()
            .load_dictionary(crate::family::DEFAULT_DICTIONARY)
            .unwrap();
        let s = recipe_schema(&d);
        let text = s.to_string();
        for word in [
            "speed_setpoint",
            "operation_enabled",
            "enable_operation",
            "wait_until",
            "ramp",
        ] {
            assert!(text.contains(word), "{word}");
        }
        // Read-only objects are not offered for `set`.
        let set = &s["$defs"]["step"]["oneOf"][2]["properties"]["set"]["properties"];
        assert!(set.get("speed_setpoint").is_some());
        assert!(set.get("status_word").is_none());
    }
}
