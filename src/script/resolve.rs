//! The words and values a script gives the drive API (object names, units, values to
//! write, durations, states, tolerances), resolved against the dictionary: the same rules
//! for `check` (on literals, before anything runs) and for a running script (on whatever
//! the script computed). Each refusal says what is wrong and what to write instead. It
//! must not talk to a drive.

use crate::diag::{did_you_mean, suggestion_text};
use crate::dictionary::{Dictionary, ObjectDef, Quantity, Unit, ValueError};
use crate::drive::DeviceState;
use crate::session::{ObjectRef, SetValue, Tolerance};
use std::path::{Component, Path, PathBuf};
use std::time::Duration;

/// The longest duration a script may give (as for recipes).
pub use crate::recipe::MAX_DURATION;

/// A refusal: the message, a short label for the underline, and help.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    pub message: String,
    pub label: &'static str,
    pub help: Option<String>,
}

impl Refusal {
    pub(super) fn new(message: impl Into<String>, label: &'static str, help: Option<String>) -> Self {
        Refusal {
            message: message.into(),
            label,
            help,
        }
    }

    /// The message and its help in one sentence (a run-time error a script may catch).
    pub fn sentence(&self) -> String {
        match &self.help {
            Some(h) => format!("{}; {h}", self.message),
            None => self.message.clone(),
        }
    }
}

/// The object called `name` (or an alias of it).
pub fn object(dict: &Dictionary, name: &str) -> Result<(ObjectDef, ObjectRef), Refusal> {
    match dict.lookup(name) {
        Ok(def) => Ok((
            def.clone(),
            ObjectRef {
                name: def.name.clone(),
                unit: def.unit.map(|u| u.symbol().to_string()),
            },
        )),
        Err(e) => Err(Refusal::new(
            format!("unknown object `{name}` in the {} dictionary", dict.name()),
            "unknown object",
            Some(e.help()),
        )),
    }
}

/// `allowed`, refused as `label` with `problem`'s message when it is not.
fn allowed(allowed: bool, problem: impl FnOnce() -> String, label: &'static str) -> Result<(), Refusal> {
    match allowed {
        true => Ok(()),
        false => Err(Refusal::new(problem(), label, None)),
    }
}

/// The object called `name`, which must be readable.
pub fn readable(dict: &Dictionary, name: &str) -> Result<ObjectRef, Refusal> {
    let (def, r) = object(dict, name)?;
    let problem = || format!("{} is write-only and cannot be read", def.name);
    allowed(def.readable(), problem, "write-only")?;
    // Every read a script makes (read, read_as, wait_until, sample) gives a number.
    if !def.data_type.is_number() {
        return Err(Refusal::new(
            format!("{} holds text ({}), not a number", def.name, def.data_type),
            "text, not a number",
            Some(format!(
                "a script reads numbers only; read {} in a recipe's `read:` step or with `drivescript read {}`",
                def.name, def.name
            )),
        ));
    }
    Ok(r)
}

/// A value read in its object's unit, converted to `unit` (Hz for an inverter's rpm where
/// the dictionary knows the motor's pole pairs): the unit and the factor to multiply by.
pub fn unit_for(def: &ObjectDef, unit: &str) -> Result<(Unit, f64), Refusal> {
    let to = Unit::parse(unit).map_err(|e| not_a_unit(unit, &e.to_string()))?;
    def.factor_to(to)
        .map(|factor| (to, factor))
        .map_err(|e| match (e, def.unit) {
            (e @ ValueError::NoPolePairs { .. }, _) => {
                Refusal::new(e.to_string(), "pole pairs unknown", None)
            }
            (_, Some(own)) => Refusal::new(
                format!("{to} is not a unit of {} ({own})", def.name),
                "wrong unit",
                None,
            ),
            (_, None) => Refusal::new(
                format!("{} has no unit to convert to {to}", def.name),
                "wrong unit",
                None,
            ),
        })
}

/// The factor a value of `name` read in its own unit is multiplied by to be in `unit`.
pub fn read_factor(dict: &Dictionary, name: &str, unit: &str) -> Result<f64, Refusal> {
    let (def, _) = object(dict, name)?;
    unit_for(&def, unit).map(|(_, factor)| factor)
}

/// What the script asked to write: text, or a number (bare: a script's integer exactly)
/// with or without its unit.
#[derive(Debug, Clone, PartialEq)]
pub enum Written {
    Text(String),
    Number(Quantity, Option<String>),
}

