//! `d.watch("motor_temperature", #{ below: "80 °C", for: "2 s", every: "1 s" })`: a recipe's
//! `watch:` in a script, held from the call until the script's steps end. The limit is
//! resolved against the dictionary by [`watch_of`] — the same rules for `check` (on
//! literals) and for the running script; the session reads and judges it. It must not
//! read the drive itself.

use super::bridge::{Bridge, RhaiResult};
use super::drive_api::{dictionary_of, done, error, refused, DriveHandle};
use super::exchange::Call;
use super::literal_calls::Arg;
use super::resolve::{self, Refusal};
use crate::diag::Span;
use crate::dictionary::{Dictionary, ObjectDef, Quantity};
use crate::session::{
    Condition, Predicate, StepOrigin, Tolerance, Watch, DEFAULT_WATCH_EVERY, MIN_WATCH_EVERY,
};
use rhai::{Dynamic, Engine, Map, NativeCallContext};
use std::sync::Arc;

/// The keys a watch's map takes.
pub const WATCH_KEYS: [&str; 6] = ["below", "above", "near", "within", "for", "every"];
const LIMITS: [&str; 3] = ["below", "above", "near"];
const EXAMPLE: &str = "e.g. d.watch(\"motor_temperature\", #{ below: \"80 °C\", every: \"1 s\" })";

/// One value of the map as written: text (`"80 °C"`, `"2 s"`) or a number (in the
/// object's own unit).
#[derive(Debug, Clone, PartialEq)]
pub enum WatchValue {
    Text(String),
    Number(f64),
    /// Anything else (a list, a map).
    Other(String),
}

/// The watch of `name` on `dict` with the limit, `for` and `every` of `entries`; a refusal
/// names the key it is about (`None`: the object or the map as a whole).
pub fn watch_of(
    dict: &Dictionary,
    name: &str,
    entries: &[(String, WatchValue)],
) -> Result<Watch, (Option<String>, Refusal)> {
    let whole = |r: Refusal| (None, r);
    let (def, object) = resolve::object(dict, name).map_err(whole)?;
    resolve::readable(dict, name).map_err(whole)?;
    if let Some((key, _)) = entries.iter().find(|(k, _)| !WATCH_KEYS.contains(&k.as_str())) {
        let at = Some(key.clone());
        return Err((
            at,
            Refusal::new(
                format!("a watch takes {}, not `{key}`", WATCH_KEYS.join(", ")),
                "unknown key",
                Some(EXAMPLE.into()),
            ),
        ));
    }
    let get = |key: &str| entries.iter().find(|(k, _)| k == key).map(|(_, v)| v);
    let limits: Vec<&str> = LIMITS.into_iter().filter(|k| get(k).is_some()).collect();
    let [op] = limits.as_slice() else {
        return Err(whole(Refusal::new(
            format!(
                "a watch on {} has exactly one of below, above, near; this has {}",
                def.name,
                limits.len()
            ),
            "one limit",
            Some(EXAMPLE.into()),
        )));
    };
    let at = |key: &str| {
        let key = key.to_string();
        move |r: Refusal| (Some(key), r)
    };
    let limit = in_own_unit(&def, get(op).into_iter().next(), op).map_err(at(op))?;
    let within = get("within");
    let predicate = match (*op, within) {
        ("near", Some(w)) => Predicate::Near {
            target: limit,
            tolerance: tolerance(&def, w).map_err(at("within"))?,
        },
        ("near", None) => {
            return Err(whole(Refusal::new(
                "a watch `near` a value says how near with `within`",
                "no within",
                Some("e.g. #{ near: \"3000 rpm\", within: \"2 %\" }".into()),
            )))
        }
        (_, Some(_)) => {
            let r = Refusal::new("`within` goes with `near`", "only with near", None);
            return Err((Some("within".into()), r));
        }
        ("above", None) => Predicate::Above(limit),
        _ => Predicate::Below(limit),
    };
    let hold = match get("for") {
        Some(v) => duration(v).map_err(at("for"))?,
        None => std::time::Duration::ZERO,
    };
    let every = match get("every") {
        Some(v) => duration(v).map_err(at("every"))?,
        None => DEFAULT_WATCH_EVERY,
    };
    if every < MIN_WATCH_EVERY {
        let r = Refusal::new(
            format!(
                "a watch reads at most every {} ms, so the steps keep the line",
                MIN_WATCH_EVERY.as_millis()
            ),
            "too often",
            Some("e.g. every: \"500 ms\"".into()),
        );
        return Err((Some("every".into()), r));
    }
    Ok(Watch {
        condition: Condition::Value { object, predicate },
        hold,
        every,
        // The session puts the call's place here.
        origin: StepOrigin {
            path: String::new(),
            line: 0,
            column: 0,
        },
    })
}

