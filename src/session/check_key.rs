//! The key a check keeps from run to run: what it measures, without its limits. A check is
//! the same check in every run when its object, statistic and kind of limit (`near`,
//! `below`, …) are the same, or when the recipe gave it the same name: a limit tightened
//! from `below: 5 A` to `below: 4.5 A` keeps the unit's history (the comparison with its
//! last passed run, `results trend`, JUnit's case names). Pure text; also reads the key
//! back out of a name stored before keys were.

use super::{Predicate, Statistic};

/// Ends the name and the key of a comparison with the unit's last passed run.
pub const COMPARED: &str = " compared with last pass";

/// Begins the name and the key of a wait.
pub const WAIT: &str = "wait until ";

/// `speed_actual mean near`: the key of a check named after what it measures
/// (`speed_actual mean near 6000 rpm ± 0.5 %`).
pub fn measured_key(object: &str, statistic: Option<&str>, predicate: &Predicate) -> String {
    match statistic {
        Some(s) => format!("{object} {s} {}", predicate.kind()),
        None => format!("{object} {}", predicate.kind()),
    }
}

/// The key of the comparison of the check keyed `key` with the unit's last passed run.
pub fn compared_key(key: &str) -> String {
    format!("{key}{COMPARED}")
}

/// The key of a check stored with its name only (written before keys were stored): the
/// name without its limits when it is one drivescript makes — `speed_actual mean near
/// 6000 rpm ± 0.5 %`, `wait until motor_temperature slope below 0.5 K/min over 10m`,
/// `coast-down from 6000 rpm below 100 rpm near 19.7 s ± 0.5 s`, `NAME: current_actual
/// max below 5 A` and their comparisons — with every limit a number (and unit) where it
/// belongs; `None` for any other name (a name the recipe gave, a question, a state), which
/// is its own key.
pub fn key_of_name(name: &str) -> Option<String> {
    if let Some(stem) = name.strip_suffix(COMPARED) {
        return key_of_name(stem).map(|k| compared_key(&k));
    }
    if let Some(key) = coast_down_key(name) {
        return Some(key);
    }
    let (wait, rest) = match name.strip_prefix(WAIT) {
        Some(rest) => (WAIT, rest),
        None => ("", name),
    };
    if let Some(key) = measured_key_of(rest, !wait.is_empty()) {
        return Some(format!("{wait}{key}"));
    }
    // `NAME: …`, a named expect of several checks: each keeps the name before its own.
    if wait.is_empty() {
        for (at, _) in name.match_indices(": ") {
            if let Some(key) = measured_key_of(&name[at + 2..], false) {
                return Some(format!("{}: {key}", &name[..at]));
            }
        }
    }
    None
}

/// `object [statistic] predicate` (a wait's slope with ` over DURATION` after it) → its key.
fn measured_key_of(text: &str, wait: bool) -> Option<String> {
    let words: Vec<&str> = text.split(' ').collect();
    let object = *words.first()?;
    if object.is_empty() || object.contains(':') {
        return None;
    }
    let statistic = words.get(1).copied().filter(|w| Statistic::from_id(w).is_some());
    let start = 1 + usize::from(statistic.is_some());
    let kind = *words.get(start)?;
    let used = predicate_words(&words[start..])?;
    let rest = &words[start + used..];
    let complete = match rest {
        [] => true,
        // `wait until x slope below 0.5 K/min over 10m` (`1h 30m`: several words).
        ["over", _, ..] => wait && statistic == Some(Statistic::SLOPE),
        _ => false,
    };
    complete.then(|| match statistic {
        Some(s) => format!("{object} {s} {kind}"),
        None => format!("{object} {kind}"),
    })
}

/// `coast-down from 6000 rpm below 100 rpm PREDICATE` → `coast-down from 6000 rpm below
/// 100 rpm`.
fn coast_down_key(name: &str) -> Option<String> {
    let words: Vec<&str> = name.split(' ').collect();
    if words.first() != Some(&"coast-down") || words.get(1) != Some(&"from") {
        return None;
    }
    let from = 2 + quantity_words(&words[2..])?;
    if words.get(from) != Some(&"below") {
        return None;
    }
    let below = from + 1 + quantity_words(&words[from + 1..])?;
    let used = predicate_words(&words[below..])?;
    (below + used == words.len()).then(|| words[..below].join(" "))
}

