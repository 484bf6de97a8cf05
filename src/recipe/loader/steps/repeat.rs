//! The `repeat` step: its steps run a number of `times` or `for` a time (then at least one
//! of them must take time, or it would never end). It must not run anything.

use crate::diag::{Shape, YamlNode};
use crate::recipe::loader::{show_duration, Loader};
use crate::recipe::step::{Step, StepKind};

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn repeat(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let shape = Shape::new("this repeat", &["times", "for", "steps", "on_failure", "watch"])
            .require(&["steps"])
            .example("repeat: { times: 3, steps: [...] }");
        let f = self.r.fields(body, &shape)?;
        let times = match f.get("times") {
            Some(n) => Some(u32::try_from(self.r.int(n, "`times`", 1, u32::MAX.into())?).ok()?),
            None => None,
        };
        let duration = match f.get("for") {
            Some(n) => Some(self.duration(n, "for")?),
            None => None,
        };
        if times.is_none() && duration.is_none() {
            return self.refuse(
                &body.span,
                "repeat needs `times` or `for`",
                "how often?",
                Some("e.g. `times: 3` or `for: 2 h`".into()),
            );
        }
        if times.is_some() && duration.is_some() {
            return self.refuse(
                &body.span,
                "give repeat either `times` or `for`, not both",
                "both given",
                None,
            );
        }
        let steps = self.steps(f.get("steps")?, "`steps`");
        if duration.is_some() && !steps.iter().any(Step::takes_time) {
            return self.refuse(
                f.span_of("for"),
                "`repeat` with `for` needs a step that takes time (a wait, dwell, sample, ramp or drive access); these steps take none, so it would never end",
                "nothing takes time",
                Some("use `times` to repeat them a number of times".into()),
            );
        }
        let label = match (times, duration) {
            (Some(t), _) => format!("repeat {t} times ({} steps)", steps.len()),
            (_, Some(d)) => format!("repeat for {} ({} steps)", show_duration(d), steps.len()),
            _ => "repeat".into(),
        };
        Some((
            StepKind::Repeat {
                times,
                duration,
                steps,
            },
            label,
        ))
    }
}
