//! What a recipe will check and sample, known before it runs: its checks (`expect` checks
//! and `wait_until` conditions) with the stage that holds each, so reports can show the
//! ones a run never reached, and the objects its sample steps read, for the columns of a
//! wide CSV. Reads the validated recipe only.
//!
//! A check inside a `times: N` repeat is planned once per pass, with the stage the run
//! will give it (`repeat 2 times #2 / …`), so a report names a check the same whether the
//! run reached it or not. A repeat bounded by `for:` has an unknown number of passes: its
//! first pass (which always runs) is planned, later passes are named as they run.

use super::recipe::Recipe;
use super::step::{Step, StepKind};
use crate::session::{Condition, ObjectRef, PlannedCheck};

/// Every check of the recipe's steps in run order (a check inside a `times:` repeat once
/// per pass).
pub fn planned_checks(recipe: &Recipe) -> Vec<PlannedCheck> {
    let mut out = Vec::new();
    walk(&recipe.steps, "", &mut Vec::new(), &mut out);
    out
}

fn walk(steps: &[Step], prefix: &str, stage: &mut Vec<String>, out: &mut Vec<PlannedCheck>) {
    for (i, step) in steps.iter().enumerate() {
        // Numbered as the runner numbers steps.
        let number = match prefix {
            "" => format!("{}", i + 1),
            _ => format!("{prefix}.{}", i + 1),
        };
        match &step.kind {
            StepKind::Expect(checks) => {
                for c in checks {
                    out.push(PlannedCheck {
                        name: c.name.clone(),
                        object: Some(c.object.name.clone()),
                        statistic: c.statistic.map(|s| s.id().to_string()),
                        stage: stage.join(" / "),
                        step: number.clone(),
                        origin: step.origin.clone(),
                    });
                    if c.last_pass.is_some() {
                        out.push(PlannedCheck {
                            name: format!("{} compared with last pass", c.name),
                            object: None,
                            statistic: None,
                            stage: stage.join(" / "),
                            step: number.clone(),
                            origin: step.origin.clone(),
                        });
                    }
                }
            }
            StepKind::WaitUntil { condition, .. } => out.push(PlannedCheck {
                name: format!("wait until {condition}"),
                object: match condition {
                    Condition::Value { object, .. } | Condition::Stable { object, .. } => {
                        Some(object.name.clone())
                    }
                    Condition::State(_) => None,
                },
                statistic: None,
                stage: stage.join(" / "),
                step: number.clone(),
                origin: step.origin.clone(),
            }),
            StepKind::Ask(prompt) => out.push(PlannedCheck {
                name: prompt.text.clone(),
                object: None,
                statistic: None,
                stage: stage.join(" / "),
                step: number.clone(),
                origin: step.origin.clone(),
            }),
            StepKind::CoastDown(c) => out.push(PlannedCheck {
                name: c.check_name(),
                object: None,
                statistic: Some("coast_down".into()),
                stage: stage.join(" / "),
                step: number.clone(),
                origin: step.origin.clone(),
            }),
            StepKind::Repeat {
                times, steps: nested, ..
            } => {
                for pass in 1..=times.unwrap_or(1) {
                    stage.push(format!("{} #{pass}", step.label));
                    walk(nested, &number, stage, out);
                    stage.pop();
                }
            }
            // The first attempt always runs; later ones are named as they run.
            StepKind::Attempts { steps: nested, .. } => {
                stage.push(format!("{} #1", step.label));
                walk(nested, &number, stage, out);
                stage.pop();
            }
            StepKind::Include { steps: nested, .. } => {
                stage.push(step.label.clone());
                walk(nested, &number, stage, out);
                stage.pop();
            }
            _ => {}
        }
    }
}

/// The shortest interval any sample step of the recipe asks for (finally's too).
pub fn shortest_sample_interval(recipe: &Recipe) -> Option<std::time::Duration> {
    fn walk(steps: &[Step], out: &mut Option<std::time::Duration>) {
        for step in steps {
            match &step.kind {
                StepKind::Sample { every, .. } => *out = Some(out.map_or(*every, |o| o.min(*every))),
                StepKind::Repeat { steps, .. }
                | StepKind::Include { steps, .. }
                | StepKind::Attempts { steps, .. } => walk(steps, out),
                _ => {}
            }
        }
    }
    let mut out = None;
    walk(&recipe.steps, &mut out);
    walk(recipe.finally.as_deref().unwrap_or_default(), &mut out);
    out
}

/// The objects the recipe's sample steps read (finally's too), each once, in recipe order.
pub fn sampled_objects(recipe: &Recipe) -> Vec<ObjectRef> {
    fn walk(steps: &[Step], out: &mut Vec<ObjectRef>) {
        for step in steps {
            match &step.kind {
                StepKind::Sample { objects, .. } => {
                    for o in objects {
                        if !out.iter().any(|seen| seen.name == o.name) {
                            out.push(o.clone());
                        }
                    }
                }
                StepKind::Repeat { steps, .. }
                | StepKind::Include { steps, .. }
                | StepKind::Attempts { steps, .. } => walk(steps, out),
                _ => {}
            }
        }
    }
    let mut out = Vec::new();
    walk(&recipe.steps, &mut out);
    walk(recipe.finally.as_deref().unwrap_or_default(), &mut out);
    out
}

/// Every operator step of the recipe (its `finally` and `on_fault` too) with its place,
/// in the order written, each once: a run without a terminal needs an answer for each.
pub fn operator_prompts(recipe: &Recipe) -> Vec<(crate::session::Prompt, crate::session::StepOrigin)> {
    fn walk(steps: &[Step], out: &mut Vec<(crate::session::Prompt, crate::session::StepOrigin)>) {
        for step in steps {
            match &step.kind {
                StepKind::Ask(p) => out.push((p.clone(), step.origin.clone())),
                _ => walk(step.nested(), out),
            }
        }
    }
    let mut out = Vec::new();
    walk(&recipe.steps, &mut out);
    walk(recipe.finally.as_deref().unwrap_or_default(), &mut out);
    walk(&recipe.on_fault, &mut out);
    out
}

/// The checks that compare with the unit's last passed run, each name once, with where
/// the first of them writes `compared_with_last_pass`. (One in `finally` judges by what was
/// looked up before: the safe stop never waits for a store.)
pub fn last_pass_checks(recipe: &Recipe) -> (Vec<String>, Option<crate::session::StepOrigin>) {
    fn walk(steps: &[Step], names: &mut Vec<String>, first: &mut Option<crate::session::StepOrigin>) {
        for step in steps {
            if let StepKind::Expect(checks) = &step.kind {
                for (c, lp) in checks
                    .iter()
                    .filter_map(|c| c.last_pass.as_ref().map(|lp| (c, lp)))
                {
                    first.get_or_insert_with(|| lp.written.clone());
                    if !names.contains(&c.name) {
                        names.push(c.name.clone());
                    }
                }
            }
            walk(step.nested(), names, first);
        }
    }
    let (mut names, mut first) = (Vec::new(), None);
    walk(&recipe.steps, &mut names, &mut first);
    walk(
        recipe.finally.as_deref().unwrap_or_default(),
        &mut names,
        &mut first,
    );
    walk(&recipe.on_fault, &mut names, &mut first);
    (names, first)
}