/// A limit: a bare number in `def`'s unit, or text with a unit it converts from.
fn in_own_unit(def: &ObjectDef, value: Option<&WatchValue>, key: &str) -> Result<f64, Refusal> {
    let q = match value {
        Some(WatchValue::Number(v)) if v.is_finite() => return Ok(*v),
        Some(WatchValue::Text(t)) => Quantity::parse(t).ok(),
        _ => None,
    };
    let own = def.unit;
    let wanted = || {
        let unit = own.map(|u| format!(" {}", u.symbol())).unwrap_or_default();
        Refusal::new(
            format!("`{key}` of a watch on {} is a number{unit}", def.name),
            "not a limit",
            Some(EXAMPLE.into()),
        )
    };
    let q = q.ok_or_else(wanted)?;
    match (q.unit, own) {
        (None, _) => Ok(q.value),
        (Some(_), Some(unit)) => q.value_in(unit).filter(|v| v.is_finite()).ok_or_else(|| {
            Refusal::new(
                format!(
                    "{} is not a unit of {} ({})",
                    q.unit.map_or("", |u| u.symbol()),
                    def.name,
                    unit
                ),
                "wrong unit",
                None,
            )
        }),
        (Some(u), None) => Err(Refusal::new(
            format!("{} has no unit to compare {} with", def.name, u.symbol()),
            "wrong unit",
            Some("give a bare number".into()),
        )),
    }
}

fn tolerance(def: &ObjectDef, value: &WatchValue) -> Result<Tolerance, Refusal> {
    match value {
        WatchValue::Number(v) if *v >= 0.0 => Ok(Tolerance::Absolute(*v)),
        WatchValue::Text(t) if t.trim().ends_with('%') => resolve::tolerance(t).map(|(t, _)| t),
        WatchValue::Text(_) => in_own_unit(def, Some(value), "within").map(|v| Tolerance::Absolute(v.abs())),
        _ => Err(Refusal::new(
            "`within` is a tolerance",
            "not a tolerance",
            Some("write e.g. \"0.5 %\" or \"5 rpm\"".into()),
        )),
    }
}

fn duration(value: &WatchValue) -> Result<std::time::Duration, Refusal> {
    match value {
        WatchValue::Text(t) => resolve::duration(t),
        _ => Err(Refusal::new(
            "a watch's durations are text with a unit",
            "not a duration",
            Some("e.g. \"2 s\", \"500 ms\"".into()),
        )),
    }
}

/// `check` of `d.watch(name, #{ ... })` written with literals: the problem and where it is
/// (the key's value, else the object's name). A map with a computed value is left to the
/// run, but for its object.
pub(super) fn check_literal_watch(
    dict: &Dictionary,
    name: &str,
    name_at: &Span,
    limit: Option<&(Arg, Span)>,
) -> Option<(Span, Refusal)> {
    let Some((Arg::Map(written), _)) = limit else {
        return resolve::readable(dict, name).err().map(|r| (name_at.clone(), r));
    };
    let mut entries = Vec::new();
    for (key, value, _) in written {
        entries.push((
            key.clone(),
            match value {
                Arg::Text(t) => WatchValue::Text(t.clone()),
                Arg::Number(v) => WatchValue::Number(*v),
                _ => return resolve::readable(dict, name).err().map(|r| (name_at.clone(), r)),
            },
        ));
    }
    let (key, r) = watch_of(dict, name, &entries).err()?;
    let at = key
        .and_then(|k| written.iter().find(|(w, _, _)| *w == k))
        .map_or(name_at.clone(), |(_, _, at)| at.clone());
    Some((at, r))
}

/// The watches of `d.watch` calls written wholly with literals that `dict` takes, each at
/// its call's place: what `check` compares with the line before the script runs.
pub(super) fn literal_watches(calls: &[super::literal_calls::LiteralCall], dict: &Dictionary) -> Vec<Watch> {
    let mut out = Vec::new();
    for c in calls.iter().filter(|c| c.name == "watch" && c.method) {
        let (Some((Arg::Text(name), _)), Some((Arg::Map(written), _))) = (c.args.first(), c.args.get(1))
        else {
            continue;
        };
        let entries: Option<Vec<(String, WatchValue)>> = written
            .iter()
            .map(|(k, v, _)| match v {
                Arg::Text(t) => Some((k.clone(), WatchValue::Text(t.clone()))),
                Arg::Number(n) => Some((k.clone(), WatchValue::Number(*n))),
                _ => None,
            })
            .collect();
        if let Some(Ok(mut watch)) = entries.map(|e| watch_of(dict, name, &e)) {
            watch.origin = StepOrigin {
                path: c.span.path().to_string(),
                line: c.span.line(),
                column: c.span.column(),
            };
            out.push(watch);
        }
    }
    out
}

