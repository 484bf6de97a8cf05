//! The JSON Schema of recipe files, for editor completion and checking as you type
//! (`# yaml-language-server: $schema=...`). Object names and states come from the
//! dictionary so editors complete them. Written by hand: the recipe language is externally
//! tagged YAML whose exact shape a derive could not express. Pure; no I/O.

use super::loader::{
    DEFAULT_GO_TO_TIMEOUT, DEFAULT_POLL, DEFAULT_RAMP_EVERY, DEFAULT_WAIT_TIMEOUT, STEP_KEYS,
};
use super::schema_dynamics::{
    dynamics_steps, last_pass_schema, on_failure_schema, one_statistic, watch_schema, with_slope,
    STEP_STATISTICS,
};
use super::schema_units::value_key;
pub(super) use super::schema_units::{any_case, units_of};
use crate::dictionary::{Dictionary, Dimension, ObjectDef, Unit};
use crate::drive::{AddressKeyTable, KeyUse, KeyValues};
use crate::session::number;
use serde_json::{json, Value};

/// The hover text of a step's `name:`.
const STEP_NAME_DOC: &str = "the step's own name in reports (a stage name for include and repeat)";
/// A number as recipes write it.
pub(super) const NUMBER: &str = r"-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?";
/// A parameter reference, `{{speed}}`.
pub(super) const PARAM: &str = r"\{\{\s*[A-Za-z_][A-Za-z0-9_]*\s*\}\}";
/// Duration units as the loader (humantime) reads them.
const DURATION_UNITS: &str = "ns|nsec|us|usec|ms|msec|s|sec|secs|second|seconds|m|min|mins|minute|minutes|h|hr|hrs|hour|hours|d|day|days|w|week|weeks|M|month|months|y|year|years";

/// A default as the schema's texts write durations (`5 s`, `100 ms`, `10 min`): the loader's
/// own constants, so that the hover texts and the reference generated from them cannot
/// say another default than the loader applies.
pub(super) fn spaced(d: std::time::Duration) -> String {
    let ms = d.as_millis();
    match ms {
        _ if ms.is_multiple_of(60_000) && ms >= 60_000 => format!("{} min", ms / 60_000),
        _ if ms.is_multiple_of(1000) => format!("{} s", ms / 1000),
        _ => format!("{ms} ms"),
    }
}

/// Text matching `regex` (with `numbers`, a bare number too: a pattern applies to text
/// only), described by `what`: the hover text, and the message editors show for text that
/// does not match instead of the regex (yaml-language-server's `patternErrorMessage`).
/// The `type` also lets an editor complete `name: ` for a key taking it.
fn written_as(what: &str, regex: String, numbers: bool) -> Value {
    json!({
        "type": if numbers { json!(["string", "number"]) } else { json!("string") },
        "description": what,
        "pattern": regex,
        "patternErrorMessage": format!("expected {what}")
    })
}

