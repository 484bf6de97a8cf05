//! Every number a validated recipe writes to an object, with its place: set values and
//! ramp points, in the steps, repeats, includes, `on_fault` and `finally`. For checks
//! against limits learnt from the drive itself (the loader already checked the
//! dictionary's). Pure: it walks the recipe, never a drive.

use super::recipe::Recipe;
use super::step::{Step, StepKind};
use crate::session::{ObjectRef, SetValue, StepOrigin};

#[derive(Debug, Clone, PartialEq)]
pub struct WrittenValue {
    pub object: ObjectRef,
    /// In the object's engineering unit.
    pub value: f64,
    pub origin: StepOrigin,
    /// `set` or `ramp`.
    pub step: &'static str,
}

impl WrittenValue {
    /// ` rpm`: the object's unit with its leading space; empty without one.
    pub fn unit_text(&self) -> String {
        self.object
            .unit
            .as_deref()
            .map(|u| format!(" {u}"))
            .unwrap_or_default()
    }

    /// `recipe.yaml:6:5 set speed_setpoint = 30000 rpm`: where and what, for a refusal.
    pub fn described(&self) -> String {
        format!(
            "{}:{}:{}: {} {} = {}{}",
            self.origin.path,
            self.origin.line,
            self.origin.column,
            self.step,
            self.object.name,
            crate::session::number(self.value),
            self.unit_text()
        )
    }
}

/// The numbers `recipe` writes, in recipe order (a value inside a repeat once).
pub fn written_values(recipe: &Recipe) -> Vec<WrittenValue> {
    let mut out = Vec::new();
    let lists = [
        Some(recipe.steps.as_slice()),
        Some(recipe.on_fault.as_slice()),
        recipe.finally.as_deref(),
    ];
    for steps in lists.into_iter().flatten() {
        collect(steps, &mut out);
    }
    out
}

fn collect(steps: &[Step], out: &mut Vec<WrittenValue>) {
    for step in steps {
        match &step.kind {
            StepKind::Set(writes) => {
                for (object, value) in writes {
                    if let SetValue::Number(n) = value {
                        out.push(WrittenValue {
                            object: object.clone(),
                            value: n.value,
                            origin: step.origin.clone(),
                            step: "set",
                        });
                    }
                }
            }
            StepKind::Ramp { object, points, .. } => {
                // The extremes are enough: a ramp's points lie between them.
                let lowest = points.iter().copied().fold(f64::INFINITY, f64::min);
                let highest = points.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                for value in [lowest, highest].into_iter().filter(|v| v.is_finite()) {
                    out.push(WrittenValue {
                        object: object.clone(),
                        value,
                        origin: step.origin.clone(),
                        step: "ramp",
                    });
                }
            }
            StepKind::Repeat { steps, .. }
            | StepKind::Include { steps, .. }
            | StepKind::Attempts { steps, .. } => collect(steps, out),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dictionary::Dictionary;
    use std::path::Path;

    #[test]
    fn sets_and_ramp_extremes_everywhere_in_the_recipe() {
        let dictionary: Dictionary = crate::family::Registry::builtin().load_dictionary("sd2").unwrap();
        let text = "name: t\ndrive: sd2\nsteps:\n  - set: { speed_setpoint: 100 rpm }\n  - repeat:\n      times: 2\n      steps:\n        - ramp: { object: speed_setpoint, from: 200 rpm, to: 50 rpm, rate: 50 rpm/s }\nfinally:\n  - set: { speed_setpoint: 0 rpm }\n";
        let recipe =
            crate::recipe::load_recipe_text("t.yaml", text, Path::new("."), &dictionary, &[]).unwrap();
        let got: Vec<(f64, &str, u32)> = written_values(&recipe)
            .iter()
            .map(|w| (w.value, w.step, w.origin.line as u32))
            .collect();
        assert_eq!(
            got,
            vec![
                (100.0, "set", 4),
                (50.0, "ramp", 8),
                (200.0, "ramp", 8),
                (0.0, "set", 10)
            ]
        );
    }
}
