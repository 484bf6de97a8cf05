//! A condition on one object's value, shared by `wait_until` and `expect`: exactly one of
//! `equals`, `above`, `below`, `between`, `near` (with `within`, a tolerance in the
//! object's unit or in %). It must not know which step asks, nor evaluate anything.

use crate::diag::{Shape, YamlNode, YamlValue};
use crate::dictionary::{DataType, ObjectDef};
use crate::recipe::loader::values::FINITE_HELP;
use crate::recipe::loader::Loader;
use crate::session::{Predicate, Tolerance};

const OPERATORS: [&str; 5] = ["equals", "above", "below", "between", "near"];

impl Loader<'_, '_> {
    /// The text an `equals` on a text, byte-string or DOMAIN object compares with. Bytes
    /// are taken however hex is written (`CAFE`, `ca fe`, `0xca 0xfe`, as `set` takes
    /// them) and kept in the one form a value read is shown in (`ca fe`), so that the same
    /// bytes always compare equal.
    fn text_to_equal(&mut self, def: &ObjectDef, value: &YamlNode, what: &str) -> Option<String> {
        let text = self.text(value, what)?;
        if !matches!(def.data_type, DataType::Octets | DataType::Domain) {
            return Some(text);
        }
        match crate::hex::parse_hex(&text) {
            Ok(bytes) => Some(crate::hex::to_hex(&bytes)),
            Err(why) => self.refuse(
                &value.span,
                format!(
                    "{} holds bytes, written as hex such as `01 0a ff`: {why}",
                    def.name
                ),
                "expected hex bytes",
                None,
            ),
        }
    }

    pub(in crate::recipe::loader) fn predicate(
        &mut self,
        def: &ObjectDef,
        node: &YamlNode,
    ) -> Option<Predicate> {
        let allowed = ["equals", "above", "below", "between", "near", "within"];
        let shape = Shape::new("this condition", &allowed).example("{ near: 6000 rpm, within: 1 % }");
        let f = self.r.fields(node, &shape)?;
        let given: Vec<&str> = f
            .entries()
            .iter()
            .map(|(k, _)| k.value.as_str())
            .filter(|k| OPERATORS.contains(k))
            .collect();
        let [op] = given.as_slice() else {
            return self.refuse(
                &node.span,
                format!(
                    "a condition on {} has exactly one of equals, above, below, between, near; this has {}",
                    def.name,
                    given.len()
                ),
                "one condition",
                Some("e.g. `{ near: 6000 rpm, within: 1 % }` or `{ above: 100 rpm }`".into()),
            );
        };
        let value = f.get(op)?;
        let what = format!("`{op}`");
        if *op != "near" {
            if let Some(w) = f.get("within") {
                return self.refuse(&w.span, "`within` goes with `near`", "only with near", None);
            }
        }
        match *op {
            "equals" if !def.data_type.is_number() => {
                Some(Predicate::EqualsText(self.text_to_equal(def, value, &what)?))
            }
            "equals" => Some(Predicate::Equals(self.quantity_for(def, value, &what, false)?)),
            "above" => Some(Predicate::Above(self.number_for(def, value, &what, false)?)),
            "below" => Some(Predicate::Below(self.number_for(def, value, &what, false)?)),
            "between" => {
                let (low, high) = self.between_ends(value, "[5900 rpm, 6100 rpm]", |n| {
                    format!("between takes two values, this has {n}")
                })?;
                let lo = self.number_for(def, low, "the low end of `between`", false);
                let hi = self.number_for(def, high, "the high end of `between`", false);
                Some(Predicate::Between(lo?, hi?))
            }
            _ => {
                let target = self.number_for(def, value, &what, false);
                let Some(w) = f.get("within") else {
                    return self.refuse(
                        &node.span,
                        "`near` needs `within`: how close is near enough",
                        "within missing",
                        Some("e.g. `within: 1 %` or `within: 20 rpm`".into()),
                    );
                };
                let tolerance = self.tolerance(def, w);
                Some(Predicate::Near {
                    target: target?,
                    tolerance: tolerance?,
                })
            }
        }
    }

    /// The two ends of `between: [low, high]` (`example`: such a list); a list of another
    /// length is refused with `wrong_length`'s message for its length.
    pub(in crate::recipe::loader) fn between_ends<'n>(
        &mut self,
        node: &'n YamlNode,
        example: &str,
        wrong_length: impl FnOnce(usize) -> String,
    ) -> Option<(&'n YamlNode, &'n YamlNode)> {
        let YamlValue::Seq(bounds) = &node.value else {
            return self.refuse(
                &node.span,
                format!("between takes two values: `between: {example}`"),
                "expected [low, high]",
                None,
            );
        };
        let [low, high] = bounds.as_slice() else {
            return self.refuse(
                &node.span,
                wrong_length(bounds.len()),
                "expected [low, high]",
                None,
            );
        };
        Some((low, high))
    }

    /// `within`: a percentage of the target or an amount in the object's unit.
    fn tolerance(&mut self, def: &ObjectDef, node: &YamlNode) -> Option<Tolerance> {
        if self.r.refuse_non_finite(node, "`within`", FINITE_HELP) {
            return None;
        }
        let text = self.text(node, "`within`")?;
        let t = text.trim();
        if let Some(p) = t.strip_suffix('%') {
            return match p.trim().parse::<f64>() {
                Ok(v) if v.is_finite() && v >= 0.0 => Some(Tolerance::Percent(v)),
                _ => {
                    self.problem(
                        &node.span,
                        format!("`{t}` is not a percentage"),
                        "expected e.g. 1 %",
                        None,
                    );
                    None
                }
            };
        }
        let v = self.difference_for(def, node, "`within`")?;
        if v < 0.0 {
            return self.refuse(&node.span, "a tolerance cannot be negative", "negative", None);
        }
        Some(Tolerance::Absolute(v))
    }
}
