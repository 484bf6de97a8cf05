//! The checks a recipe holds (`expect` checks and `wait_until` conditions of its steps),
//! with the stage that holds each, so reports can show the ones a run never reached.
//! Reads the validated recipe only.

use super::recipe::Recipe;
use super::step::{Step, StepKind};
use crate::session::{Condition, PlannedCheck};

/// Every check of the recipe's steps in recipe order (a check inside a repeat once).
pub fn planned_checks(recipe: &Recipe) -> Vec<PlannedCheck> {
    let mut out = Vec::new();
    walk(&recipe.steps, &mut Vec::new(), &mut out);
    out
}

fn walk(steps: &[Step], stage: &mut Vec<String>, out: &mut Vec<PlannedCheck>) {
    for step in steps {
        match &step.kind {
            StepKind::Expect(checks) => {
                for c in checks {
                    out.push(PlannedCheck {
                        name: c.name.clone(),
                        object: Some(c.object.name.clone()),
                        statistic: c.statistic.map(|s| s.id().to_string()),
                        stage: stage.join(" / "),
                        origin: step.origin.clone(),
                    });
                }
            }
            StepKind::WaitUntil { condition, .. } => out.push(PlannedCheck {
                name: format!("wait until {condition}"),
                object: match condition {
                    Condition::Value { object, .. } => Some(object.name.clone()),
                    Condition::State(_) => None,
                },
                statistic: None,
                stage: stage.join(" / "),
                origin: step.origin.clone(),
            }),
            StepKind::Repeat { steps: nested, .. } | StepKind::Include { steps: nested, .. } => {
                stage.push(step.label.clone());
                walk(nested, stage, out);
                stage.pop();
            }
            _ => {}
        }
    }
}
