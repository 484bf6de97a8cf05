//! Comparing two parameter sets (a backup and the live drive, or two backups): objects
//! changed, missing from the second and extra in it, with both values; numbers within a
//! tolerance in the object's unit count as equal. Pure.

use super::parameter_file::{ParameterFile, Reading, SavedObject};
use crate::dictionary::Quantity;

#[derive(Debug, Clone, PartialEq)]
pub enum Difference {
    /// Both have the object with different values (or one could not read it).
    Changed {
        name: String,
        left: String,
        right: String,
    },
    /// Only the first has it.
    Missing { name: String, left: String },
    /// Only the second has it.
    Extra { name: String, right: String },
}

impl Difference {
    pub fn name(&self) -> &str {
        match self {
            Difference::Changed { name, .. }
            | Difference::Missing { name, .. }
            | Difference::Extra { name, .. } => name,
        }
    }
}

fn shown(o: &SavedObject) -> String {
    match &o.reading {
        Reading::Value { shown, raw } if shown.is_empty() => raw.clone(),
        Reading::Value { shown, .. } => shown.clone(),
        Reading::Error(e) => format!("unreadable ({e})"),
    }
}

/// Whether two readings of one object agree: the same raw value, or numbers of the same
/// unit no further apart than `tolerance` (in that unit); whole numbers apart exactly, so
/// that 64-bit counts a float cannot tell apart differ by their one count.
pub fn same(left: &SavedObject, right: &SavedObject, tolerance: f64) -> bool {
    match (&left.reading, &right.reading) {
        (Reading::Value { raw: a, shown: sa }, Reading::Value { raw: b, shown: sb }) => {
            if a == b {
                return true;
            }
            match (Quantity::parse(sa), Quantity::parse(sb)) {
                (Ok(x), Ok(y)) if x.unit == y.unit => match (x.whole(), y.whole()) {
                    (Some(m), Some(n)) => m.abs_diff(n) as f64 <= tolerance,
                    _ => (x.value - y.value).abs() <= tolerance,
                },
                _ => false,
            }
        }
        _ => false,
    }
}

/// Every difference, in the first set's order, then the second's extra objects.
pub fn compare(left: &ParameterFile, right: &ParameterFile, tolerance: f64) -> Vec<Difference> {
    let mut out = Vec::new();
    for l in &left.objects {
        match right.objects.iter().find(|r| r.name == l.name) {
            Some(r) if same(l, r, tolerance) => {}
            Some(r) => out.push(Difference::Changed {
                name: l.name.clone(),
                left: shown(l),
                right: shown(r),
            }),
            None => out.push(Difference::Missing {
                name: l.name.clone(),
                left: shown(l),
            }),
        }
    }
    for r in &right.objects {
        if !left.objects.iter().any(|l| l.name == r.name) {
            out.push(Difference::Extra {
                name: r.name.clone(),
                right: shown(r),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(objects: &[(&str, &str, &str)]) -> ParameterFile {
        ParameterFile {
            family: "sd2".into(),
            dictionary: "sd2".into(),
            address: String::new(),
            identity: vec![],
            date: String::new(),
            tool: String::new(),
            objects: objects
                .iter()
                .map(|(n, shown, raw)| SavedObject {
                    name: n.to_string(),
                    address: String::new(),
                    reading: if raw.is_empty() {
                        Reading::Error("no reply".into())
                    } else {
                        Reading::Value {
                            shown: shown.to_string(),
                            raw: raw.to_string(),
                        }
                    },
                })
                .collect(),
        }
    }

    #[test]
    fn changed_missing_and_extra_with_both_values() {
        let a = set(&[("a", "1", "1"), ("b", "6000 rpm", "6000000"), ("c", "5", "5")]);
        let b = set(&[("a", "1", "1"), ("b", "6001 rpm", "6001000"), ("d", "7", "7")]);
        assert_eq!(
            compare(&a, &b, 0.0),
            [
                Difference::Changed {
                    name: "b".into(),
                    left: "6000 rpm".into(),
                    right: "6001 rpm".into()
                },
                Difference::Missing {
                    name: "c".into(),
                    left: "5".into()
                },
                Difference::Extra {
                    name: "d".into(),
                    right: "7".into()
                },
            ]
        );
    }

    #[test]
    fn a_tolerance_in_the_unit_hides_small_differences_only() {
        let a = set(&[("b", "6000 rpm", "6000000")]);
        let b = set(&[("b", "6000.4 rpm", "6000400")]);
        assert!(compare(&a, &b, 0.5).is_empty());
        assert_eq!(compare(&a, &b, 0.1).len(), 1);
        let volts = set(&[("b", "6000.4 V", "6000400")]);
        assert_eq!(compare(&a, &volts, 1.0).len(), 1, "other units never match");
    }

    /// Whole numbers a float cannot tell apart (beyond 2^53) differ by their one count.
    #[test]
    fn sixty_four_bit_counts_differ_by_one() {
        let a = set(&[("c", "9007199254740993", "9007199254740993")]);
        let b = set(&[("c", "9007199254740992", "9007199254740992")]);
        assert_eq!(compare(&a, &b, 0.0).len(), 1);
        assert!(compare(&a, &b, 1.0).is_empty(), "a tolerance of one count");
        let max = set(&[("c", "9223372036854775807", "9223372036854775807")]);
        let near = set(&[("c", "9223372036854775806", "9223372036854775806")]);
        assert_eq!(compare(&max, &near, 0.0).len(), 1);
    }

    #[test]
    fn an_unreadable_object_is_a_difference() {
        let a = set(&[("a", "1", "1")]);
        let b = set(&[("a", "", "")]);
        let d = compare(&a, &b, 0.0);
        assert!(
            matches!(&d[0], Difference::Changed { right, .. } if right.contains("unreadable")),
            "{d:?}"
        );
    }
}
