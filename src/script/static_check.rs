//! `check` for scripts beyond syntax: every drive call whose words are written as literals
//! is resolved against the dictionary with the same rules a running script uses
//! (`resolve`), and each refusal is a located diagnostic with did-you-mean; so is a state
//! a `d.state()` is compared with (`d.state() == "fault"`). Also: each
//! `--set` parameter must be read by a `param("name")`, in a type its default allows
//! (`param_value`). Values a script computes are
//! checked when the script runs. It must not run the script.

use super::literal_calls::{Arg, LiteralCall};
use super::param_value::{param_value, ParamKind};
use super::resolve::{self, Refusal, Written};
use crate::diag::{did_you_mean, suggestion_text, Diagnostic, Span};
use crate::dictionary::{Dictionary, Quantity};
use crate::session::Statistic;

/// The numbers written by `set` calls whose object, value and unit are all literals and
/// which the dictionary takes, in the object's unit, each at its value's place. Other
/// calls are left to [`check_calls`] (their problems) and to the run (computed values).
pub fn literal_writes(calls: &[LiteralCall], dict: &Dictionary) -> Vec<crate::recipe::WrittenValue> {
    let mut out = Vec::new();
    for c in calls.iter().filter(|c| c.name == "set" && c.method) {
        let (Some((Arg::Text(name), _)), Some((Arg::Number(v), vspan))) = (c.args.first(), c.args.get(1))
        else {
            continue;
        };
        let unit = match c.args.get(2) {
            Some((Arg::Text(u), _)) => Some(u.clone()),
            None => None,
            Some(_) => continue,
        };
        if let Ok((object, crate::session::SetValue::Number(value))) =
            resolve::set_value(dict, name, &Written::Number(Quantity::new(*v, None), unit))
        {
            out.push(crate::recipe::WrittenValue {
                object,
                value: value.value,
                origin: crate::session::StepOrigin {
                    path: vspan.path().to_string(),
                    line: vspan.line(),
                    column: vspan.column(),
                },
                step: "set",
            });
        }
    }
    out
}

/// [`literal_writes`] for a script with `//! drives:`: the `set` calls on a variable the
/// script gives one named drive (`let left = drive("left");`), each taken by that drive's
/// dictionary and named as a recipe with `drives:` names it (`left.speed_setpoint`), in
/// text order. A variable given several drives, or a drive whose name is not a literal,
/// is left to the run, where each value still meets its drive's dictionary.
pub fn named_literal_writes(
    calls: &[LiteralCall],
    drives: &[(String, std::sync::Arc<Dictionary>)],
) -> Vec<crate::recipe::WrittenValue> {
    let mut bound: Vec<(&str, Option<&str>)> = Vec::new();
    for c in calls.iter().filter(|c| c.name == "drive" && !c.method) {
        let (Some(var), Some((Arg::Text(name), _))) = (&c.assigned_to, c.args.first()) else {
            continue;
        };
        match bound.iter_mut().find(|(v, _)| v == var) {
            Some((_, drive)) if *drive != Some(name.as_str()) => *drive = None,
            Some(_) => {}
            None => bound.push((var, Some(name))),
        }
    }
    let mut out = Vec::new();
    for (var, drive) in bound {
        let Some((name, dict)) = drive.and_then(|d| drives.iter().find(|(n, _)| n == d)) else {
            continue;
        };
        let own: Vec<LiteralCall> = calls
            .iter()
            .filter(|c| c.receiver.as_deref() == Some(var))
            .cloned()
            .collect();
        out.extend(literal_writes(&own, dict).into_iter().map(|mut w| {
            w.object.name = format!("{name}.{}", w.object.name);
            w
        }));
    }
    out.sort_by_key(|w| (w.origin.line, w.origin.column));
    out
}