/// `value_X`, `condition_X` and `check_X` for one dimension (or none); a speed with
/// `pole_pairs` takes the units of frequency too.
fn dimension_defs(defs: &mut serde_json::Map<String, Value>, unit: Option<Unit>, pole_pairs: bool) {
    let key = value_key(unit, pole_pairs);
    let suffix = key.trim_start_matches("value_").to_string();
    let value = match unit {
        Some(u) => {
            let d = u.dimension();
            let also = (key == "value_speed_or_frequency").then_some(Dimension::Frequency);
            let units = std::iter::once(d)
                .chain(also)
                .map(units_of)
                .collect::<Vec<_>>()
                .join("|");
            let examples: Vec<&str> = Unit::ALL
                .iter()
                .filter(|x| x.dimension() == d || Some(x.dimension()) == also)
                .map(|x| x.symbol())
                .collect();
            let description = format!(
                "a {} with its unit ({}), a bare number in {}, or {{{{param}}}}",
                d.name(),
                examples.join(", "),
                u.symbol()
            );
            written_as(
                &description,
                format!(r"^\s*(({NUMBER})\s*({units})?|{PARAM})\s*$"),
                true,
            )
        }
        None => json!({
            "description": "a number in the object's own terms, text for text objects, or {{param}}",
            "type": ["string", "number"]
        }),
    };
    let value_ref = json!({ "$ref": format!("#/$defs/{key}") });
    let within_units = match unit {
        // A tolerance is a difference: K around a temperature in °C.
        Some(u) => format!("%|{}", units_of(u.difference().dimension())),
        None => "%".to_string(),
    };
    let mut within = written_as(
        "the tolerance of near: absolute with the object's unit (20 rpm) or relative (1 %)",
        format!(r"^\s*(({NUMBER})\s*({within_units})?|{PARAM})\s*$"),
        true,
    );
    within["minimum"] = json!(0);
    let predicates = json!({
        "equals": value_ref, "above": value_ref, "below": value_ref,
        "between": { "type": "array", "items": value_ref, "minItems": 2, "maxItems": 2,
                     "description": "[low, high], both included" },
        "near": value_ref, "within": within,
        "warn": { "description": "a narrower band in the shape of the condition's own (a tolerance for near, a value for above/below, [low, high] for between): a pass outside it is marginal" },
        "compared_with_last_pass": last_pass_schema(&within_units)
    });
    // Exactly one predicate; `near` only with `within` and `within` only with `near`.
    let one_predicate = json!([
        { "required": ["equals"], "not": { "anyOf": [ { "required": ["above"] }, { "required": ["below"] }, { "required": ["between"] }, { "required": ["near"] }, { "required": ["within"] } ] } },
        { "required": ["above"], "not": { "anyOf": [ { "required": ["equals"] }, { "required": ["below"] }, { "required": ["between"] }, { "required": ["near"] }, { "required": ["within"] } ] } },
        { "required": ["below"], "not": { "anyOf": [ { "required": ["equals"] }, { "required": ["above"] }, { "required": ["between"] }, { "required": ["near"] }, { "required": ["within"] } ] } },
        { "required": ["between"], "not": { "anyOf": [ { "required": ["equals"] }, { "required": ["above"] }, { "required": ["below"] }, { "required": ["near"] }, { "required": ["within"] } ] } },
        { "required": ["near", "within"], "not": { "anyOf": [ { "required": ["equals"] }, { "required": ["above"] }, { "required": ["below"] }, { "required": ["between"] } ] } }
    ]);
    let (condition_props, condition_shapes) = with_slope(&predicates, &one_predicate);
    let condition = json!({
        "type": "object",
        "description": "exactly one of: equals, above, below, between [low, high], near with within; or slope (wait_until)",
        "properties": condition_props,
        "additionalProperties": false,
        "oneOf": condition_shapes
    });
    let condition_ref = json!({ "$ref": format!("#/$defs/condition_{suffix}") });
    let mut check_props = predicates.as_object().cloned().unwrap_or_default();
    for stat in ["mean", "min", "max", "ripple", "std"] {
        check_props.insert(stat.into(), condition_ref.clone());
    }
    for (stat, doc) in STEP_STATISTICS {
        check_props.insert(stat.into(), json!({ "type": "object", "description": doc }));
    }
    let check = json!({
        "type": "object",
        "description": "a condition on the value now (equals, above, below, between, near + within), or on a statistic of the last sample window (mean, min, max, ripple, std)",
        "properties": check_props,
        "additionalProperties": false,
        "oneOf": [
            { "oneOf": one_predicate },
            { "minProperties": 1, "maxProperties": 1, "anyOf": one_statistic() }
        ]
    });
    defs.insert(key, value);
    defs.insert(format!("condition_{suffix}"), condition);
    defs.insert(format!("check_{suffix}"), check);
}

/// The hover text of an object: what it is, its unit and resolution, range and access.
fn object_doc(o: &ObjectDef) -> (String, String) {
    let unit = o.unit.map(|u| u.symbol().to_string());
    let u = unit.as_deref().map(|u| format!(" {u}")).unwrap_or_default();
    let range = match (o.min, o.max) {
        (Some(lo), Some(hi)) => format!("{}{u} to {}{u}", number(lo), number(hi)),
        (Some(lo), None) => format!("from {}{u}", number(lo)),
        (None, Some(hi)) => format!("up to {}{u}", number(hi)),
        (None, None) => "not limited by the dictionary".into(),
    };
    let bench = if o.bench.is_some() { " (bench limit)" } else { "" };
    let resolution = if o.scale.is_finite() && o.scale > 0.0 {
        format!("{}{u}", number(o.scale))
    } else {
        "—".into()
    };
    let description = o.description.trim().trim_end_matches('.');
    let plain = format!(
        "{description}{}unit: {}; range: {range}{bench}; {}; resolution {resolution}",
        if description.is_empty() { "" } else { ". " },
        unit.as_deref().unwrap_or("none"),
        o.access.describe()
    );
    let mut md = format!("**{}**", o.name);
    if !o.description.trim().is_empty() {
        md.push_str(&format!(" — {}", o.description.trim()));
    }
    md.push_str(&format!(
        "\n\n| unit | range | access | resolution |\n|---|---|---|---|\n| {} | {range}{bench} | {} | {resolution} |",
        unit.as_deref().unwrap_or("none"),
        o.access.describe()
    ));
    if let Some(why) = &o.unconfirmed {
        md.push_str(&format!("\n\n*Unconfirmed:* {why}"));
    }
    (plain, md)
}

