//! Where in the run the current step is: the steps that hold it (repeat, include) with
//! their repeat iteration, so every report can name a step by an id that differs between
//! iterations (`4[2].1`: step 1 of the 2nd iteration of step 4) and group checks by the
//! stage that holds them. Plain bookkeeping; knows no drive and no output format.

use super::StepInfo;
use std::fmt::Write as _;

#[derive(Debug, Clone)]
struct Frame {
    number: String,
    label: String,
    container: bool,
    iteration: Option<u32>,
}

/// The chain of steps from the top level to the one that runs now.
#[derive(Debug, Clone, Default)]
pub struct StepPath {
    frames: Vec<Frame>,
}

impl StepPath {
    /// A step starts; it becomes the current one until [`StepPath::leave`].
    pub fn enter(&mut self, step: &StepInfo) {
        self.frames.push(Frame {
            number: step.number.clone(),
            // Only containers name a stage; the label of any other step is never asked for.
            label: match step.container {
                true => step.label.clone(),
                false => String::new(),
            },
            container: step.container,
            iteration: None,
        });
    }

    /// The current step has ended.
    pub fn leave(&mut self) {
        self.frames.pop();
    }

    /// The current step (a repeat) begins its `n`th iteration (from 1).
    pub fn iteration(&mut self, n: u32) {
        if let Some(f) = self.frames.last_mut() {
            f.iteration = Some(n);
        }
    }

    /// The current step's id: its number with the iteration of every repeat around it,
    /// `4[2].1`; the plain number outside repeats. Empty outside any step.
    pub fn id(&self) -> String {
        let mut id = String::new();
        let mut parent: Option<&Frame> = None;
        for f in &self.frames {
            match parent {
                None => id.push_str(&f.number),
                Some(p) => {
                    if let Some(n) = p.iteration {
                        let _ = write!(id, "[{n}]");
                    }
                    let own = f.number.rsplit('.').next().unwrap_or(&f.number);
                    id.push('.');
                    id.push_str(own);
                }
            }
            parent = Some(f);
        }
        id
    }

    /// The steps that hold the current one, outermost first, each with its iteration:
    /// `Stage 2, 12000 rpm / repeat 2 times #2`. Empty at the top level.
    pub fn stage(&self) -> String {
        let held = self.frames.len().saturating_sub(1);
        self.frames[..held]
            .iter()
            .filter(|f| f.container)
            .map(|f| match f.iteration {
                Some(n) => format!("{} #{n}", f.label),
                None => f.label.clone(),
            })
            .collect::<Vec<_>>()
            .join(" / ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::StepOrigin;

    fn step(number: &str, label: &str, container: bool) -> StepInfo {
        StepInfo {
            number: number.into(),
            label: label.into(),
            origin: StepOrigin {
                path: "r.yaml".into(),
                line: 1,
                column: 1,
            },
            phase: "steps",
            container,
        }
    }

    #[test]
    fn ids_carry_the_iteration_of_every_repeat_around_them() {
        let mut p = StepPath::default();
        p.enter(&step("2", "expect", false));
        assert_eq!((p.id(), p.stage()), ("2".into(), String::new()));
        p.leave();
        p.enter(&step("4", "repeat 2 times", true));
        assert_eq!(p.id(), "4");
        for n in 1..=2 {
            p.iteration(n);
            p.enter(&step("4.1", "Stage", true));
            p.enter(&step("4.1.3", "expect", false));
            assert_eq!(p.id(), format!("4[{n}].1.3"));
            assert_eq!(p.stage(), format!("repeat 2 times #{n} / Stage"));
            p.leave();
            p.leave();
        }
        p.leave();
        p.enter(&step("finally.1", "shutdown", false));
        assert_eq!(p.id(), "finally.1");
    }
}