/// How many words a predicate as [`Predicate::describe`] writes it takes at the start of
/// `words`: `below 5 A`, `near 6000 rpm ± 0.5 %`, `between 1 and 2 s`, `equals "on"`.
fn predicate_words(words: &[&str]) -> Option<usize> {
    let after = &words.get(1..)?;
    let n = match *words.first()? {
        "above" | "below" => quantity_words(after)?,
        // Text: the rest of the name, in quotes.
        "equals" if after.first().is_some_and(|w| w.starts_with('"')) => {
            let text = after.join(" ");
            (text.len() > 1 && text.ends_with('"')).then_some(after.len())?
        }
        "equals" => quantity_words(after)?,
        "between" => {
            let low = quantity_words(after)?;
            (after.get(low) == Some(&"and")).then_some(())?;
            low + 1 + quantity_words(&after[low + 1..])?
        }
        "near" => {
            let target = quantity_words(after)?;
            (after.get(target) == Some(&"±")).then_some(())?;
            target + 1 + quantity_words(&after[target + 1..])?
        }
        _ => return None,
    };
    Some(1 + n)
}

/// A number, and its unit when one follows: how many words (1 or 2) at the start of
/// `words`.
fn quantity_words(words: &[&str]) -> Option<usize> {
    words.first()?.parse::<f64>().ok()?;
    let unit = words.get(1).is_some_and(|w| {
        !w.is_empty()
            && w.parse::<f64>().is_err()
            && !matches!(*w, "and" | "±" | "over" | "below")
            && Predicate::KINDS.iter().all(|k| k != w)
    });
    Some(1 + usize::from(unit))
}

/// The stage without the attempt number of an `attempts` block (`attempts: up to 3 times
/// (2 steps) #2` → `attempts: up to 3 times (2 steps)`); a repeat's iteration stays (its
/// passes are measurements of their own: cold and warm).
pub fn identity_stage(stage: &str) -> String {
    stage
        .split(" / ")
        .map(|part| match part.starts_with("attempts: ") {
            true => match part.rsplit_once(" #") {
                Some((label, n)) if n.parse::<u32>().is_ok() => label,
                _ => part,
            },
            false => part,
        })
        .collect::<Vec<_>>()
        .join(" / ")
}

