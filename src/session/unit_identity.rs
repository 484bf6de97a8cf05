//! What a run tested and who tested it: the unit's serial and part number, the operator and
//! the station. Plain data the reports, the console and the results store show alike; it
//! says nothing of where a value came from (the command line or an operator's answer).

use serde::{Deserialize, Serialize};
use std::fmt;

/// The unit under test and the run's people and place; any part may be unknown. The
/// results store keeps it as it is (its spool lines are this type's JSON).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct UnitIdentity {
    pub serial: Option<String>,
    pub part: Option<String>,
    pub operator: Option<String>,
    pub station: Option<String>,
}

/// The names a user writes for each part (`--unit serial=SP-104233`), in display order.
pub const UNIT_FIELDS: [&str; 4] = ["serial", "part", "operator", "station"];

impl UnitIdentity {
    /// Whether nothing is known: reports then leave the identity out.
    pub fn is_empty(&self) -> bool {
        self.fields().next().is_none()
    }

    /// The known parts as (name, value), in [`UNIT_FIELDS`] order.
    pub fn fields(&self) -> impl Iterator<Item = (&'static str, &str)> {
        UNIT_FIELDS
            .into_iter()
            .zip([&self.serial, &self.part, &self.operator, &self.station])
            .filter_map(|(name, value)| value.as_deref().map(|v| (name, v)))
    }

    /// The part called `name` where it is known.
    pub fn field(&self, name: &str) -> Option<&str> {
        self.fields().find(|(n, _)| *n == name).map(|(_, v)| v)
    }

    /// The part called `name`, for filling it in from a command line or an answer; `None`
    /// for a name that is not one of [`UNIT_FIELDS`].
    pub fn field_mut(&mut self, name: &str) -> Option<&mut Option<String>> {
        match name {
            "serial" => Some(&mut self.serial),
            "part" => Some(&mut self.part),
            "operator" => Some(&mut self.operator),
            "station" => Some(&mut self.station),
            _ => None,
        }
    }
}

impl fmt::Display for UnitIdentity {
    /// `serial SP-104233, operator J. Smith`: one line for a console header.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, (name, value)) in self.fields().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{name} {value}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shows_only_the_known_parts_in_order() {
        let mut unit = UnitIdentity::default();
        assert!(unit.is_empty());
        *unit.field_mut("operator").unwrap() = Some("J. Smith".into());
        *unit.field_mut("serial").unwrap() = Some("SP-104233".into());
        assert!(!unit.is_empty());
        assert_eq!(unit.to_string(), "serial SP-104233, operator J. Smith");
        assert!(unit.field_mut("colour").is_none());
        assert_eq!(unit.field("serial"), Some("SP-104233"));
        assert_eq!(unit.field("part"), None);
    }
}
