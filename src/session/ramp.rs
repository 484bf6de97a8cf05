//! `ramp`: write an object in steps from one value to another at a fixed period.

use super::session::{value_of, Session};
use super::stop::{nth_tick, Stop};
use super::{ObjectRef, SetValue};
use crate::dictionary::{Quantity, Unit};
use crate::drive::WriteOutcome;
use std::time::Duration;

impl Session<'_> {
    /// Writes `points` to `object`, one every `every`; nothing after a stop request.
    pub fn ramp(
        &mut self,
        object: &ObjectRef,
        points: &[f64],
        every: Duration,
        number: &str,
    ) -> Result<String, Stop> {
        let unit = object.unit.as_deref().and_then(Unit::from_symbol);
        let start = self.clock.now();
        let last = u32::try_from(points.len().saturating_sub(1)).unwrap_or(u32::MAX);
        let total = every.checked_mul(last).unwrap_or(Duration::MAX);
        // How many points the drive limited, and the warning of the last one.
        let mut limited: Option<(usize, String)> = None;
        for (i, p) in points.iter().enumerate() {
            let due = nth_tick(start, every, u32::try_from(i).unwrap_or(u32::MAX))?;
            self.wait(due)?;
            // Nothing more is written once a stop is requested, not even a point already
            // due: the next setpoint would be a step away from a standstill.
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.track_setpoint(object, *p);
            let name = self.select_object(&object.name)?;
            if let WriteOutcome::Limited(stored) = self.drive().write(name, &Quantity::new(*p, unit))? {
                let line = self.limited_warning(object, &SetValue::number(*p), stored);
                self.observer.message(&format!("warning: {line}"));
                limited = Some((limited.map_or(0, |(n, _)| n) + 1, line));
            }
            self.observer.step_progress(
                number,
                self.clock.now() - start,
                Some(total),
                &format!("{} = {}", object.name, value_of(*p, object)),
            );
            self.watch_fault(false)?;
        }
        Ok(match limited {
            None => format!("{} values written", points.len()),
            Some((n, last)) => format!(
                "{} values written; warning: {n} limited by the drive, the last: {last}",
                points.len()
            ),
        })
    }
}
