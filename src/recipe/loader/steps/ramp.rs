//! The `ramp` step: an object written from one value to another in steps (`step`) or at a
//! rate per second (`rate: 1000 rpm/s`), every interval; the points are computed here and
//! bounded in number. It must not write anything.

use crate::diag::{Shape, YamlNode, YamlValue};
use crate::dictionary::ObjectDef;
use crate::recipe::loader::{show_duration, Loader, DEFAULT_RAMP_EVERY};
use crate::recipe::step::StepKind;

/// A ramp of more points than this is almost certainly a typo in its step.
const MAX_RAMP_POINTS: usize = 100_000;

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn ramp(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let shape = Shape::new("this ramp", &["object", "from", "to", "step", "rate", "every"])
            .require(&["object", "from", "to"])
            .example("ramp: { object: speed_setpoint, from: 0 rpm, to: 6000 rpm, rate: 1000 rpm/s }");
        let f = self.r.fields(body, &shape)?;
        let obj_node = f.get("object")?;
        let obj_name = self.r.scalar_text(obj_node, "`object`")?;
        let (def, r) = self.object(&obj_name, &obj_node.span)?;
        if !self.writable(&def, &obj_node.span, "ramped") {
            return None;
        }
        let from = f
            .get("from")
            .and_then(|n| self.number_for(&def, n, "`from`", true));
        let to = f.get("to").and_then(|n| self.number_for(&def, n, "`to`", true));
        let every = match f.get("every") {
            Some(n) => self.duration(n, "every"),
            None => Some(DEFAULT_RAMP_EVERY),
        };
        let step_size = match (f.get("step"), f.get("rate")) {
            (Some(_), Some(rate)) => {
                self.problem(
                    &rate.span,
                    "give either `step` or `rate`, not both",
                    "both given",
                    None,
                );
                None
            }
            (Some(s), None) => self.number_for(&def, s, "`step`", false).map(f64::abs),
            (None, Some(rate)) => self
                .rate(&def, rate)
                .and_then(|per_s| every.map(|e| per_s * e.as_secs_f64())),
            (None, None) => {
                self.problem(
                    &body.span,
                    "a ramp needs `step` (how much each write changes) or `rate` (per second)",
                    "step or rate missing",
                    Some("e.g. `rate: 1000 rpm/s` or `step: 500 rpm`".into()),
                );
                None
            }
        };
        let (from, to, every, step_size) = (from?, to?, every?, step_size?);
        if !step_size.is_finite() {
            return self.refuse(
                &body.span,
                "the ramp's step or rate is too large to be a number",
                "not finite",
                None,
            );
        }
        if step_size <= 0.0 {
            return self.refuse(
                &body.span,
                "the ramp's step or rate must be more than zero",
                "zero step",
                None,
            );
        }
        let n = ((to - from).abs() / step_size).ceil() as usize;
        if n > MAX_RAMP_POINTS {
            return self.refuse(
                &body.span,
                format!("this ramp would write {n} values; make the step larger"),
                "too many steps",
                None,
            );
        }
        let dir = if to >= from { 1.0 } else { -1.0 };
        let mut points: Vec<f64> = (0..n).map(|i| from + dir * step_size * i as f64).collect();
        points.push(to);
        let u = r.unit.clone().map(|u| format!(" {u}")).unwrap_or_default();
        let label = format!(
            "ramp {} from {}{u} to {}{u} in {} steps every {}",
            r.name,
            crate::session::number(from),
            crate::session::number(to),
            points.len(),
            show_duration(every)
        );
        Some((
            StepKind::Ramp {
                object: r,
                points,
                every,
            },
            label,
        ))
    }

    /// `1000 rpm/s` → 1000 (object units per second).
    fn rate(&mut self, def: &ObjectDef, node: &YamlNode) -> Option<f64> {
        let text = self.text(node, "`rate`")?;
        let Some((amount, per)) = text.rsplit_once('/') else {
            return self.refuse(
                &node.span,
                format!("`{text}` is not a rate"),
                "expected e.g. 1000 rpm/s",
                None,
            );
        };
        let seconds = match per.trim() {
            "s" => 1.0,
            "min" => 60.0,
            "ms" => 0.001,
            "h" => 3600.0,
            other => {
                return self.refuse(
                    &node.span,
                    format!("`/{other}`: a rate is per s, min, ms or h"),
                    "unknown time unit",
                    None,
                );
            }
        };
        let amount_node = YamlNode {
            value: YamlValue::Str(amount.trim().to_string()),
            span: node.span.clone(),
        };
        self.number_for(def, &amount_node, "`rate`", false)
            .map(|v| v.abs() / seconds)
    }
}