/// The problems of `calls`; `set` are the `--set` parameters.
pub fn check_calls(
    calls: &[LiteralCall],
    dict: &Dictionary,
    set: &[(String, String)],
    path: &str,
) -> Vec<Diagnostic> {
    let mut problems = Vec::new();
    let mut refuse = |span: &Span, r: Refusal| {
        problems.push(Diagnostic::at(span, r.message, r.label).with_optional_help(r.help));
    };
    let text = |i: usize, c: &LiteralCall| match c.args.get(i) {
        Some((Arg::Text(t), span)) => Some((t.clone(), span.clone())),
        _ => None,
    };
    let mut params = Vec::new();
    for c in calls {
        let name = text(0, c);
        match (c.name.as_str(), c.method) {
            ("read" | "wait_until", true) => {
                if let Some((n, span)) = &name {
                    if let Err(r) = resolve::readable(dict, n) {
                        refuse(span, r);
                    }
                }
                if c.name == "wait_until" {
                    for i in [2, 3] {
                        if let Some((t, span)) = text(i, c) {
                            if let Err(r) = resolve::duration(&t) {
                                refuse(&span, r);
                            }
                        }
                    }
                }
            }
            ("read_as", true) => {
                if let Some((n, span)) = &name {
                    match resolve::readable(dict, n) {
                        Ok(_) => {
                            if let Some((unit, uspan)) = text(1, c) {
                                if let Err(r) = resolve::read_factor(dict, n, &unit) {
                                    refuse(&uspan, r);
                                }
                            }
                        }
                        Err(r) => refuse(span, r),
                    }
                }
            }
            ("set", true) => {
                let Some((n, span)) = &name else { continue };
                let value = match (c.args.get(1), c.args.get(2)) {
                    (Some((Arg::Number(v), vspan)), Some((Arg::Text(u), uspan))) => Some((
                        Written::Number(Quantity::new(*v, None), Some(u.clone())),
                        vspan.clone(),
                        uspan.clone(),
                    )),
                    (Some((Arg::Number(v), vspan)), None) => Some((
                        Written::Number(Quantity::new(*v, None), None),
                        vspan.clone(),
                        vspan.clone(),
                    )),
                    (Some((Arg::Text(t), vspan)), None) => {
                        Some((Written::Text(t.clone()), vspan.clone(), vspan.clone()))
                    }
                    _ => None,
                };
                match value {
                    Some((value, vspan, uspan)) => {
                        if let Err(r) = resolve::set_value(dict, n, &value) {
                            let at = match r.label {
                                "unknown object" | "read-only" => span,
                                "not a unit" | "wrong unit" | "no unit here" => &uspan,
                                _ => &vspan,
                            };
                            refuse(at, r);
                        }
                    }
                    None => {
                        if let Err(r) = resolve::object(dict, n) {
                            refuse(span, r);
                        }
                    }
                }
            }
            ("sample", true) => {
                if let Some((Arg::TextList(items), _)) = c.args.first() {
                    for (n, span) in items {
                        if let Err(r) = resolve::readable(dict, n) {
                            refuse(span, r);
                        }
                    }
                }
                for i in [1, 2] {
                    if let Some((t, span)) = text(i, c) {
                        if let Err(r) = resolve::duration(&t) {
                            refuse(&span, r);
                        }
                    }
                }
                match c.args.get(3) {
                    Some((Arg::Text(t), span)) => {
                        if let Err(r) = resolve::csv_file(t) {
                            refuse(span, r);
                        }
                    }
                    Some((Arg::Number(_) | Arg::TextList(_), span)) => refuse(
                        span,
                        Refusal {
                            message: "the csv file of a sample is named with text".into(),
                            label: "not text",
                            help: Some(
                                "e.g. d.sample([\"speed_actual\"], \"100 ms\", \"20 s\", \"sweep.csv\")"
                                    .into(),
                            ),
                        },
                    ),
                    _ => {}
                }
            }
            ("watch", true) => {
                if let Some((n, span)) = &name {
                    if let Some((at, r)) = super::watch_api::check_literal_watch(dict, n, span, c.args.get(1))
                    {
                        refuse(&at, r);
                    }
                }
            }
            ("state", true) => {
                if let Some((s, span)) = &c.compared_with {
                    if let Err(r) = resolve::state(s) {
                        refuse(span, r);
                    }
                }
            }
            ("go_to", true) => {
                if let Some((s, span)) = &name {
                    if let Err(r) = resolve::state(s) {
                        refuse(span, r);
                    }
                }
                if let Some((t, span)) = text(1, c) {
                    if let Err(r) = resolve::duration(&t) {
                        refuse(&span, r);
                    }
                }
            }
            (m, true)
                if m == "values" || m == "count" || Statistic::OF_SUMS.iter().any(|(id, _)| *id == m) =>
            {
                if let Some((n, span)) = &name {
                    if let Err(r) = resolve::readable(dict, n) {
                        refuse(span, r);
                    }
                }
            }
            ("dwell", false) => {
                if let Some((t, span)) = &name {
                    if let Err(r) = resolve::duration(t) {
                        refuse(span, r);
                    }
                }
            }
            ("expect_near", false) => {
                if let Some((t, span)) = text(3, c) {
                    if let Err(r) = resolve::tolerance(&t) {
                        refuse(&span, r);
                    }
                }
            }
            ("param", false) => {
                if let Some((n, _)) = name {
                    match param_kind(c) {
                        Ok(Some(kind)) => {
                            let given = set.iter().find(|(s, _)| *s == n);
                            if let Some(Err(r)) = given.map(|(_, v)| param_value(&n, v, kind)) {
                                refuse(&c.span, r);
                            }
                        }
                        Ok(None) => {}
                        Err((span, r)) => refuse(&span, r),
                    }
                    params.push(n);
                }
            }
            _ => {}
        }
    }
    for (name, _) in set {
        if !params.contains(name) {
            let help = suggestion_text(&did_you_mean(name, params.iter().map(String::as_str)))
                .or_else(|| Some("the script reads its parameters with param(\"name\")".into()));
            problems.push(
                Diagnostic::unlocated(
                    path,
                    format!("--set {name}: the script reads no parameter `{name}`"),
                )
                .with_optional_help(help),
            );
        }
    }
    problems
}

/// The kind of value a `param(…)` call asks for, from its literal default and unit;
/// `None` when they are computed (the run converts the value then).
fn param_kind(c: &LiteralCall) -> Result<Option<ParamKind>, (Span, Refusal)> {
    match (c.args.get(1), c.args.get(2)) {
        (None, _) => Ok(Some(ParamKind::Any)),
        (Some((Arg::Text(_) | Arg::TextList(_) | Arg::Closure(_), span)), Some((Arg::Text(_), _))) => Err((
            span.clone(),
            Refusal {
                message: "the default of a parameter with a unit is a number in that unit".into(),
                label: "not a number",
                help: Some("e.g. param(\"top\", 12000.0, \"rpm\")".into()),
            },
        )),
        (Some(_), Some((Arg::Text(unit), span))) => match crate::dictionary::Unit::parse(unit) {
            Ok(unit) => Ok(Some(ParamKind::InUnit(unit))),
            Err(e) => Err((span.clone(), resolve::not_a_unit(unit, &e.to_string()))),
        },
        (Some(_), Some(_)) => Ok(None),
        (Some((_, default)), None) => Ok(ParamKind::of_literal(default.written())),
    }
}
