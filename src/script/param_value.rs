//! What a script's `param(…)` gives it for a `--set NAME=VALUE`: the value converted to
//! the type the script's default implies (`param("holds", 2)` a whole number,
//! `param("limit", 3.0)` a number, `param("top", 18000.0, "rpm")` a number in rpm from
//! `14krpm`, `14000` or `14000 rpm`), or a refusal saying why that cannot work. The same
//! rule for `check` (literal defaults, before anything runs) and for the running script.
//! It must not know Rhai or the drive.

use super::resolve::Refusal;
use crate::dictionary::{Quantity, Unit};

/// What the script's call implies the parameter is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamKind {
    /// `param("top")`: no default; a number when the value is one, else text.
    Any,
    /// A default with a decimal point (`1000.0`): a plain number.
    Number,
    /// A whole default (`3`): a whole number.
    Integer,
    /// `true` / `false`.
    Bool,
    /// A text default: the value as written.
    Text,
    /// `param("top", 1000.0, "rpm")`: a number in this unit; a bare number is in it already.
    InUnit(Unit),
}

/// A parameter's value as the script receives it.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    Number(f64),
    Integer(i64),
    Bool(bool),
    Text(String),
}

impl ParamKind {
    /// The kind a default written as `literal` (Rhai source text) implies; `None` when the
    /// text is not a literal whose type is clear.
    pub fn of_literal(literal: &str) -> Option<ParamKind> {
        let t = literal.trim().trim_start_matches('-').replace('_', "");
        if t == "true" || t == "false" {
            return Some(ParamKind::Bool);
        }
        if t.starts_with('"') {
            return Some(ParamKind::Text);
        }
        if t.parse::<i64>().is_ok() {
            return Some(ParamKind::Integer);
        }
        t.parse::<f64>().is_ok().then_some(ParamKind::Number)
    }
}

/// `given` (the `--set` value of parameter `name`) as `kind` asks.
pub fn param_value(name: &str, given: &str, kind: ParamKind) -> Result<ParamValue, Refusal> {
    let t = given.trim();
    let plain = t.parse::<f64>().ok().filter(|n| n.is_finite());
    let refuse = |what: &str, help: String| {
        Err(Refusal::new(
            format!("--set {name}={t}: {what}"),
            "parameter read here",
            Some(help),
        ))
    };
    match kind {
        ParamKind::Any => Ok(plain.map_or_else(|| ParamValue::Text(t.to_string()), ParamValue::Number)),
        ParamKind::Text => Ok(ParamValue::Text(t.to_string())),
        ParamKind::Bool => match t {
            "true" => Ok(ParamValue::Bool(true)),
            "false" => Ok(ParamValue::Bool(false)),
            _ => refuse(
                "the script's default is true or false",
                format!("write --set {name}=true or --set {name}=false"),
            ),
        },
        ParamKind::Integer => match (t.parse::<i64>(), plain) {
            (Ok(n), _) => Ok(ParamValue::Integer(n)),
            (Err(_), Some(_)) => refuse(
                "the script's default is a whole number",
                format!("give a whole number, or write the default with a decimal point (param(\"{name}\", 2.0)) to take any number"),
            ),
            (Err(_), None) => refuse(
                "the script's default is a whole number",
                format!("give a whole number, e.g. --set {name}=3"),
            ),
        },
        ParamKind::Number => match (plain, Quantity::parse(t)) {
            (Some(n), _) => Ok(ParamValue::Number(n)),
            (None, Ok(Quantity { unit: Some(unit), .. })) => refuse(
                "the script's default is a plain number, without a unit",
                format!("name the unit the script works in: param(\"{name}\", DEFAULT, \"{unit}\"), or give a plain number"),
            ),
            _ => refuse(
                "the script's default is a number",
                format!("give a number, e.g. --set {name}=1000"),
            ),
        },
        ParamKind::InUnit(unit) => match Quantity::parse(t) {
            Ok(q) => match q.value_in(unit) {
                Some(v) => Ok(ParamValue::Number(v)),
                None => refuse(
                    &format!("the script reads `{name}` in {unit}"),
                    format!(
                        "give a value in {unit} or a unit that measures {}, e.g. --set {name}=1000{unit}",
                        unit.dimension().name()
                    ),
                ),
            },
            Err(e) => refuse(&e.to_string(), format!("e.g. --set {name}=1000{unit}")),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_imply_kinds() {
        assert_eq!(ParamKind::of_literal("1000.0"), Some(ParamKind::Number));
        assert_eq!(ParamKind::of_literal("-2e3"), Some(ParamKind::Number));
        assert_eq!(ParamKind::of_literal("3"), Some(ParamKind::Integer));
        assert_eq!(ParamKind::of_literal("1_000"), Some(ParamKind::Integer));
        assert_eq!(ParamKind::of_literal("true"), Some(ParamKind::Bool));
        assert_eq!(ParamKind::of_literal("\"fast\""), Some(ParamKind::Text));
        assert_eq!(ParamKind::of_literal("top * 2"), None);
    }

    #[test]
    fn a_value_with_a_unit_becomes_a_number_in_the_scripts_unit() {
        let rpm = ParamKind::InUnit(Unit::Rpm);
        assert_eq!(param_value("top", "2krpm", rpm), Ok(ParamValue::Number(2000.0)));
        assert_eq!(param_value("top", "2000", rpm), Ok(ParamValue::Number(2000.0)));
        assert_eq!(
            param_value("top", " 1500 rpm ", rpm),
            Ok(ParamValue::Number(1500.0))
        );
        let e = param_value("top", "5 A", rpm).unwrap_err();
        assert!(e.message.contains("reads `top` in rpm"), "{e:?}");
        let e = param_value("top", "2 rmp", rpm).unwrap_err();
        assert!(e.message.contains("did you mean `rpm`?"), "{e:?}");
    }

    #[test]
    fn a_value_that_cannot_be_the_defaults_type_is_refused() {
        let e = param_value("top", "2krpm", ParamKind::Number).unwrap_err();
        assert_eq!(
            e.message,
            "--set top=2krpm: the script's default is a plain number, without a unit"
        );
        assert!(e
            .help
            .unwrap_or_default()
            .contains("param(\"top\", DEFAULT, \"krpm\")"));
        assert!(param_value("holds", "2.5", ParamKind::Integer).is_err());
        assert_eq!(
            param_value("holds", "2", ParamKind::Integer),
            Ok(ParamValue::Integer(2))
        );
        assert_eq!(
            param_value("limit", "3", ParamKind::Number),
            Ok(ParamValue::Number(3.0))
        );
        assert!(param_value("dry", "yes", ParamKind::Bool).is_err());
        assert_eq!(
            param_value("dry", "true", ParamKind::Bool),
            Ok(ParamValue::Bool(true))
        );
        assert_eq!(
            param_value("mode", "2krpm", ParamKind::Text),
            Ok(ParamValue::Text("2krpm".into()))
        );
        assert_eq!(
            param_value("top", "2krpm", ParamKind::Any),
            Ok(ParamValue::Text("2krpm".into()))
        );
        assert_eq!(
            param_value("top", "14000", ParamKind::Any),
            Ok(ParamValue::Number(14000.0))
        );
    }
}
