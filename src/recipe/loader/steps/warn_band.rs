//! `warn:` on an `expect` condition: a narrower band inside the limits, written in the
//! shape of the condition it narrows (`{ near: 6000 rpm, within: 1 %, warn: 0.5 % }`, `{
//! below: 80 °C, warn: 70 °C }`, `{ between: [a, b], warn: [c, d] }`); a pass outside it is
//! marginal. It must not evaluate anything.

use crate::diag::{Spanned, YamlNode, YamlValue};
use crate::dictionary::ObjectDef;
use crate::recipe::loader::Loader;
use crate::session::Predicate;

impl Loader<'_, '_> {
    /// `node` without its `warn` entry, and that entry.
    pub(in crate::recipe::loader) fn split_warn(node: &YamlNode) -> (YamlNode, Option<YamlNode>) {
        let YamlValue::Map(entries) = &node.value else {
            return (node.clone(), None);
        };
        let warn = entries
            .iter()
            .find(|(k, _)| k.value == "warn")
            .map(|(_, v)| v.clone());
        (node.without("warn"), warn)
    }

    /// The warning band `warn` gives `pass` (parsed against `def`, the condition's own
    /// node `condition`), refused unless it lies within the limits.
    pub(in crate::recipe::loader) fn warn_band(
        &mut self,
        def: &ObjectDef,
        condition: &YamlNode,
        pass: &Predicate,
        warn: &YamlNode,
    ) -> Option<Predicate> {
        let key = |k: &str| Spanned {
            value: k.to_string(),
            span: warn.span.clone(),
        };
        let entries = match pass {
            Predicate::Near { .. } => vec![
                (key("near"), condition.get("near")?.clone()),
                (key("within"), warn.clone()),
            ],
            Predicate::Above(_) => vec![(key("above"), warn.clone())],
            Predicate::Below(_) => vec![(key("below"), warn.clone())],
            Predicate::Between(..) => vec![(key("between"), warn.clone())],
            Predicate::Equals(_) | Predicate::EqualsText(_) => {
                return self.refuse(
                    &warn.span,
                    "`warn` narrows a band; `equals` has none",
                    "nothing to narrow",
                    Some("use `near` with `within` and `warn`".into()),
                );
            }
        };
        let band = self.predicate(
            def,
            &YamlNode {
                value: YamlValue::Map(entries),
                span: warn.span.clone(),
            },
        )?;
        let (lo, hi) = pass.limits();
        let (wlo, whi) = band.limits();
        let inside =
            lo.is_none_or(|l| wlo.is_some_and(|w| w >= l)) && hi.is_none_or(|h| whi.is_some_and(|w| w <= h));
        if !inside {
            return self.refuse(
                &warn.span,
                format!(
                    "the warning band {} is not inside the limits {}",
                    band.describe(def.unit.map(|u| u.symbol())),
                    pass.describe(def.unit.map(|u| u.symbol()))
                ),
                "wider than the limits",
                Some(
                    "a warning band is narrower than the check: a pass outside it is marked marginal".into(),
                ),
            );
        }
        Some(band)
    }
}
