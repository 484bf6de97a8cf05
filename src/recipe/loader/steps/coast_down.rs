//! The `coast_down` step: `{ from: 6000 rpm, below: 100 rpm, expect: { near: 20 s, within:
//! 1 s }, timeout: 2 min, every: 100 ms }` — the speeds in the actual speed's unit, the
//! check on the time in seconds, with its `warn:` band and `compared_with_last_pass:`
//! beside the condition in `expect:`; the step's `name:` names its check. It must not run
//! anything.

use super::last_pass::{Measured, KEY};
use crate::diag::{Shape, YamlNode};
use crate::dictionary::{Role, Unit};
use crate::recipe::loader::values::in_unit;
use crate::recipe::loader::{show_duration, Loader};
use crate::recipe::step::StepKind;
use crate::session::CoastDown;
use std::time::Duration;

/// How long a coast-down may take unless the recipe says.
pub(in crate::recipe) const DEFAULT_TIMEOUT: Duration = Duration::from_secs(10 * 60);
pub(in crate::recipe) const DEFAULT_EVERY: Duration = Duration::from_millis(100);

impl Loader<'_, '_> {
    /// `name`: the step's, which names its check (as an `expect`'s does).
    pub(in crate::recipe::loader) fn coast_down(
        &mut self,
        body: &YamlNode,
        name: Option<&str>,
    ) -> Option<(StepKind, String)> {
        let shape = Shape::new(
            "this coast_down",
            &["from", "below", "expect", "timeout", "every"],
        )
        .require(&["from", "below", "expect"])
        .example("coast_down: { from: 6000 rpm, below: 100 rpm, expect: { below: 30 s }, timeout: 2 min }");
        if let Some((key, _)) = body
            .entries()
            .and_then(|e| e.iter().find(|(k, _)| k.value == KEY))
        {
            return self.refuse(
                &key.span,
                format!(
                    "`{KEY}` compares the coast-down's time: write it in `expect:`, beside the condition"
                ),
                "not here",
                Some(format!(
                    "e.g. `expect: {{ above: 20 s, {KEY}: {{ at_least: -10 %, without_history: pass }} }}`"
                )),
            );
        }
        let f = self.r.fields(body, &shape)?;
        let Some(speed) = self.dict.role(Role::SpeedActual).cloned() else {
            return self.refuse(
                &body.span,
                "the drive's profile names no actual speed, so a coast-down cannot be timed",
                "no actual speed",
                None,
            );
        };
        let from = f
            .get("from")
            .and_then(|n| self.number_for(&speed, n, "`from`", false));
        let below = f
            .get("below")
            .and_then(|n| self.number_for(&speed, n, "`below`", false));
        let seconds = in_unit(&speed, Some(Unit::Second));
        let (predicate, warn, last_pass) = match f.get("expect") {
            Some(n) => {
                let (condition, last_pass_node) = Self::split_last_pass(n);
                let (condition, warn_node) = Self::split_warn(&condition);
                let predicate = self.predicate(&seconds, &condition);
                let warn = match (&predicate, &warn_node) {
                    (Some(p), Some(w)) => self.warn_band(&seconds, &condition, p, w).map(Some),
                    _ => Some(None),
                };
                let last_pass = match &last_pass_node {
                    Some((key, node)) => self.last_pass(&Measured::Object(&seconds), key, node).map(Some),
                    None => Some(None),
                };
                (predicate, warn, last_pass)
            }
            None => (None, None, None),
        };
        let timeout = match f.get("timeout") {
            Some(n) => self.duration(n, "timeout"),
            None => Some(DEFAULT_TIMEOUT),
        };
        let every = match f.get("every") {
            Some(n) => self.duration(n, "every"),
            None => Some(DEFAULT_EVERY),
        };
        let (from, below, predicate, warn, last_pass, timeout, every) =
            (from?, below?, predicate?, warn?, last_pass?, timeout?, every?);
        if below.abs() >= from.abs() {
            return self.refuse(
                f.span_of("below"),
                "a coast-down counts from a speed down past a lower one; `below` is not lower than `from`",
                "not below `from`",
                None,
            );
        }
        let c = CoastDown {
            name: name.map(str::to_string),
            from: from.abs(),
            below: below.abs(),
            predicate,
            warn,
            timeout,
            every,
            unit: speed.unit.map(|u| u.symbol().to_string()),
            last_pass,
        };
        let label = format!(
            "{} (power stage off, timeout {})",
            c.check_name(),
            show_duration(timeout)
        );
        Some((StepKind::CoastDown(c), label))
    }
}
