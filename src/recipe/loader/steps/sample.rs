//! The `sample` step: objects read every interval for a time (and an optional CSV file),
//! within the most samples one step may keep, and the setpoint step an object's response is
//! measured against (`step: { speed_actual: { to: 6000 rpm, band: 2 % } }`); remembers what
//! was sampled for `expect`. It must not sample.

use crate::diag::{Shape, YamlNode};
use crate::recipe::loader::{show_duration, Loader, MAX_SAMPLES};
use crate::recipe::step::StepKind;
use crate::session::Sampling;
use crate::session::{ObjectRef, StepSpec, DEFAULT_BAND_PERCENT};
use std::path::PathBuf;

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn sample(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let step = self.sample_step(body);
        self.sample_refused |= step.is_none();
        step
    }

    fn sample_step(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let shape = Shape::new("this sample", &["objects", "every", "for", "csv", "step"])
            .require(&["objects", "every", "for"])
            .example("sample: { objects: [speed_actual], every: 100 ms, for: 60 s }");
        let f = self.r.fields(body, &shape)?;
        let objects = f.get("objects").and_then(|n| self.object_list(n, "`objects`"));
        let every = f.get("every").and_then(|n| self.duration(n, "every"));
        let duration = f.get("for").and_then(|n| self.duration(n, "for"));
        let csv = match f.get("csv") {
            Some(n) => Some(PathBuf::from(self.text(n, "`csv`")?)),
            None => None,
        };
        let (objects, every, duration) = (objects?, every?, duration?);
        let steps = match f.get("step") {
            Some(n) => self.response_steps(n, &objects)?,
            None => Vec::new(),
        };
        if every > duration {
            return self.refuse(
                f.span_of("every"),
                format!(
                    "sampling every {} for {} takes no sample after the first",
                    show_duration(every),
                    show_duration(duration)
                ),
                "longer than `for`",
                None,
            );
        }
        let samples = duration.as_nanos() / every.as_nanos() + 1;
        if samples > u128::from(MAX_SAMPLES) {
            return self.refuse(
                f.span_of("every"),
                format!(
                    "sampling every {} for {} takes {samples} samples, more than {MAX_SAMPLES}",
                    show_duration(every),
                    show_duration(duration)
                ),
                "too often for so long",
                Some(
                    "sample less often (a larger `every`), or split the time into several sample steps"
                        .into(),
                ),
            );
        }
        for o in &objects {
            let stepped = steps.iter().any(|(name, _)| *name == o.name);
            self.sampled.insert(o.name.clone(), stepped);
        }
        let sampling = Sampling {
            objects,
            every,
            duration,
            csv,
        };
        let label = sampling.label();
        Some((StepKind::Sample { sampling, steps }, label))
    }
}

impl Loader<'_, '_> {
    /// `step: { OBJECT: { to: VALUE, from: VALUE, band: 2 % } }`: for each sampled object,
    /// the step its response is measured against.
    fn response_steps(&mut self, node: &YamlNode, objects: &[ObjectRef]) -> Option<Vec<(String, StepSpec)>> {
        let shape = Shape::any_keys("`step`").example("step: { speed_actual: { to: 6000 rpm, band: 2 % } }");
        self.per_object(node, &shape, |this, def, r, k, v| {
            if !objects.iter().any(|o| o.name == r.name) {
                return this.refuse(
                    &k.span,
                    format!("`step` names {}, which this sample does not read", r.name),
                    "not sampled here",
                    Some(format!("add {} to `objects`", r.name)),
                );
            }
            let shape = Shape::new("this step", &["to", "from", "band"])
                .require(&["to"])
                .example("{ to: 6000 rpm, band: 2 % }");
            let g = this.r.fields(v, &shape)?;
            let to = g.get("to").and_then(|n| this.number_for(&def, n, "`to`", false));
            let from = match g.get("from") {
                Some(n) => this.number_for(&def, n, "`from`", false).map(Some),
                None => Some(None),
            };
            let band = match g.get("band") {
                Some(n) => this.band_percent(n),
                None => Some(DEFAULT_BAND_PERCENT),
            };
            Some((
                r.name.clone(),
                StepSpec {
                    from: from?,
                    to: to?,
                    band_percent: band?,
                },
            ))
        })
    }

    /// A settling band in % of the step, above 0 and below 100.
    fn band_percent(&mut self, node: &YamlNode) -> Option<f64> {
        let text = self.text(node, "`band`")?;
        match text.trim().strip_suffix('%').map(|p| p.trim().parse::<f64>()) {
            Some(Ok(v)) if v > 0.0 && v < 100.0 => Some(v),
            _ => self.refuse(
                &node.span,
                format!("`band: {}` is not a share of the step", text.trim()),
                "expected e.g. 2 %",
                Some("the settling band is given in % of the step's size, above 0 and below 100".into()),
            ),
        }
    }
}
