//! A script's `param(…)` and `number(…)`: the `--set NAME=VALUE` values in the type and
//! unit the script asks for, through the one rule of `param_value.rs`. It must not reach
//! the drive.

use super::bridge::{Bridge, RhaiResult};
use super::drive_api::{as_number, error, number_arg, refused};
use super::param_value::{param_value, ParamKind, ParamValue};
use super::resolve;
use rhai::{Dynamic, Engine};
use std::sync::Arc;

pub(super) fn register_params(engine: &mut Engine, bridge: &Arc<Bridge>) {
    let lookup = |b: &Bridge, name: &str, kind: ParamKind| -> RhaiResult<Option<Dynamic>> {
        let Some((_, given)) = b.params.iter().find(|(n, _)| n == name) else {
            return Ok(None);
        };
        Ok(Some(match param_value(name, given, kind).map_err(refused)? {
            ParamValue::Number(n) => Dynamic::from_float(n),
            ParamValue::Integer(n) => Dynamic::from_int(n),
            ParamValue::Bool(v) => Dynamic::from_bool(v),
            ParamValue::Text(t) => Dynamic::from(t),
        }))
    };
    let b = bridge.clone();
    engine.register_fn("param", move |name: &str| -> RhaiResult<Dynamic> {
        lookup(&b, name, ParamKind::Any)?.ok_or_else(|| {
            error(format!(
                "parameter `{name}` is not set: run with --set {name}=VALUE, or give a default: param(\"{name}\", VALUE)"
            ))
        })
    });
    let b = bridge.clone();
    engine.register_fn(
        "param",
        move |name: &str, default: Dynamic| -> RhaiResult<Dynamic> {
            let kind = if default.is_float() {
                ParamKind::Number
            } else if default.is_int() {
                ParamKind::Integer
            } else if default.is_bool() {
                ParamKind::Bool
            } else if default.is_string() {
                ParamKind::Text
            } else {
                ParamKind::Any
            };
            Ok(lookup(&b, name, kind)?.unwrap_or(default))
        },
    );
    // `param("top", 18000.0, "rpm")`: a number in the unit the script works in, whatever
    // unit the `--set` value is written in.
    let b = bridge.clone();
    engine.register_fn(
        "param",
        move |name: &str, default: Dynamic, unit: &str| -> RhaiResult<Dynamic> {
            let unit = crate::dictionary::Unit::parse(unit)
                .map_err(|e| refused(resolve::not_a_unit(unit, &e.to_string())))?;
            let default = number_arg(&default, &format!("the default of parameter `{name}`"))?;
            Ok(lookup(&b, name, ParamKind::InUnit(unit))?.unwrap_or(Dynamic::from_float(default)))
        },
    );
    // `number("8000 rpm", "rpm")`: a parameter with a unit as a number in that unit; a
    // number stays as it is (a parameter given without a unit).
    engine.register_fn("number", |value: Dynamic, unit: &str| -> RhaiResult<f64> {
        if let Some(v) = as_number(&value) {
            return Ok(v);
        }
        let text = value.to_string();
        let q = crate::dictionary::Quantity::parse(&text).map_err(|e| error(e.to_string()))?;
        let to = crate::dictionary::Unit::parse(unit).map_err(|e| error(e.to_string()))?;
        q.value_in(to)
            .ok_or_else(|| error(format!("`{text}` cannot be given in {to}")))
    });
}
