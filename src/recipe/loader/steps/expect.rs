//! The `expect` step: checks on objects' values now, or on statistics of what an earlier
//! `sample` step sampled (`{ mean: { near: … } }`), each named for the report. It must not
//! evaluate the checks.

use super::last_pass::{self, Measured};
use crate::diag::{Shape, YamlNode};
use crate::recipe::loader::Loader;
use crate::recipe::step::StepKind;
use crate::session::{measured_key, Check, ObjectRef, Predicate, Statistic};

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn expect(
        &mut self,
        body: &YamlNode,
        name: Option<&str>,
    ) -> Option<(StepKind, String)> {
        let shape =
            Shape::any_keys("`expect`").example("expect: { speed_actual: { near: 6000 rpm, within: 1 % } }");
        // A step's name names its one check, or leads the names of its several checks.
        let single = body.entries().is_some_and(|e| e.len() == 1);
        let checks = self.per_object(body, &shape, |this, def, r, k, v| {
            if !this.readable(&def, &k.span) {
                return None;
            }
            // `{ mean: { near: ... } }` checks a statistic; `{ near: ... }` the value now.
            let (stat, pred_node) = match v.entries() {
                Some([(key, node)]) if Statistic::from_id(&key.value).is_some() => {
                    let found = this.statistic_of(&r, key, node)?;
                    (Some(found.0), found.1)
                }
                // `{ avg: { below: … } }`: a condition nested under a word that is no
                // statistic is a statistic misspelt, not a condition with an unknown key.
                Some([(key, node)]) if node.entries().is_some() && !Self::is_condition_key(&key.value) => {
                    this.unknown_statistic(key);
                    return None;
                }
                _ => (None, v.clone()),
            };
            let measured = match stat {
                Some(s) => this.measure_def(&def, s, &pred_node)?,
                None => def.clone(),
            };
            let r = match stat {
                Some(_) => ObjectRef {
                    unit: measured.unit.map(|u| u.symbol().to_string()),
                    ..r
                },
                None => r,
            };
            let (pred_node, last_pass_node) = Self::split_last_pass(&pred_node);
            let (pred_node, warn_node) = Self::split_warn(&pred_node);
            let predicate = this.predicate(&measured, &pred_node);
            let last_pass = match (&predicate, &last_pass_node) {
                (Some(Predicate::EqualsText(_)), Some((key, _))) => {
                    return this.refuse(
                        &key.span,
                        format!("`{}` compares numbers; {} is text", last_pass::KEY, def.name),
                        "not a number",
                        None,
                    );
                }
                (Some(_), Some((key, node))) => {
                    Some(this.last_pass(&Measured::Object(&measured), key, node)?)
                }
                _ => None,
            };
            let warn = match (&predicate, &warn_node) {
                (Some(p), Some(w)) => Some(this.warn_band(&measured, &pred_node, p, w)?),
                _ => None,
            };
            let p = predicate?;
            let stat_text = stat.map(|s| format!("{} ", s.id())).unwrap_or_default();
            let default_name = format!("{} {stat_text}{}", r.name, p.describe(r.unit.as_deref()));
            let default_key = measured_key(&r.name, stat.map(Statistic::id), &p);
            let (check_name, key) = match name {
                Some(n) if single => (n.to_string(), n.to_string()),
                Some(n) => (format!("{n}: {default_name}"), format!("{n}: {default_key}")),
                None => (default_name, default_key),
            };
            Some(Check {
                name: check_name,
                key,
                object: r,
                statistic: stat,
                predicate: p,
                warn,
                last_pass,
            })
        })?;
        let checks = self.not_empty(checks, body, "expect names no check", None)?;
        let label = format!(
            "expect {}",
            checks
                .iter()
                .map(|c| c.name.clone())
                .collect::<Vec<_>>()
                .join("; ")
        );
        Some((StepKind::Expect(checks), label))
    }
}
