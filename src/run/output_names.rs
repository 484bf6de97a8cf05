//! Output names from the run's identity: `--report "{serial}-{date}.html"` fills in the
//! parts `--unit` gives (serial, part, operator, station) or an answer given beforehand
//! (`--answers`, `--answer`) to the operator step that sets one, and the date and time the
//! command started (UTC: `{date}` 2026-11-25, `{time}` 023338). The files are opened before
//! anything is sent, so a part the run learns only from an answer typed during the run is
//! not known yet: a name that needs it, or names something else in braces, is refused
//! (exit code 2). Only text; it opens nothing (it reads the recipe for its operator steps).

use super::{BadValue, DictionaryArgs, OperatorArgs, OutputArgs, RunPlan};
use crate::family::Registry;
use crate::session::{UnitIdentity, UNIT_FIELDS};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// `outputs` with every `{name}` in its paths filled in.
pub fn outputs_named(
    outputs: &OutputArgs,
    unit: &UnitIdentity,
    now: SystemTime,
) -> Result<OutputArgs, BadValue> {
    let stamp = humantime::format_rfc3339_seconds(now).to_string();
    let date = stamp.get(..10).unwrap_or_default().to_string();
    let time = stamp.get(11..19).unwrap_or_default().replace(':', "");
    let fill = |flag: &str, path: &Option<PathBuf>| -> Result<Option<PathBuf>, BadValue> {
        path.as_deref()
            .map(|p| filled(flag, p, unit, &date, &time))
            .transpose()
    };
    Ok(OutputArgs {
        junit: fill("--junit", &outputs.junit)?,
        report: fill("--report", &outputs.report)?,
        csv: fill("--csv", &outputs.csv)?,
        trace: fill("--trace", &outputs.trace)?,
        ..outputs.clone()
    })
}

/// The unit as known before `file` starts: `--unit`'s parts, and those the answers given
/// beforehand set through the file's operator steps (`sets: serial`). A file that cannot
/// be loaded gives `--unit`'s alone (its run says why it cannot start).
pub fn unit_before_start(
    registry: &Registry,
    file: &Path,
    set: &[(String, String)],
    dictionary: &DictionaryArgs,
    operator: &OperatorArgs,
) -> UnitIdentity {
    let (Ok(loaded), Ok(given)) = (
        RunPlan::load_file(registry, file, set, dictionary),
        operator.given(),
    ) else {
        return operator.identity();
    };
    operator.identity_with_answers(&loaded.plan.prompts(), &given)
}

fn filled(flag: &str, path: &Path, unit: &UnitIdentity, date: &str, time: &str) -> Result<PathBuf, BadValue> {
    let text = path.to_string_lossy();
    if !text.contains('{') {
        return Ok(path.to_path_buf());
    }
    let mut out = String::new();
    let mut rest = text.as_ref();
    while let Some(open) = rest.find('{') {
        out.push_str(&rest[..open]);
        let Some(close) = rest[open..].find('}') else {
            return Err(BadValue(format!(
                "{flag} {text}: a `{{` without its `}}`; names are written `{{serial}}`, `{{date}}`"
            )));
        };
        let name = &rest[open + 1..open + close];
        let value = match name {
            "date" => date.to_string(),
            "time" => time.to_string(),
            part if UNIT_FIELDS.contains(&part) => {
                let given = unit
                    .fields()
                    .find(|(n, _)| *n == part)
                    .map(|(_, v)| v.to_string());
                given.ok_or_else(|| {
                    BadValue(format!(
                        "{flag} {text}: `{{{part}}}` needs the unit's {part}, which is not given: give it with --unit {part}=…, or answer the operator step that sets it beforehand (--answers FILE, --answer NAME=VALUE); one typed during the run is learnt only after the files are opened"
                    ))
                })?
            }
            other => {
                return Err(BadValue(format!(
                    "{flag} {text}: `{{{other}}}` is no name an output may use; names: {}, date, time",
                    UNIT_FIELDS.join(", ")
                )))
            }
        };
        // A value is one part of a file name: no folders, nothing a shell or a file system
        // trips over.
        out.extend(value.chars().map(|c| {
            if c.is_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        }));
        rest = &rest[open + close + 1..];
    }
    out.push_str(rest);
    Ok(PathBuf::from(out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn outputs(report: &str) -> OutputArgs {
        OutputArgs {
            report: Some(report.into()),
            ..Default::default()
        }
    }

    #[test]
    fn names_are_filled_from_the_unit_and_the_start() {
        let unit = UnitIdentity {
            serial: Some("SP-104233".into()),
            station: Some("Bench 3/a".into()),
            ..Default::default()
        };
        let now = SystemTime::UNIX_EPOCH + Duration::from_secs(1_764_037_418);
        let o = outputs_named(&outputs("out/{serial}-{station}-{date}T{time}.html"), &unit, now).unwrap();
        assert_eq!(
            o.report.unwrap(),
            PathBuf::from("out/SP-104233-Bench_3_a-2025-11-25T022338.html")
        );
        let plain = outputs_named(&outputs("r.html"), &unit, now).unwrap();
        assert_eq!(plain.report.unwrap(), PathBuf::from("r.html"));
    }

    #[test]
    fn an_unknown_or_missing_part_is_refused() {
        let now = SystemTime::UNIX_EPOCH;
        let e = outputs_named(&outputs("{serial}.html"), &UnitIdentity::default(), now)
            .unwrap_err()
            .0;
        assert!(e.contains("--report {serial}.html: `{serial}` needs the unit's serial, which is not given: give it with --unit serial=…"), "{e}");
        let e = outputs_named(&outputs("{colour}.html"), &UnitIdentity::default(), now)
            .unwrap_err()
            .0;
        assert!(
            e.contains(
                "`{colour}` is no name an output may use; names: serial, part, operator, station, date, time"
            ),
            "{e}"
        );
        assert!(outputs_named(&outputs("{serial.html"), &UnitIdentity::default(), now).is_err());
    }
}
