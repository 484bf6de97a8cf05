//! `compared_with_last_pass` on a check — an `expect` condition, a `coast_down`'s `expect`,
//! an `enter_value` — how far the value may move from the same check in the unit's last
//! passed run of this recipe (`{ at_most: 10 %, at_least: -5 %, without_history: pass }`;
//! relative in %, or absolute in the unit a difference of the check's values is written
//! in), and what a run with no earlier pass does. It must not look anything up.

use crate::diag::{Shape, Spanned, YamlNode, YamlValue};
use crate::dictionary::{ObjectDef, Unit};
use crate::recipe::loader::Loader;
use crate::session::LastPass;

/// The key, as recipes write it.
pub(in crate::recipe) const KEY: &str = "compared_with_last_pass";

/// What the check measures, for the absolute ends of a change: a difference of its values.
pub(in crate::recipe::loader) enum Measured<'d> {
    /// An object's values, or a quantity derived from them (a statistic, a coast-down's
    /// time): K for one in °C.
    Object(&'d ObjectDef),
    /// A value the operator types in this unit (`mm`, `µm` too; none: a bare number).
    Typed(Option<Unit>),
}

impl Loader<'_, '_> {
    /// `node` without its `compared_with_last_pass` entry, and that entry (key and value).
    pub(in crate::recipe::loader) fn split_last_pass(
        node: &YamlNode,
    ) -> (YamlNode, Option<(Spanned<String>, YamlNode)>) {
        let YamlValue::Map(entries) = &node.value else {
            return (node.clone(), None);
        };
        let found = entries.iter().find(|(k, _)| k.value == KEY).cloned();
        (node.without(KEY), found)
    }

    /// The comparison written at `key: node` for a check on `measured`.
    pub(in crate::recipe::loader) fn last_pass(
        &mut self,
        measured: &Measured,
        key: &Spanned<String>,
        node: &YamlNode,
    ) -> Option<LastPass> {
        let what = format!("`{KEY}`");
        let shape = Shape::new(&what, &["at_most", "at_least", "without_history"])
            .require(&["without_history"])
            .example("compared_with_last_pass: { at_most: 10 %, at_least: -5 %, without_history: pass }");
        let f = self.r.fields(node, &shape)?;
        let without = f.get("without_history")?;
        let pass_without_history = match self.text(without, "`without_history`")?.trim() {
            "pass" => Some(true),
            "fail" => Some(false),
            other => self.refuse(
                &without.span,
                format!("`without_history: {other}`: a run with no earlier pass of the unit passes or fails this check"),
                "expected pass or fail",
                Some("`pass` lets a unit's first run through; `fail` insists on an earlier pass".into()),
            ),
        };
        let mut ends = Vec::new();
        let mut ok = pass_without_history.is_some();
        for end in ["at_least", "at_most"] {
            match f.get(end) {
                Some(n) => match self.change(measured, n, end) {
                    Some(c) => ends.push((end, Some(c), n.span.clone())),
                    None => ok = false,
                },
                None => ends.push((end, None, node.span.clone())),
            }
        }
        if !ok {
            return None;
        }
        let [(_, low, _), (_, high, high_span)] = ends.as_slice() else {
            return None;
        };
        let relative = match (low, high) {
            (None, None) => {
                return self.refuse(
                    &node.span,
                    format!("`{KEY}` needs `at_most`, `at_least` or both: how far the value may move"),
                    "no change given",
                    Some("e.g. `at_most: 10 %` (of the last pass's value) or `at_most: 0.5 A`".into()),
                )
            }
            (Some((_, a)), Some((_, b))) if a != b => {
                return self.refuse(
                    high_span,
                    "`at_least` and `at_most` are both in % (of the last pass's value) or both in the check's unit",
                    "one in %, one not",
                    None,
                )
            }
            (Some((_, r)), _) | (_, Some((_, r))) => *r,
        };
        let (at_least, at_most) = (low.map(|(v, _)| v), high.map(|(v, _)| v));
        if let (Some(l), Some(h)) = (at_least, at_most) {
            if l > h {
                return self.refuse(
                    high_span,
                    format!(
                        "`at_most` ({}) is below `at_least` ({}): no value could pass",
                        crate::session::number(h),
                        crate::session::number(l)
                    ),
                    "below at_least",
                    None,
                );
            }
        }
        Some(LastPass {
            at_least,
            at_most,
            relative,
            pass_without_history: pass_without_history?,
            written: self.origin(&key.span),
        })
    }

    /// One end of the change: `10 %` (relative: true) or a difference in the check's unit.
    fn change(&mut self, measured: &Measured, node: &YamlNode, end: &str) -> Option<(f64, bool)> {
        let what = format!("`{end}`");
        if self
            .r
            .refuse_non_finite(node, &what, crate::recipe::loader::values::FINITE_HELP)
        {
            return None;
        }
        let text = self.text(node, &what)?;
        if let Some(p) = text.trim().strip_suffix('%') {
            return match p.trim().parse::<f64>() {
                Ok(v) if v.is_finite() => Some((v, true)),
                _ => self.refuse(
                    &node.span,
                    format!("`{}` is not a percentage", text.trim()),
                    "expected e.g. 10 % or -5 %",
                    None,
                ),
            };
        }
        match measured {
            Measured::Object(def) => self.difference_for(def, node, &what),
            Measured::Typed(unit) => self.limit_in(node, unit.map(Unit::difference), end),
        }
        .map(|v| (v, false))
    }
}
