//! `expect_parameters`: the drive holds a backup's parameters, one check per object (the
//! object's live value against the saved one), feeding the same verdicts and reports as
//! `expect`. Reads only.

use super::session::Session;
use super::stop::Stop;
use super::{CheckResult, StepOrigin};
use crate::parameters::{raw_text, same, ParameterFile, Reading, SavedObject};

impl Session<'_> {
    pub fn expect_parameters(
        &mut self,
        file: &str,
        parameters: &ParameterFile,
        origin: &StepOrigin,
    ) -> Result<String, Stop> {
        let mut failed = Vec::new();
        for saved in &parameters.objects {
            let started = self.clock.now();
            let Reading::Value { shown: wanted, .. } = &saved.reading else {
                // Unreadable when the backup was taken: there is nothing to compare with.
                continue;
            };
            let value = self.drive().read(&saved.name)?;
            let live = SavedObject {
                name: saved.name.clone(),
                address: saved.address.clone(),
                reading: Reading::Value {
                    shown: value.to_string(),
                    raw: raw_text(&value.raw),
                },
            };
            let passed = same(saved, &live, 0.0);
            let message = if passed {
                format!("{} = {value} as in {file}", saved.name)
            } else {
                format!("{} = {value}, {file} holds {wanted}", saved.name)
            };
            if !passed {
                failed.push(message.clone());
            }
            // A parameter's check holds no limits: its name is its key.
            let name = format!("parameter {}", saved.name);
            let result = CheckResult {
                passed,
                measured: value.number(),
                measured_text: Some(value.to_string()),
                unit: value.unit().map(|u| u.symbol().to_string()),
                object: Some(saved.name.clone()),
                message,
                ..self.check_now(name.clone(), name, origin, started)
            };
            self.record_check_result(result);
        }
        if failed.is_empty() {
            Ok(format!("{} parameter(s) as in {file}", parameters.objects.len()))
        } else {
            self.failed_checks = true;
            Ok(format!("FAILED: {}", failed.join("; ")))
        }
    }
}
