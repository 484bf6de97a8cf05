//! The `wait_until` step: exactly one condition (a state, a condition on an object's
//! value, or its stabilisation: `{ slope: { below: 0.5 K/min, over: 10 min } }`) with its
//! `timeout` and poll interval (`every`, also `poll`). It must not wait.

use crate::diag::{Shape, YamlNode};
use crate::recipe::loader::{did_you_mean, show_duration, Loader, DEFAULT_POLL, DEFAULT_WAIT_TIMEOUT};
use crate::recipe::step::StepKind;
use crate::session::Condition;

/// The keys of a `wait_until` besides its condition's object.
const WAIT_KEYS: &[&str] = &["timeout", "every", "poll", "state"];

/// The `wait_until` key a word that is no object was likely meant to be.
fn meant_key(word: &str) -> Option<String> {
    did_you_mean(word, WAIT_KEYS.iter().copied())
}

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn wait_until(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let shape =
            Shape::any_keys("`wait_until`").example("wait_until: { state: operation_enabled, timeout: 5 s }");
        let f = self.r.fields(body, &shape)?;
        let mut timeout = DEFAULT_WAIT_TIMEOUT;
        let mut every = DEFAULT_POLL;
        let mut conditions = Vec::new();
        let mut ok = true;
        for (k, v) in f.entries() {
            match k.value.as_str() {
                "timeout" => match self.duration(v, "timeout") {
                    Some(d) => timeout = d,
                    None => ok = false,
                },
                "every" | "poll" => match self.duration(v, "every") {
                    Some(d) => every = d,
                    None => ok = false,
                },
                "state" => match self.state(v, "`state`") {
                    Some(s) => conditions.push(Condition::State(s)),
                    None => ok = false,
                },
                // Any other key names an object, so a misspelt `timout` would be reported
                // as an unknown object with no word of the key that was meant.
                name if self.dict.get(name).is_none() && meant_key(name).is_some() => {
                    self.problem(
                        &k.span,
                        format!("unknown key `{name}` in this wait_until"),
                        "unknown key",
                        meant_key(name).map(|m| format!("did you mean `{m}`?")),
                    );
                    ok = false;
                }
                name => match self.object(name, &k.span) {
                    Some((def, r)) if self.readable(&def, &k.span) && v.get("slope").is_some() => {
                        match self.stable(&def, r, v) {
                            Some(c) => conditions.push(c),
                            None => ok = false,
                        }
                    }
                    Some((def, r)) if self.readable(&def, &k.span) => match self.predicate(&def, v) {
                        Some(p) => conditions.push(Condition::Value {
                            object: r,
                            predicate: p,
                        }),
                        None => ok = false,
                    },
                    _ => ok = false,
                },
            }
        }
        if !ok {
            return None;
        }
        if conditions.len() != 1 {
            return self.refuse(
                &body.span,
                format!(
                    "wait_until waits for exactly one condition, this has {}",
                    conditions.len()
                ),
                "one condition",
                Some("use two wait_until steps to wait for two things".into()),
            );
        }
        let condition = conditions.remove(0);
        let label = format!("wait until {condition} (timeout {})", show_duration(timeout));
        Some((
            StepKind::WaitUntil {
                condition,
                timeout,
                every,
            },
            label,
        ))
    }
}

impl Loader<'_, '_> {
    /// `{ slope: { below: 0.5 K/min, over: 10 min } }`: until the value is stable.
    fn stable(
        &mut self,
        def: &crate::dictionary::ObjectDef,
        r: crate::session::ObjectRef,
        v: &YamlNode,
    ) -> Option<Condition> {
        let node = v.get("slope")?;
        if v.entries().is_some_and(|e| e.len() > 1) {
            return self.refuse(
                &v.span,
                format!("a slope condition on {} stands alone", r.name),
                "one condition",
                Some("e.g. `motor_temperature: { slope: { below: 0.5 K/min, over: 10 min } }`".into()),
            );
        }
        let (over, condition) = self.slope_over(&r.name, node)?;
        let rate = self.measure_def(def, crate::session::Statistic::Slope(over), node)?;
        let predicate = self.predicate(&rate, &condition)?;
        Some(Condition::Stable {
            object: r,
            over,
            predicate,
            rate_unit: rate.unit.map(|u| u.symbol().to_string()).unwrap_or_default(),
        })
    }
}
