//! `watch:` at the top of a recipe: limits that hold for the whole run, one object each
//! (`motor_temperature: { below: 80 °C }`, `current_actual: { below: 12 A, for: 2 s }`),
//! read `every` interval. Checked like `expect`'s conditions; it must not run anything.

use super::Loader;
use crate::diag::{YamlNode, YamlValue};
use crate::session::{Condition, Watch};
use std::time::Duration;

/// How often a watch reads its objects when the recipe names no `every`.
pub(in crate::recipe) const DEFAULT_WATCH_EVERY: Duration = Duration::from_secs(1);
/// The shortest interval: a watch must leave the line to the steps.
pub(in crate::recipe) const MIN_WATCH_EVERY: Duration = Duration::from_millis(50);

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn watch_section(&mut self, node: &YamlNode) -> Vec<Watch> {
        let Some(entries) = node.entries() else {
            self.problem(
                &node.span,
                "`watch` is a mapping of objects to limits",
                "expected a mapping",
                Some("e.g. `watch: { motor_temperature: { below: 80 °C }, every: 1 s }`".into()),
            );
            return Vec::new();
        };
        let mut every = DEFAULT_WATCH_EVERY;
        if let Some(n) = node.get("every") {
            match self.duration(n, "every") {
                Some(d) if d < MIN_WATCH_EVERY => {
                    self.problem(
                        &n.span,
                        format!(
                            "a watch reads at most every {} ms, so the steps keep the line",
                            MIN_WATCH_EVERY.as_millis()
                        ),
                        "too often",
                        Some("e.g. `every: 500 ms`".into()),
                    );
                }
                Some(d) => every = d,
                None => {}
            }
        }
        let mut out = Vec::new();
        for (k, v) in entries {
            if k.value == "every" {
                continue;
            }
            let origin = self.origin(&k.span);
            let Some((def, object)) = self.object(&k.value, &k.span) else {
                continue;
            };
            if !self.readable(&def, &k.span) {
                continue;
            }
            let hold = match v.get("for") {
                Some(n) => match self.duration(n, "for") {
                    Some(d) => d,
                    None => continue,
                },
                None => Duration::ZERO,
            };
            // The limit itself is read as `expect` reads one; `for` is the watch's own.
            let mut limit = v.clone();
            if let YamlValue::Map(entries) = &mut limit.value {
                entries.retain(|(key, _)| key.value != "for");
            }
            let Some(predicate) = self.predicate(&def, &limit) else {
                continue;
            };
            out.push(Watch {
                condition: Condition::Value { object, predicate },
                hold,
                every,
                origin,
            });
        }
        out
    }
}