/// A write of `value` to `name`: the object must be writable and the value fit its type,
/// unit and limits (the bench limits too).
pub fn set_value(dict: &Dictionary, name: &str, value: &Written) -> Result<(ObjectRef, SetValue), Refusal> {
    let (def, r) = object(dict, name)?;
    let problem = || format!("{} is read-only and cannot be written", def.name);
    allowed(def.writable(), problem, "read-only")?;
    if !def.data_type.is_number() {
        return match value {
            Written::Text(t) => match def.text_to_raw(t) {
                Ok(_) => Ok((r, SetValue::Text(t.clone()))),
                Err(e) => Err(Refusal::new(
                    e.to_string(),
                    "refused before anything is sent",
                    None,
                )),
            },
            Written::Number(..) => Err(Refusal::new(
                format!("{} holds text; write a string", def.name),
                "not text",
                None,
            )),
        };
    }
    let quantity = match value {
        Written::Text(t) => {
            Quantity::parse(t).map_err(|e| Refusal::new(format!("{}: {e}", def.name), "not a value", None))?
        }
        Written::Number(q, None) => *q,
        Written::Number(q, Some(u)) => {
            let unit = Unit::parse(u).map_err(|e| not_a_unit(u, &e.to_string()))?;
            q.in_unit(Some(unit))
        }
    };
    if !quantity.value.is_finite() {
        return Err(Refusal::new(
            format!(
                "{}: {} is not a number that can be written",
                def.name, quantity.value
            ),
            "not finite",
            None,
        ));
    }
    // In the object's own unit a whole number stays exact (a 64-bit count).
    let in_own = match (quantity.unit, def.unit) {
        (None, _) => quantity,
        (Some(u), Some(own)) if u == own => quantity.in_unit(None),
        (Some(u), Some(own)) => match def.in_own_unit(quantity.value, u) {
            Ok(v) => Quantity::new(v, None),
            Err(e @ ValueError::NoPolePairs { .. }) => {
                return Err(Refusal::new(e.to_string(), "pole pairs unknown", None))
            }
            Err(_) => {
                return Err(Refusal::new(
                    format!("{u} is not a unit of {} ({own})", def.name),
                    "wrong unit",
                    None,
                ))
            }
        },
        (Some(u), None) => {
            return Err(Refusal::new(
                format!("{} has no unit; write a plain number, not {u}", def.name),
                "no unit here",
                None,
            ))
        }
    };
    def.to_raw(&quantity).map_err(|e| {
        Refusal::new(
            e.to_string(),
            "refused before anything is sent",
            limits_help(&def),
        )
    })?;
    Ok((r, SetValue::Number(in_own)))
}

/// `rpn` is not a unit; the unit parser's own words, with did-you-mean unless they
/// already suggest one.
pub(super) fn not_a_unit(unit: &str, why: &str) -> Refusal {
    let help = if why.contains("did you mean") {
        None
    } else {
        let symbols: Vec<&str> = Unit::symbols().collect();
        suggestion_text(&did_you_mean(unit, symbols))
    };
    Refusal::new(format!("`{unit}` is not a unit: {why}"), "not a unit", help)
}

fn limits_help(def: &ObjectDef) -> Option<String> {
    let unit = def.unit.map(|u| format!(" {}", u.symbol())).unwrap_or_default();
    match (def.min, def.max) {
        (Some(lo), Some(hi)) => Some(format!("{} accepts {lo}{unit} to {hi}{unit}", def.name)),
        _ => None,
    }
}

/// `500 ms`, `5 s`, `10 min`: longer than zero, at most [`MAX_DURATION`].
pub fn duration(text: &str) -> Result<Duration, Refusal> {
    let help =
        Some("write a duration with its unit, e.g. \"500 ms\", \"5 s\", \"10 min\", \"2 h\"".to_string());
    match humantime::parse_duration(text.trim()) {
        Ok(d) if d.is_zero() => Err(Refusal::new("a duration must be longer than zero", "zero", None)),
        Ok(d) if d > MAX_DURATION => Err(Refusal::new(
            format!(
                "`{}` is longer than {} days, the longest duration a script may give",
                text.trim(),
                MAX_DURATION.as_secs() / (24 * 3600)
            ),
            "too long",
            help,
        )),
        Ok(d) => Ok(d),
        Err(e) => Err(Refusal::new(
            format!("`{text}` is not a duration ({e})"),
            "not a duration",
            help,
        )),
    }
}

/// The `csv` file of a `sample`, as a recipe's `csv:` names it: relative paths go under
/// `--output-dir`. A script computes its names and runs in a sandbox without file access,
/// so a name must stay inside that directory: relative, without `..`.
pub fn csv_file(text: &str) -> Result<PathBuf, Refusal> {
    let path = Path::new(text);
    let inside = path
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    if text.trim().is_empty() || path.file_name().is_none() {
        return Err(Refusal::new(
            format!("`{text}` is not a file name"),
            "not a file name",
            Some("name the CSV file, e.g. \"sweep.csv\"".into()),
        ));
    }
    if !inside {
        return Err(Refusal::new(
            format!("`{text}` is outside the output directory"),
            "outside --output-dir",
            Some(
                "a script writes its CSV files under --output-dir: give a relative name without `..`, e.g. \"sweep.csv\" or \"run-in/stage-1.csv\"".into(),
            ),
        ));
    }
    Ok(path.to_path_buf())
}