/// A reference with the object's hover text beside it. Draft-07 validators ignore keywords
/// next to a `$ref`, which costs nothing here: these are annotations, not constraints, and
/// editors show them (an `allOf` wrapper would put the referenced value's generic text
/// first).
fn documented(reference: String, doc: &(String, String)) -> Value {
    json!({
        "$ref": reference,
        "description": doc.0,
        "markdownDescription": doc.1
    })
}

/// The schema for recipes written against `dictionary`.
/// `address_keys`: every family's keys besides `address:` in a `drives:` entry.
pub fn recipe_schema(dictionary: &Dictionary, address_keys: &AddressKeyTable) -> Value {
    let mut names: Vec<String> = Vec::new();
    let mut writable: Vec<String> = Vec::new();
    let mut defs = serde_json::Map::new();
    let mut set_props = serde_json::Map::new();
    let mut check_props = serde_json::Map::new();
    let mut wait_props = serde_json::Map::new();
    let mut seen = std::collections::HashSet::new();
    for o in dictionary.objects() {
        names.push(o.name.clone());
        let key = value_key(o.unit, o.pole_pairs.is_some());
        if seen.insert(key.clone()) {
            dimension_defs(&mut defs, o.unit, o.pole_pairs.is_some());
        }
        let suffix = key.trim_start_matches("value_");
        let doc = object_doc(o);
        if o.writable() {
            writable.push(o.name.clone());
            set_props.insert(o.name.clone(), documented(format!("#/$defs/{key}"), &doc));
        }
        if o.readable() {
            check_props.insert(
                o.name.clone(),
                documented(format!("#/$defs/check_{suffix}"), &doc),
            );
            wait_props.insert(
                o.name.clone(),
                documented(format!("#/$defs/condition_{suffix}"), &doc),
            );
        }
    }
    // Only what the drive's profile has (a Control Techniques drive has no quick stop), and
    // nothing without one: `check` refuses device commands and states then.
    let (commands, states): (Vec<&str>, Vec<&str>) = match dictionary.profile() {
        Some(p) => (p.command_ids(), p.state_ids()),
        None => (Vec::new(), Vec::new()),
    };
    let no_profile = format!(
        "needs device control, but the {} dictionary has no `profile:`",
        dictionary.name()
    );
    let state = |doc: &str| {
        let mut state = json!({ "type": "string", "enum": states, "description": doc });
        if states.is_empty() {
            state["errorMessage"] = json!(format!("a state {no_profile}"));
        }
        state
    };
    let command_message = if commands.is_empty() {
        format!("a device command {no_profile}")
    } else {
        format!(
            "a step written alone is a device command: {}",
            commands.join(", ")
        )
    };
    // A recipe names its drive by family (`sd2`) or by built-in dictionary (`ct-unidrive-sp`).
    let mut drives = vec![dictionary.family()];
    if dictionary.name() != dictionary.family() {
        drives.push(dictionary.name());
    }
    let duration = written_as(
        "a duration with its unit: 500 ms, 5 s, 10 min, 2 h, 1h 30min, or {{param}}",
        format!(r"^\s*(([0-9]+\s*({DURATION_UNITS})\s*)+|{PARAM})$"),
        false,
    );
    let speed_units = units_of(Dimension::Speed);
    let mut standstill = written_as(
        "a speed with its unit up to which the drive counts as standing still: 10 rpm",
        format!(r"^\s*({NUMBER})\s*({speed_units})\s*$"),
        false,
    );
    let stop_defaults = crate::session::SafeStopSettings::default();
    standstill["examples"] = json!([stop_defaults.standstill.to_string()]);
    standstill["default"] = json!(stop_defaults.standstill.to_string());
    let object_list = json!({
        "oneOf": [
            { "type": "string", "enum": names },
            { "type": "array", "items": { "type": "string", "enum": names } }
        ]
    });
    wait_props.insert("state".into(), state("a device-control state to wait for"));
    wait_props.insert("timeout".into(), json!({ "$ref": "#/$defs/duration" }));
    wait_props.insert("every".into(), json!({ "$ref": "#/$defs/duration" }));
    // The key's own schema carries the description too: an editor shows a key's hover from
    // the schema of its value.
    let keyed = |key: &str, mut body: Value, doc: &str| {
        body["description"] = json!(doc);
        body["markdownDescription"] = json!(doc);
        json!({
            "type": "object",
            "description": doc,
            "properties": { key: body, "name": { "type": "string", "description": STEP_NAME_DOC } },
            "required": [key],
            "additionalProperties": false
        })
    };
    let steps_ref = json!({ "$ref": "#/$defs/steps" });
    let rate_units = format!(
        "{speed_units}|{}|{}|{}",
        units_of(Dimension::Voltage),
        units_of(Dimension::Current),
        units_of(Dimension::Ratio)
    );
    let rate = written_as(
        "a change per time with units: 1000 rpm/s, 50 rpm/min",
        format!(r"^\s*({NUMBER})\s*({rate_units})\s*/\s*(ms|s|min|h)\s*$"),
        false,
    );
    let step_keys = STEP_KEYS;
    let mut step_variants = vec![
        keyed(
            "go_to",
            json!({ "oneOf": [
            state("the state to walk to"),
            { "type": "object", "properties": { "state": state("the state to walk to"), "timeout": { "$ref": "#/$defs/duration" } }, "required": ["state"], "additionalProperties": false }
        ] }),
            &format!("Walk the state machine to a state by the shortest sequence of device commands: `go_to: operation_enabled`, or `{{ state: operation_enabled, timeout: 5 s }}` with its `timeout` (default {} per transition)", spaced(DEFAULT_GO_TO_TIMEOUT)),
        ),
        keyed(
            "set",
            json!({ "type": "object", "properties": set_props, "additionalProperties": false, "minProperties": 1 }),
            "Write objects: `set: { speed_setpoint: 6000 rpm }`; each value is checked against its object's unit and range before anything is sent",
        ),
        keyed(
            "read",
            object_list.clone(),
            "Read objects and show their values: `read: [speed_actual, bus_voltage]`",
        ),
        keyed(
            "print",
            json!({ "oneOf": [ { "type": "string" }, object_list.clone() ] }),
            "Show a message (`print: text`), or read objects and show their values as read does",
        ),
        keyed(
            "wait_until",
            json!({ "type": "object", "properties": wait_props, "additionalProperties": false }),
            &format!("Poll until a state (`state: operation_enabled`) or a condition on an object holds (`speed_actual: {{ near: 6000 rpm, within: 1 % }}`); fails after `timeout` (default {}), polling `every` (default {})", spaced(DEFAULT_WAIT_TIMEOUT), spaced(DEFAULT_POLL)),
        ),
        keyed(
            "dwell",
            json!({ "$ref": "#/$defs/duration" }),
            "Wait for a duration, watching for drive faults: `dwell: 5 s`",
        ),
        keyed(
            "sample",
            json!({
                "type": "object",
                "properties": {
                    "objects": { "type": "array", "items": { "type": "string", "enum": names } },
                    "every": { "$ref": "#/$defs/duration" }, "for": { "$ref": "#/$defs/duration" },
                    "csv": { "type": "string", "description": "a CSV file of this step's samples, relative to --output-dir" },
                    "step": { "type": "object", "description": "per sampled object, the setpoint step its response is measured against: `{ speed_actual: { to: 6000 rpm, from: 0 rpm, band: 2 % } }` (for rise_time, overshoot, settling_time, steady_state_error)" }
                },
                "required": ["objects", "every", "for"], "additionalProperties": false
            }),
            "Read `objects` `every` interval `for` a duration and keep their statistics (mean, min, max, ripple, std) for the `expect` steps after it; `csv:` also writes the samples to a file",
        ),
        keyed(
            "expect",
            json!({ "type": "object", "properties": check_props, "additionalProperties": false, "minProperties": 1 }),
            "Pass/fail checks, each named in the reports, on the value now or on a statistic of the last sample window: `expect: { speed_actual: { mean: { near: 6000 rpm, within: 0.5 % } } }`; a failed check fails the run (exit code 1)",
        ),
        keyed(
            "ramp",
            json!({
                "type": "object",
                "properties": {
                    "object": { "type": "string", "enum": writable }, "from": { "$ref": "#/$defs/value_any" },
                    "to": { "$ref": "#/$defs/value_any" }, "step": { "$ref": "#/$defs/value_any" },
                    "rate": rate,
                    "every": { "$ref": "#/$defs/duration" }
                },
                "required": ["object", "from", "to"], "additionalProperties": false
            }),
            &format!("Write an object in steps from `from` to `to`, one write `every` interval (default {}): by `step` each, or at a `rate` (1000 rpm/s)", spaced(DEFAULT_RAMP_EVERY)),
        ),
        keyed(
            "repeat",
            json!({
                "type": "object",
                "properties": { "times": { "type": "integer", "minimum": 1 }, "for": { "$ref": "#/$defs/duration" }, "steps": steps_ref, "on_failure": on_failure_schema("in this block"), "watch": watch_schema("this block") },
                "required": ["steps"], "additionalProperties": false,
                "oneOf": [ { "required": ["times"], "not": { "required": ["for"] } }, { "required": ["for"], "not": { "required": ["times"] } } ]
            }),
            "Run nested `steps` a number of `times`, or again and again `for` a duration: an iteration starts while the duration has not run out and always runs to its end (whole iterations), so the repeat takes up to one iteration longer",
        ),
        keyed(
            "include",
            json!({ "oneOf": [
            { "type": "string" },
            { "type": "object", "properties": { "file": { "type": "string" }, "params": { "type": "object" }, "on_failure": on_failure_schema("in this block") }, "required": ["file"], "additionalProperties": false }
        ] }),
            "Run the steps of another recipe file, relative to this one: `include: stage.yaml`, or `{ file: stage.yaml, params: { speed: 6000 rpm } }` with parameters of its own",
        ),
        keyed(
            "expect_parameters",
            json!({ "type": "string", "description": "a file written by `drivescript backup`, relative to this recipe" }),
            "Check that the drive holds a backup's parameters (a file written by `drivescript backup`, relative to this recipe), one check per object",
        ),
    ];
    step_variants.extend(
        super::prompt_schema::prompt_steps()
            .into_iter()
            .map(|(key, body, doc)| keyed(key, body, doc)),
    );
    step_variants.extend(dynamics_steps(&steps_ref).map(|(key, body, doc)| keyed(key, body, &doc)));
    let mut step_key_names: Vec<&str> = step_keys.to_vec();
    step_key_names.push("name");
    defs.insert(
        "value_any".into(),
        json!({ "type": ["string", "number"], "description": "a value with the object's unit, a bare number in it, or {{param}}" }),
    );
    defs.insert("duration".into(), duration);
    // A string step is a device command; a map step has one step key (and maybe a name).
    // Split by type first, so a misspelt key is reported against the list of step keys
    // instead of as "expected a string". An editor offers neither branch's values on an
    // empty step, so the commands are offered as snippets too.
    let command_doc = "a device command: writes the control word";
    let snippets: Vec<Value> = commands
        .iter()
        .map(|c| json!({ "label": c, "description": command_doc, "body": c }))
        .collect();
    defs.insert(
        "step".into(),
        json!({
            "defaultSnippets": snippets,
            "if": { "type": "string" },
            "then": { "type": "string", "enum": commands, "description": command_doc,
                      "errorMessage": command_message },
            "else": {
                "type": "object",
                "propertyNames": { "enum": step_key_names,
                                   "errorMessage": format!("a step is one of: {}", step_keys.join(", ")) },
                "minProperties": 1,
                "oneOf": step_variants
            }
        }),
    );
    defs.insert(
        "steps".into(),
        json!({ "type": "array", "items": { "$ref": "#/$defs/step" } }),
    );
    // `finally` and `on_fault` run unattended: the safe stop never waits for a person, so
    // an editor flags an operator step there as `check` refuses it.
    let prompts: Vec<Value> = super::prompt_schema::prompt_steps()
        .into_iter()
        .map(|(key, _, _)| json!({ "required": [key] }))
        .collect();
    defs.insert(
        "unattended_steps".into(),
        json!({ "type": "array", "items": { "allOf": [
            { "$ref": "#/$defs/step" },
            { "not": { "type": "object", "anyOf": prompts },
              "errorMessage": "no operator steps here: `finally` and `on_fault` run unattended" }
        ] } }),
    );
    json!({
        "$schema": "http://json-schema.org/draft-07/schema#",
        "title": format!("drivescript recipe ({})", dictionary.title()),
        "type": "object",
        "required": ["name", "steps"],
        "additionalProperties": false,
        "properties": {
            "name": { "type": "string", "description": "the recipe's name in the console, JUnit and HTML reports" },
            "description": { "type": "string", "description": "what the recipe does, for its reader" },
            "drive": { "type": "string", "enum": drives,
                       "description": format!("the drive family (or built-in dictionary) the recipe is written for (default: `--drive`, which is `{}` unless given); this schema is the one of {}", crate::family::DEFAULT_DICTIONARY, dictionary.title()) },
            "params": { "type": "object", "additionalProperties": { "type": ["string", "number"] },
                        "description": "parameters used as {{name}} in values; --set name=value overrides them" },
            "steps": { "$ref": "#/$defs/steps", "description": "the steps, in order: device commands (`- shutdown`) and steps with one key (`- set: { speed_setpoint: 6000 rpm }`)" },
            "finally": { "$ref": "#/$defs/unattended_steps", "description": "steps run at every ending, after a turning drive is braked to standstill; they replace the default stop (disable operation, shutdown), never the verification that follows" },
            "on_fault": { "$ref": "#/$defs/unattended_steps", "description": "steps run when the drive faults during a step, before the safe stop" },
            "watch": watch_schema("the whole run"),
            "on_failure": on_failure_schema("of the recipe's steps (where no block names its own)"),
            "leave_enabled": { "type": "boolean", "default": false,
                "description": "true: a run that succeeds leaves the drive as its steps left it (no brake, no finally, the default's or the recipe's); every other ending stops it. `drivescript stop` stops it later" },
            "drives": {
                "type": "object",
                "description": "Several named drives instead of one `drive:`; steps then name objects as `left.speed_setpoint`, commands as `- enable_operation: left` (a bare command goes to every drive) and `go_to: { drive: left, state: … }`",
                "propertyNames": written_as("a drive name: lower-case letters, digits and _, starting with a letter", "^[a-z][a-z0-9_]*$".into(), false),
                "additionalProperties": drive_entry(address_keys)
            },
            "link": {
                "type": "object",
                "description": "Settings of the link of the drive's family, as --link-option NAME=VALUE gives them (the family's names and values, e.g. channel: cyclic); the command line wins",
                "additionalProperties": { "type": ["string", "number", "boolean"] }
            },
            "safe_stop": {
                "type": "object",
                "description": "The safe stop: how long to wait for standstill (setpoint 0) before disabling, what counts as standstill, and whether a turning drive is braked before any disable (also before the recipe's own finally)",
                "additionalProperties": false,
                "properties": {
                    "timeout": { "$ref": "#/$defs/duration", "default": spaced(stop_defaults.standstill_timeout) },
                    "brake_to_standstill": { "type": "boolean", "default": true,
                        "description": "true (default): a drive still enabled and turning at the end gets the speed setpoint 0 and is waited for until it stands still before anything disables it, the recipe's own finally included. false: it is disabled at speed and coasts (for a drive that brakes by itself on disable); check says so" },
                    "standstill": standstill
                }
            }
        },
        "$defs": defs
    })
}

