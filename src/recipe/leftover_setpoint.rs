//! Enables whose speed setpoint is a leftover: a setpoint written, then the drive disabled
//! (a `go_to` below operation enabled, a stop command), then enabled again without a new
//! setpoint — the spindle spins straight back to the old speed. `check` warns at the
//! enable's place. A coast-down leaves the setpoint at 0, so it clears what stood. Pure: it
//! walks the recipe's steps in order, never a drive.

use super::recipe::Recipe;
use super::step::{Step, StepKind};
use crate::drive::{DeviceCommand, DeviceState};
use crate::session::{number, SetValue, StepOrigin};

/// One enable that would start the spindle at a setpoint written before a disable.
#[derive(Debug, Clone, PartialEq)]
pub struct LeftoverSetpoint {
    /// The step that enables.
    pub enable: StepOrigin,
    /// The step that wrote the setpoint still standing.
    pub set: StepOrigin,
    /// The step that disabled the drive in between.
    pub disabled: StepOrigin,
    pub object: String,
    pub value: f64,
    pub unit: Option<String>,
}

impl std::fmt::Display for LeftoverSetpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let unit = self.unit.as_deref().map(|u| format!(" {u}")).unwrap_or_default();
        write!(
            f,
            "{}: this enable starts the drive at {} = {}{unit}, left standing from {} though the drive was disabled at {}; set the setpoint (0{unit}, or the speed wanted) right before enabling",
            self.enable,
            self.object,
            number(self.value),
            self.set,
            self.disabled
        )
    }
}

/// The enables of `recipe`'s steps whose setpoint (the object named `setpoint`, or
/// `drive.setpoint` for a named drive) is a leftover from before a disable.
pub fn leftover_setpoints(recipe: &Recipe, setpoint: &str) -> Vec<LeftoverSetpoint> {
    let mut walk = Walk {
        setpoint,
        standing: None,
        disabled: None,
        found: Vec::new(),
    };
    walk.steps(&recipe.steps);
    walk.found
}

struct Walk<'a> {
    setpoint: &'a str,
    /// The setpoint beyond 0 last written: value, unit, object and where.
    standing: Option<(f64, Option<String>, String, StepOrigin)>,
    /// Where the drive was disabled after it was written.
    disabled: Option<StepOrigin>,
    found: Vec<LeftoverSetpoint>,
}

impl Walk<'_> {
    fn is_setpoint(&self, name: &str) -> bool {
        name == self.setpoint || name.strip_suffix(self.setpoint).is_some_and(|d| d.ends_with('.'))
    }

    fn write(&mut self, name: &str, unit: &Option<String>, value: f64, at: &StepOrigin) {
        self.standing = (value != 0.0).then(|| (value, unit.clone(), name.to_string(), at.clone()));
        self.disabled = None;
    }

    fn disable(&mut self, at: &StepOrigin) {
        if self.standing.is_some() && self.disabled.is_none() {
            self.disabled = Some(at.clone());
        }
    }

    fn enable(&mut self, at: &StepOrigin) {
        if let (Some((value, unit, object, set)), Some(disabled)) = (&self.standing, self.disabled.take()) {
            self.found.push(LeftoverSetpoint {
                enable: at.clone(),
                set: set.clone(),
                disabled,
                object: object.clone(),
                value: *value,
                unit: unit.clone(),
            });
        }
    }

    fn steps(&mut self, steps: &[Step]) {
        for step in steps {
            let at = &step.origin;
            match &step.kind {
                StepKind::Set(writes) => {
                    for (object, value) in writes {
                        if let (true, SetValue::Number(n)) = (self.is_setpoint(&object.name), value) {
                            self.write(&object.name, &object.unit, n.value, at);
                        }
                    }
                }
                StepKind::Ramp { object, points, .. } if self.is_setpoint(&object.name) => {
                    if let Some(last) = points.last() {
                        self.write(&object.name, &object.unit, *last, at);
                    }
                }
                StepKind::GoTo {
                    state: DeviceState::OperationEnabled,
                    ..
                }
                | StepKind::Command(DeviceCommand::EnableOperation, _) => self.enable(at),
                StepKind::GoTo { .. }
                | StepKind::Command(
                    DeviceCommand::DisableOperation
                    | DeviceCommand::Shutdown
                    | DeviceCommand::DisableVoltage
                    | DeviceCommand::QuickStop,
                    _,
                ) => self.disable(at),
                // The coast-down disables and leaves the setpoint at 0.
                StepKind::CoastDown(_) => {
                    self.standing = None;
                    self.disabled = None;
                }
                _ => self.steps(step.nested()),
            }
        }
    }
}

#[cfg(test)]
#[path = "leftover_setpoint_tests.rs"]
mod tests;