/// A state of the device-control profile: `operation_enabled`.
pub fn state(text: &str) -> Result<DeviceState, Refusal> {
    DeviceState::from_id(text).ok_or_else(|| {
        let ids = DeviceState::ALL.map(DeviceState::id);
        Refusal::new(
            format!("unknown state `{text}`"),
            "unknown state",
            suggestion_text(&did_you_mean(text, ids)).or_else(|| Some(format!("states: {}", ids.join(", ")))),
        )
    })
}

/// `0.5 %` (of the target) or `5 rpm` / `5` (absolute); with the unit, if one was given.
pub fn tolerance(text: &str) -> Result<(Tolerance, Option<String>), Refusal> {
    let t = text.trim();
    if let Some(p) = t.strip_suffix('%') {
        return match p.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 => Ok((Tolerance::Percent(v), None)),
            _ => Err(Refusal::new(
                format!("`{text}` is not a tolerance"),
                "not a tolerance",
                Some("write e.g. \"0.5 %\" or \"5 rpm\"".into()),
            )),
        };
    }
    match Quantity::parse(t) {
        Ok(q) if q.value >= 0.0 => Ok((
            Tolerance::Absolute(q.value),
            q.unit.map(|u| u.symbol().to_string()),
        )),
        _ => Err(Refusal::new(
            format!("`{text}` is not a tolerance"),
            "not a tolerance",
            Some("write e.g. \"0.5 %\" or \"5 rpm\"".into()),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sd2() -> std::sync::Arc<Dictionary> {
        std::sync::Arc::new(
            crate::family::Registry::builtin()
                .load_dictionary("sd2")
                .expect("the built-in dictionary"),
        )
    }

    /// A script's whole number goes to a 64-bit object exactly, as a number or as text.
    #[test]
    fn whole_numbers_are_written_exactly() {
        let mut d = crate::family::Registry::builtin()
            .load_dictionary("canopen")
            .unwrap();
        d.extend_from(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/family/canopen/sim/cia402_node.eds"),
        )
        .unwrap();
        let above = (1i128 << 53) + 1;
        for written in [
            Written::Number(Quantity::integer(above, None), None),
            Written::Text("9007199254740993".into()),
        ] {
            let (_, v) = set_value(&d, "position_counter", &written).unwrap();
            assert!(
                matches!(v, SetValue::Number(q) if q.whole() == Some(above)),
                "{written:?}"
            );
        }
    }

    #[test]
    fn names_units_values_and_durations() {
        let d = sd2();
        let e = object(&d, "speed_actul").unwrap_err();
        assert!(e.help.unwrap_or_default().contains("speed_actual"));
        let (r, v) = set_value(
            &d,
            "speed_setpoint",
            &Written::Number(Quantity::new(6.0, None), Some("krpm".into())),
        )
        .unwrap();
        assert_eq!((r.name.as_str(), v), ("speed_setpoint", SetValue::number(6000.0)));
        let (_, v) = set_value(&d, "speed_setpoint", &Written::Text("6000 rpm".into())).unwrap();
        assert_eq!(v, SetValue::number(6000.0));
        assert_eq!(
            set_value(
                &d,
                "speed_setpoint",
                &Written::Number(Quantity::new(6.0, None), Some("V".into()))
            )
            .unwrap_err()
            .label,
            "wrong unit"
        );
        assert!(set_value(
            &d,
            "speed_setpoint",
            &Written::Number(Quantity::new(1e12, None), None)
        )
        .is_err());
        let speed = d.get("speed_actual").unwrap();
        assert_eq!(unit_for(speed, "krpm").unwrap().1, 0.001);
        assert!(unit_for(speed, "A").is_err());
        assert_eq!(duration("2 s").unwrap(), Duration::from_secs(2));
        assert!(duration("2").is_err() && duration("0 s").is_err());
        assert!(state("operation_enabld")
            .unwrap_err()
            .help
            .unwrap()
            .contains("operation_enabled"));
        assert_eq!(tolerance("0.5 %").unwrap().0, Tolerance::Percent(0.5));
        assert_eq!(
            tolerance("5 rpm").unwrap(),
            (Tolerance::Absolute(5.0), Some("rpm".to_string()))
        );
        assert!(tolerance("lots").is_err());
    }

    #[test]
    fn a_csv_file_stays_under_the_output_directory() {
        assert_eq!(csv_file("sweep.csv").unwrap(), PathBuf::from("sweep.csv"));
        assert_eq!(
            csv_file("run-in/stage-1.csv").unwrap(),
            PathBuf::from("run-in/stage-1.csv")
        );
        for outside in ["/tmp/x.csv", "../x.csv", "a/../../x.csv"] {
            assert_eq!(
                csv_file(outside).unwrap_err().label,
                "outside --output-dir",
                "{outside}"
            );
        }
        for nothing in ["", "  ", ".", ".."] {
            assert!(csv_file(nothing).is_err(), "{nothing:?}");
        }
    }
}