/// One `drives:` entry: the keys every drive has, and each family's address keys, offered
/// only for a `drive:` of that family, never with `address:` where they stand instead of
/// it, and never without `address:` where they qualify it.
fn drive_entry(address_keys: &AddressKeyTable) -> Value {
    let mut props = serde_json::Map::new();
    let names = address_keys.drive_names().join(", ");
    let notations: Vec<String> = address_keys
        .families()
        .filter(|f| !f.address_help.is_empty())
        .map(|f| format!("{}: {}", f.family, f.address_help))
        .collect();
    let address = match notations.is_empty() {
        true => "the address in the family's notation".to_string(),
        false => format!("the address in the family's notation ({})", notations.join("; ")),
    };
    props.insert(
        "drive".into(),
        json!({ "type": "string", "description": format!("the built-in dictionary or family: {names}") }),
    );
    props.insert(
        "address".into(),
        json!({ "type": ["string", "number"], "description": address }),
    );
    props.insert("port".into(), json!({ "type": "string", "description": "its own serial port (default: the command line's connection, shared)" }));
    props.insert(
        "tcp".into(),
        json!({ "type": "string", "description": "its own TCP serial server HOST:PORT" }),
    );
    props.insert(
        "can".into(),
        json!({ "type": "string", "description": "its own CAN bus: slcan:PATH or socketcan:IF" }),
    );
    props.insert(
        "pole_pairs".into(),
        json!({ "type": "integer", "minimum": 1, "maximum": crate::dictionary::MAX_POLE_PAIRS,
                "description": "an inverter's motor pole pairs (rpm = Hz × 60 / pole pairs), over its dictionary's; --link-option pole-pairs=N wins" }),
    );
    let mut rules = Vec::new();
    let mut dependencies = serde_json::Map::new();
    for name in address_keys.all_key_names() {
        let takers = address_keys.families_with(name);
        let drives: Vec<&str> = takers
            .iter()
            .flat_map(|(f, _)| f.drive_names.iter().copied())
            .collect();
        let description = takers
            .iter()
            .map(|(f, k)| format!("{}: {}", f.family, k.meaning))
            .collect::<Vec<_>>()
            .join("; ");
        let Some((_, key)) = takers.first() else {
            continue;
        };
        let mut value = match key.values {
            KeyValues::Number { min, max } => json!({ "type": "integer", "minimum": min, "maximum": max }),
            KeyValues::OneOf(values) => json!({ "type": "string", "enum": values }),
        };
        value["description"] = json!(description);
        props.insert(name.into(), value);
        rules.push(json!({
            "if": { "properties": { "drive": { "not": { "enum": drives } } } },
            "then": { "properties": { name: false } }
        }));
        match key.usage {
            KeyUse::InsteadOfAddress => rules.push(json!({ "not": { "required": ["address", name] } })),
            KeyUse::WithAddress => {
                dependencies.insert(name.into(), json!(["address"]));
            }
        }
    }
    let mut entry = json!({
        "type": "object",
        "required": ["drive"],
        "additionalProperties": false,
        "properties": props
    });
    if !rules.is_empty() {
        entry["allOf"] = json!(rules);
    }
    if !dependencies.is_empty() {
        entry["dependencies"] = Value::Object(dependencies);
    }
    entry
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_objects_states_and_commands() {
        let d = crate::family::Registry::builtin()
            .load_dictionary(crate::family::DEFAULT_DICTIONARY)
            .unwrap();
        let s = recipe_schema(&d, &crate::family::Registry::builtin().address_keys());
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
        let set = &s["$defs"]["step"]["else"]["oneOf"][1]["properties"]["set"]["properties"];
        assert!(set.get("speed_setpoint").is_some());
        assert!(set.get("status_word").is_none());
        // Hover text with unit, range, access and resolution for every object.
        let md = set["speed_setpoint"]["markdownDescription"].as_str().unwrap();
        for part in ["**speed_setpoint**", "| rpm |", "read-write", "0.001 rpm"] {
            assert!(md.contains(part), "{part}: {md}");
        }
        let expect = &s["$defs"]["step"]["else"]["oneOf"][7]["properties"]["expect"]["properties"];
        assert!(expect["status_word"]["markdownDescription"]
            .as_str()
            .unwrap()
            .contains("read-only"));
        // Values of speed objects take speed units only; durations take time units only.
        let speed = s["$defs"]["value_speed"]["pattern"].as_str().unwrap();
        assert!(
            speed.contains("[rR][pP][mM]") && !speed.contains("[aA]"),
            "{speed}"
        );
        let duration = s["$defs"]["duration"]["pattern"].as_str().unwrap();
        assert!(
            duration.contains("|min|") && !duration.contains("parsec"),
            "{duration}"
        );
        // `near` needs `within`.
        let shapes = s["$defs"]["condition_speed"]["oneOf"].to_string();
        assert!(shapes.contains(r#"["near","within"]"#), "{shapes}");
    }

    /// What an editor needs beyond validation: the object's own hover text beside its
    /// `$ref` (not under an `allOf` whose referenced text comes first), a description on
    /// every step key, a `type` on every value so completing a key inserts `key: `, words
    /// instead of regexes for a value that does not match, and the device commands offered
    /// on an empty step.
    #[test]
    fn gives_editors_hover_texts_key_types_pattern_messages_and_commands() {
        let registry = crate::family::Registry::builtin();
        let d = registry
            .load_dictionary(crate::family::DEFAULT_DICTIONARY)
            .unwrap();
        let s = recipe_schema(&d, &registry.address_keys());
        let variants = s["$defs"]["step"]["else"]["oneOf"].as_array().unwrap();
        let set = &variants[1]["properties"]["set"]["properties"]["speed_setpoint"];
        assert_eq!(set["$ref"], "#/$defs/value_speed");
        assert!(set.get("allOf").is_none(), "{set}");
        assert!(set["description"].as_str().unwrap().contains("rpm"), "{set}");
        for variant in variants {
            let props = variant["properties"].as_object().unwrap();
            for (key, body) in props {
                let doc = body["description"].as_str().unwrap_or_default();
                assert!(doc.len() > 20, "step key `{key}` has no description: {body}");
            }
        }
        for def in [
            "value_speed",
            "value_plain",
            "value_any",
            "condition_speed",
            "check_speed",
            "duration",
        ] {
            assert!(s["$defs"][def].get("type").is_some(), "{def} has no type");
        }
        assert_eq!(
            s["$defs"]["duration"]["patternErrorMessage"],
            "expected a duration with its unit: 500 ms, 5 s, 10 min, 2 h, 1h 30min, or {{param}}"
        );
        assert!(s["$defs"]["value_speed"]["patternErrorMessage"]
            .as_str()
            .unwrap()
            .starts_with("expected a speed with its unit (rpm"));
        let snippets: Vec<&str> = s["$defs"]["step"]["defaultSnippets"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x["body"].as_str().unwrap())
            .collect();
        assert_eq!(
            snippets,
            s["$defs"]["step"]["then"]["enum"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_str().unwrap())
                .collect::<Vec<_>>()
        );
        assert!(snippets.contains(&"disable_operation"), "{snippets:?}");
    }

    /// Without a device-control profile `check` refuses device commands and states, so the
    /// schema offers none and says why.
    #[test]
    fn offers_no_device_command_or_state_without_a_profile() {
        let registry = crate::family::Registry::builtin();
        let d = registry.load_dictionary("lenze-9400").unwrap();
        assert!(d.profile().is_none());
        let s = recipe_schema(&d, &registry.address_keys());
        let step = &s["$defs"]["step"];
        assert_eq!(step["defaultSnippets"], json!([]));
        assert_eq!(step["then"]["enum"], json!([]));
        assert_eq!(
            step["then"]["errorMessage"],
            "a device command needs device control, but the lenze-9400 dictionary has no `profile:`"
        );
        let go_to = &step["else"]["oneOf"][0]["properties"]["go_to"]["oneOf"][0];
        assert_eq!(go_to["enum"], json!([]));
        assert!(go_to["errorMessage"]
            .as_str()
            .unwrap()
            .starts_with("a state needs device control"));
    }

    #[test]
    fn drives_entries_offer_each_familys_address_keys_for_its_drives_only() {
        let registry = crate::family::Registry::builtin();
        let d = registry.load_dictionary("ct-unidrive-sp").unwrap();
        // Whatever dictionary the schema is printed for, a `drives:` entry may be any family's.
        let s = recipe_schema(&d, &registry.address_keys());
        let entry = &s["properties"]["drives"]["additionalProperties"];
        assert_eq!(entry["properties"]["dnc_address"]["minimum"], 2);
        assert_eq!(entry["properties"]["dnc_address"]["maximum"], 255);
        assert!(entry["properties"]["dnc_address"]["description"]
            .as_str()
            .unwrap()
            .starts_with("sd2: the drive's raw DNC address"));
        assert_eq!(entry["properties"]["axis"]["enum"], json!(["a", "b", "A", "B"]));
        assert_eq!(entry["dependencies"]["axis"], json!(["address"]));
        let rules = entry["allOf"].to_string();
        assert!(
            rules.contains(r#"{"if":{"properties":{"drive":{"not":{"enum":["sd2"]}}}},"then":{"properties":{"dnc_address":false}}}"#),
            "{rules}"
        );
        assert!(
            rules.contains(r#"{"not":{"required":["address","dnc_address"]}}"#),
            "{rules}"
        );
        // The drive names and address notations are the registry's, not a copy.
        let registry = crate::family::Registry::builtin();
        let drive = entry["properties"]["drive"]["description"].as_str().unwrap();
        for name in registry.dictionary_names() {
            assert!(drive.contains(name), "{name}: {drive}");
        }
        let address = entry["properties"]["address"]["description"].as_str().unwrap();
        for f in registry.address_keys().families() {
            assert!(address.contains(f.address_help), "{}: {address}", f.family);
        }
        let link = s["properties"]["link"]["description"].as_str().unwrap();
        assert!(!link.contains("SD2"), "{link}");
        // Without address keys in the table, an entry has the keys every drive has.
        let plain = recipe_schema(&d, &AddressKeyTable::default());
        let entry = &plain["properties"]["drives"]["additionalProperties"];
        assert!(entry["properties"].get("dnc_address").is_none());
        assert!(entry.get("allOf").is_none());
        let drive = entry["properties"]["drive"]["description"].as_str().unwrap();
        assert!(
            !drive.contains("sd2") && !drive.contains("lenze"),
            "no family names its own: {drive}"
        );
    }
}