/// A Rhai map's entries as [`watch_of`] takes them.
fn entries(map: &Map) -> Vec<(String, WatchValue)> {
    map.iter()
        .map(|(k, v)| {
            let value = if let Ok(f) = v.as_float() {
                WatchValue::Number(f)
            } else if let Ok(i) = v.as_int() {
                WatchValue::Number(i as f64)
            } else if v.is_string() {
                WatchValue::Text(v.to_string())
            } else {
                WatchValue::Other(v.type_name().to_string())
            };
            (k.to_string(), value)
        })
        .collect()
}

pub(super) fn register_watch(engine: &mut Engine, bridge: &Arc<Bridge>) {
    let b = bridge.clone();
    engine.register_fn(
        "watch",
        move |ctx: NativeCallContext, h: &mut DriveHandle, name: &str, limit: Map| -> RhaiResult<()> {
            let (dictionary, prefix) = dictionary_of(&b, h)?;
            let mut watch = watch_of(&dictionary, name, &entries(&limit)).map_err(|(key, r)| match key {
                Some(key) => error(format!("watch {name}: `{key}`: {}", r.sentence())),
                None => refused(r),
            })?;
            if let Condition::Value { object, .. } = &mut watch.condition {
                object.name = format!("{prefix}{}", object.name);
            }
            let label = format!("watch {}", watch.condition);
            b.call(ctx.call_position(), Call::Watch(Box::new(watch)), label)
                .and_then(done)
        },
    );
    // Without a map there is no limit: say what a watch takes rather than "no such function".
    engine.register_fn(
        "watch",
        move |_: &mut DriveHandle, name: &str, _: Dynamic| -> RhaiResult<()> {
            Err(error(format!("watch {name}: give its limit as a map: {EXAMPLE}")))
        },
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn dictionary() -> Dictionary {
        crate::family::Registry::builtin()
            .load_dictionary(crate::family::DEFAULT_DICTIONARY)
            .expect("built-in dictionary")
    }

    fn text(k: &str, v: &str) -> (String, WatchValue) {
        (k.into(), WatchValue::Text(v.into()))
    }

    #[test]
    fn a_watch_takes_its_limit_in_any_unit_of_the_object_and_its_times() {
        let d = dictionary();
        let w = watch_of(
            &d,
            "motor_temperature",
            &[text("below", "80 °C"), text("for", "2 s")],
        )
        .unwrap();
        assert_eq!(w.hold, Duration::from_secs(2));
        assert_eq!(w.every, DEFAULT_WATCH_EVERY);
        assert_eq!(w.condition.to_string(), "motor_temperature below 80 °C");
        let w = watch_of(
            &d,
            "speed_actual",
            &[
                text("near", "3000 rpm"),
                text("within", "2 %"),
                text("every", "200 ms"),
            ],
        )
        .unwrap();
        assert_eq!(w.every, Duration::from_millis(200));
        assert!(matches!(
            w.condition,
            Condition::Value { predicate: Predicate::Near { target, tolerance: Tolerance::Percent(p) }, .. }
                if target == 3000.0 && p == 2.0
        ));
        let w = watch_of(&d, "speed_actual", &[("above".into(), WatchValue::Number(-5.0))]).unwrap();
        assert!(matches!(w.condition, Condition::Value { predicate: Predicate::Above(v), .. } if v == -5.0));
    }

    #[test]
    fn a_watch_refuses_what_a_recipe_watch_refuses_naming_the_key() {
        let d = dictionary();
        let key = |name: &str, e: &[(String, WatchValue)]| watch_of(&d, name, e).err().map(|(k, _)| k);
        assert_eq!(
            key("speed_actual", &[text("below", "80 °C")]),
            Some(Some("below".into()))
        );
        assert_eq!(
            key("speed_actual", &[text("below", "1 rpm"), text("every", "10 ms")]),
            Some(Some("every".into()))
        );
        assert_eq!(
            key("speed_actual", &[text("below", "1 rpm"), text("for", "soon")]),
            Some(Some("for".into()))
        );
        assert_eq!(
            key("speed_actual", &[text("bellow", "1 rpm")]),
            Some(Some("bellow".into()))
        );
        assert_eq!(key("speed_actual", &[]), Some(None));
        assert_eq!(key("speed_actual", &[text("near", "1 rpm")]), Some(None));
        assert_eq!(key("sped_actual", &[text("below", "1 rpm")]), Some(None));
    }
}
