//! The values a recipe writes: durations (`500 ms`, `10 min`, within the longest a recipe
//! may give) and numbers for an object, converted to its unit and, for writes, checked
//! against its type and limits. Each problem at the value's place. It must not look up
//! objects or know which step a value belongs to (callers pass the object and the key).

use super::{Loader, MAX_DURATION};
use crate::diag::{YamlNode, YamlValue};
use crate::dictionary::{ObjectDef, Quantity, ValueError};
use std::time::Duration;

/// What to write instead of `.nan` or `.inf`.
pub(super) const FINITE_HELP: &str = "write a number such as `6000 rpm`, `1 %` or `0.5 A`";

impl Loader<'_, '_> {
    /// A duration with its unit; `what` (`dwell`, `timeout`) heads the messages.
    pub(super) fn duration(&mut self, node: &YamlNode, what: &str) -> Option<Duration> {
        if let YamlValue::Int(_) | YamlValue::Float(_) = node.value {
            let n = node.as_text().unwrap_or_default();
            return self.refuse(
                &node.span,
                format!("{what}: `{n}` has no unit"),
                "which unit?",
                Some(format!(
                    "write a duration with its unit, e.g. `{n} s`, `{n} ms` or `{n} min`"
                )),
            );
        }
        let text = self.text(node, &format!("`{what}`"))?;
        match humantime::parse_duration(text.trim()) {
            Ok(d) if d.is_zero() => {
                self.problem(
                    &node.span,
                    format!("{what} must be longer than zero"),
                    "zero",
                    None,
                );
                None
            }
            Ok(d) if d > MAX_DURATION => {
                self.problem(
                    &node.span,
                    format!(
                        "{what}: `{}` is longer than {} days, the longest duration a recipe may give",
                        text.trim(),
                        MAX_DURATION.as_secs() / (24 * 3600)
                    ),
                    "too long",
                    Some("check the number and the unit; repeat a shorter step for a longer run".into()),
                );
                None
            }
            Ok(d) => Some(d),
            Err(e) => {
                self.problem(
                    &node.span,
                    format!("{what}: `{text}` is not a duration ({e})"),
                    "not a duration",
                    Some("write e.g. `500 ms`, `5 s`, `10 min`, `2 h`".into()),
                );
                None
            }
        }
    }

    /// A number for `def` in its engineering unit, written as the value of `what`;
    /// `check_limits` also refuses values outside the object's limits and type (for writes).
    pub(super) fn number_for(
        &mut self,
        def: &ObjectDef,
        node: &YamlNode,
        what: &str,
        check_limits: bool,
    ) -> Option<f64> {
        self.quantity_for(def, node, what, check_limits).map(|q| q.value)
    }

    /// [`Self::number_for`] as a bare quantity in `def`'s unit: a whole number given in
    /// that unit (or bare) keeps its exact integer, beyond a float's precision too.
    pub(super) fn quantity_for(
        &mut self,
        def: &ObjectDef,
        node: &YamlNode,
        what: &str,
        check_limits: bool,
    ) -> Option<Quantity> {
        if self.r.refuse_non_finite(node, what, FINITE_HELP) {
            return None;
        }
        let text = self.text(node, what)?;
        let q = match Quantity::parse(&text) {
            Ok(q) => q,
            Err(e) => {
                return self.refuse(&node.span, format!("{}: {e}", def.name), "not a value", None);
            }
        };
        if check_limits {
            if let Err(e) = def.to_raw(&q) {
                return self.refuse(
                    &node.span,
                    e.to_string(),
                    "refused before anything is sent",
                    limits_help(def),
                );
            }
        }
        match (q.unit, def.unit) {
            (None, _) => Some(q),
            (Some(u), Some(own)) if u == own => Some(q.in_unit(None)),
            (Some(u), Some(own)) => match def.in_own_unit(q.value, u) {
                Ok(v) if !v.is_finite() => {
                    self.problem(
                        &node.span,
                        format!("{}: `{text}` is too large to be a number of {own}", def.name),
                        "too large",
                        None,
                    );
                    None
                }
                Ok(v) => Some(Quantity::new(v, None)),
                Err(e @ ValueError::NoPolePairs { .. }) => {
                    self.problem(&node.span, e.to_string(), "pole pairs unknown", None);
                    None
                }
                Err(_) => {
                    self.problem(
                        &node.span,
                        format!("{u} is not a unit of {} ({own})", def.name),
                        "wrong unit",
                        u.mismatch_help(own),
                    );
                    None
                }
            },
            (Some(u), None) => {
                self.problem(
                    &node.span,
                    format!("{} has no unit; write a plain number, not {u}", def.name),
                    "no unit here",
                    None,
                );
                None
            }
        }
    }
}

impl Loader<'_, '_> {
    /// An amount by which `def`'s value differs (a tolerance, a ripple, an error), in the
    /// unit a difference of its values is written in: K for an object in °C.
    pub(super) fn difference_for(&mut self, def: &ObjectDef, node: &YamlNode, what: &str) -> Option<f64> {
        let as_difference = in_unit(def, def.unit.map(crate::dictionary::Unit::difference));
        self.number_for(&as_difference, node, what, false)
    }
}

/// `def` with its values read in `unit` instead of its own (a difference, a time, a rate),
/// for conditions on a quantity derived from the object's values.
pub(super) fn in_unit(def: &ObjectDef, unit: Option<crate::dictionary::Unit>) -> ObjectDef {
    let mut derived = def.clone();
    derived.unit = unit;
    derived
}

fn limits_help(def: &ObjectDef) -> Option<String> {
    let unit = def.unit.map(|u| format!(" {}", u.symbol())).unwrap_or_default();
    let bench = match def.bench {
        Some(_) => " on this bench; only the limits file can raise a bench limit (not the recipe, --set or a dictionary)",
        None => "",
    };
    match (def.min, def.max) {
        (Some(lo), Some(hi)) => Some(format!(
            "{} accepts {}{unit} to {}{unit}{bench}",
            def.name,
            crate::session::number(lo),
            crate::session::number(hi)
        )),
        _ => None,
    }
}
