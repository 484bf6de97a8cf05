//! The `sample` step: objects read every interval for a time (and an optional CSV file),
//! within the most samples one step may keep; remembers what was sampled for `expect`. It
//! must not sample.

use crate::diag::{Shape, YamlNode};
use crate::recipe::loader::objects::names;
use crate::recipe::loader::{show_duration, Loader, MAX_SAMPLES};
use crate::recipe::step::StepKind;
use std::path::PathBuf;

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn sample(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let shape = Shape::new("this sample", &["objects", "every", "for", "csv"])
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
            self.sampled.insert(o.name.clone());
        }
        let label = format!(
            "sample {} every {} for {}",
            names(&objects),
            show_duration(every),
            show_duration(duration)
        );
        Some((
            StepKind::Sample {
                objects,
                every,
                duration,
                csv,
            },
            label,
        ))
    }
}
