//! The `attempts` step: `{ times: 3, steps: [...] }`, its steps tried up to `times` times
//! until their checks pass (after re-homing, say). It must not run anything.

use crate::diag::{Shape, YamlNode};
use crate::recipe::loader::Loader;
use crate::recipe::step::StepKind;

/// The most attempts a step may make.
const MAX_ATTEMPTS: i64 = 100;

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn attempts(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let shape = Shape::new("these attempts", &["times", "steps", "on_failure", "watch"])
            .require(&["times", "steps"])
            .example("attempts: { times: 3, steps: [...] }");
        let f = self.r.fields(body, &shape)?;
        let times = f
            .get("times")
            .and_then(|n| self.r.int(n, "`times`", 1, MAX_ATTEMPTS));
        let steps = self.steps(f.get("steps")?, "`steps`");
        let times = u32::try_from(times?).ok()?;
        let label = format!("attempts: up to {times} times ({} steps)", steps.len());
        Some((StepKind::Attempts { times, steps }, label))
    }
}