/// `4[2].3[10].1` → `4.3.1`.
pub fn without_iterations(step: &str) -> String {
    let mut out = String::with_capacity(step.len());
    let mut depth = 0u32;
    for c in step.chars() {
        match c {
            '[' => depth += 1,
            ']' => depth = depth.saturating_sub(1),
            c if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::{CoastDown, Condition, ObjectRef, Tolerance};
    use proptest::prelude::*;
    use std::time::Duration;

    fn object(name: &str, unit: &str) -> ObjectRef {
        ObjectRef {
            name: name.into(),
            unit: Some(unit.into()),
        }
    }

    fn coast(predicate: Predicate, name: Option<&str>) -> CoastDown {
        CoastDown {
            name: name.map(str::to_string),
            from: 6000.0,
            below: 100.0,
            predicate,
            warn: None,
            timeout: Duration::from_secs(60),
            every: Duration::from_millis(100),
            unit: Some("rpm".into()),
            last_pass: None,
        }
    }

    #[test]
    fn a_key_leaves_out_the_limits_and_keeps_object_statistic_and_kind() {
        let near = Predicate::Near {
            target: 6000.0,
            tolerance: Tolerance::Percent(0.5),
        };
        assert_eq!(
            measured_key("speed_actual", Some("mean"), &near),
            "speed_actual mean near"
        );
        let tightened = [Predicate::Below(5.0), Predicate::Below(4.5)];
        let keys: Vec<String> = tightened
            .iter()
            .map(|p| measured_key("current_actual", Some("max"), p))
            .collect();
        assert_eq!(keys, ["current_actual max below", "current_actual max below"]);
        assert_ne!(
            measured_key("current_actual", Some("max"), &Predicate::Between(1.0, 5.0)),
            keys[0],
            "another kind of limit is another check"
        );
        // Step-response measures and a window's slope: their statistic stays.
        assert_eq!(
            measured_key("speed_actual", Some("rise_time"), &Predicate::Below(0.2)),
            "speed_actual rise_time below"
        );
        let stable = |limit: f64, over: u64| Condition::Stable {
            object: object("motor_temperature", "°C"),
            over: Duration::from_secs(over),
            predicate: Predicate::Below(limit),
            rate_unit: "K/min".into(),
        };
        assert_eq!(stable(0.5, 600).key(), "motor_temperature slope below");
        assert_eq!(stable(0.5, 600).key(), stable(0.2, 300).key());
        let value = Condition::Value {
            object: object("speed_actual", "rpm"),
            predicate: Predicate::Below(10.0),
        };
        assert_eq!(value.key(), "speed_actual below");
        let state = Condition::State(crate::drive::DeviceState::OperationEnabled);
        assert_eq!(state.key(), state.to_string());
    }

    #[test]
    fn a_coast_down_is_keyed_by_what_it_measures_or_by_its_given_name() {
        let c = coast(
            Predicate::Near {
                target: 19.7,
                tolerance: Tolerance::Absolute(0.5),
            },
            None,
        );
        assert_eq!(
            c.check_name(),
            "coast-down from 6000 rpm below 100 rpm near 19.7 s ± 0.5 s"
        );
        assert_eq!(c.check_key(), "coast-down from 6000 rpm below 100 rpm");
        assert_eq!(coast(Predicate::Above(15.0), None).check_key(), c.check_key());
        let named = coast(Predicate::Above(15.0), Some("spindle coast-down"));
        assert_eq!(
            (named.check_name(), named.check_key()),
            ("spindle coast-down".to_string(), "spindle coast-down".to_string())
        );
        assert_eq!(
            compared_key(&c.check_key()),
            "coast-down from 6000 rpm below 100 rpm compared with last pass"
        );
    }

    /// A stored name gives the key the check has when it is made now.
    #[test]
    fn a_stored_name_gives_the_key_its_check_has_now() {
        let cases = [
            (
                "speed_actual mean near 6000 rpm ± 0.5 %",
                Some("speed_actual mean near"),
            ),
            ("current_actual max below 5 A", Some("current_actual max below")),
            (
                "current_actual max below 5 A compared with last pass",
                Some("current_actual max below compared with last pass"),
            ),
            ("motor_temperature below 90 °C", Some("motor_temperature below")),
            ("speed_actual between -5 and 5", Some("speed_actual between")),
            ("status_text equals \"ready to run\"", Some("status_text equals")),
            (
                "motor_temperature near 60 °C ± 2 K",
                Some("motor_temperature near"),
            ),
            ("left.speed_actual above 100 rpm", Some("left.speed_actual above")),
            (
                "wait until speed_actual near 3000 rpm ± 1 %",
                Some("wait until speed_actual near"),
            ),
            (
                "wait until motor_temperature slope below 0.5 K/min over 1h 10m",
                Some("wait until motor_temperature slope below"),
            ),
            (
                "coast-down from 5900 rpm below 100 rpm above 10 s",
                Some("coast-down from 5900 rpm below 100 rpm"),
            ),
            (
                "coast-down from 5900 rpm below 100 rpm between 15 s and 60 s compared with last pass",
                Some("coast-down from 5900 rpm below 100 rpm compared with last pass"),
            ),
            (
                "Stage 2: current_actual mean below 5 A",
                Some("Stage 2: current_actual mean below"),
            ),
            // Names the recipe gave, questions and states are their own keys.
            ("bearing current at 18000 rpm", None),
            ("bearing current at 18000 rpm compared with last pass", None),
            ("Spindle is quiet", None),
            ("Motor above idle", None),
            ("Vibration on the hand-held meter", None),
            ("wait until state operation_enabled", None),
            ("parameter speed_limit", None),
            ("speed_actual mean near 6000 rpm ± 0.5 % today", None),
        ];
        for (name, key) in cases {
            assert_eq!(key_of_name(name).as_deref(), key, "{name}");
        }
    }

    #[test]
    fn a_stored_name_gives_the_same_key_as_the_check_made_now() {
        let speed = object("speed_actual", "rpm");
        let predicates = [
            Predicate::Equals(crate::dictionary::Quantity::new(3.0, None)),
            Predicate::Above(-1.5),
            Predicate::Below(0.001),
            Predicate::Between(10.0, 20.25),
            Predicate::Near {
                target: 60.0,
                tolerance: Tolerance::Absolute(2.0),
            },
            Predicate::Near {
                target: 6000.0,
                tolerance: Tolerance::Percent(1.0),
            },
        ];
        for p in &predicates {
            for stat in [None, Some("mean"), Some("settling_time")] {
                let name = match stat {
                    Some(s) => format!("{} {s} {}", speed.name, p.describe(speed.unit.as_deref())),
                    None => format!("{} {}", speed.name, p.describe(speed.unit.as_deref())),
                };
                let key = measured_key(&speed.name, stat, p);
                assert_eq!(key_of_name(&name), Some(key.clone()), "{name}");
                assert_eq!(
                    key_of_name(&format!("{name}{COMPARED}")),
                    Some(compared_key(&key))
                );
            }
            let wait = Condition::Value {
                object: speed.clone(),
                predicate: p.clone(),
            };
            assert_eq!(
                key_of_name(&format!("{WAIT}{wait}")),
                Some(format!("{WAIT}{}", wait.key()))
            );
            let c = coast(p.clone(), None);
            assert_eq!(key_of_name(&c.check_name()), Some(c.check_key()));
        }
    }

    /// A predicate of any kind with finite limits.
    fn any_predicate() -> impl Strategy<Value = Predicate> {
        let v = || prop_oneof![-1e6f64..1e6, (-1_000_000i64..1_000_000).prop_map(|n| n as f64)];
        prop_oneof![
            v().prop_map(|x| Predicate::Equals(crate::dictionary::Quantity::new(x, None))),
            v().prop_map(Predicate::Above),
            v().prop_map(Predicate::Below),
            (v(), v()).prop_map(|(a, b)| Predicate::Between(a, b)),
            (v(), 0.0f64..100.0, any::<bool>()).prop_map(|(target, t, percent)| Predicate::Near {
                target,
                tolerance: if percent {
                    Tolerance::Percent(t)
                } else {
                    Tolerance::Absolute(t)
                },
            }),
            "[a-z ]{0,12}".prop_map(Predicate::EqualsText),
        ]
    }

    proptest! {
        /// Whatever a store holds as a check's name, reading its key neither panics nor
        /// makes a key longer than the name.
        #[test]
        fn any_stored_name_reads_without_panic(name in "\\PC{0,80}") {
            if let Some(key) = key_of_name(&name) {
                prop_assert!(key.len() <= name.len() + COMPARED.len(), "{} → {}", name, key);
            }
        }

        /// Names as drivescript makes them, from words it writes, read without panic.
        #[test]
        fn names_of_its_own_words_read_without_panic(words in proptest::collection::vec(
            prop_oneof![
                Just("below"), Just("above"), Just("near"), Just("between"), Just("equals"),
                Just("and"), Just("±"), Just("over"), Just("5"), Just("-1.5"), Just("rpm"),
                Just("%"), Just("\""), Just("wait"), Just("until"), Just("coast-down"),
                Just("from"), Just("mean"), Just("slope"), Just("x:"), Just(""),
            ],
            0..12,
        ), compared in any::<bool>()) {
            let name = words.join(" ") + if compared { COMPARED } else { "" };
            let _ = key_of_name(&name);
        }

        /// The name of a check made now gives back the key it has now, for every kind of
        /// limit, statistic and unit.
        #[test]
        fn a_made_name_reads_back_its_key(
            object in "[a-z][a-z_]{0,12}(\\.[a-z_]{1,8})?",
            statistic in proptest::option::of(prop::sample::select(vec!["mean", "max", "ripple", "rise_time"])),
            unit in proptest::option::of(prop::sample::select(crate::dictionary::Unit::symbols().collect::<Vec<_>>())),
            predicate in any_predicate(),
        ) {
            let described = predicate.describe(unit);
            let name = match statistic {
                Some(s) => format!("{object} {s} {described}"),
                None => format!("{object} {described}"),
            };
            let key = measured_key(&object, statistic, &predicate);
            prop_assert_eq!(key_of_name(&name), Some(key.clone()), "{}", name);
            prop_assert_eq!(key_of_name(&format!("{name}{COMPARED}")), Some(compared_key(&key)));
        }
    }
}
