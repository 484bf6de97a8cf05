//! The functions a script calls: `drive()` and its methods (read, read_as, set, the device
//! commands, state, go_to, wait_until, sample with its optional CSV file), the sample window's statistics, `dwell`,
//! `expect`, `expect_near`, `fail`, `print`/`log` and `param`. Each resolves its words
//! and values against the dictionary (`resolve`), then hands the call to the session
//! thread through the [`Bridge`]. It must not touch the drive or the session itself.

use super::bridge::{Bridge, RhaiResult};
use super::exchange::{Answer, Call};
use super::resolve::{self, Refusal, Written};
use super::sample_window::SampleWindow;
use crate::dictionary::{Dictionary, Quantity};
use crate::drive::DeviceCommand;
use crate::session::{CheckResult, ObjectRef, Predicate, Statistic};
use rhai::{Array, Dynamic, Engine, EvalAltResult, FnPtr, NativeCallContext, Position};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

/// Registers the drive method `$name` twice, as Rhai has no optional arguments: with a
/// last argument `$last` of type `$lty`, which `$given` turns into what `$body` uses, and
/// without it, when `$default` stands in.
macro_rules! with_optional {
    ($engine:expr, $bridge:expr, $name:literal,
     |$b:ident, $ctx:ident, $h:ident $(, $arg:ident: $ty:ty)*| -> $ret:ty,
     $last:ident: $lty:ty => $given:expr, or $default:expr, $body:expr) => {{
        let $b = $bridge.clone();
        $engine.register_fn(
            $name,
            move |$ctx: NativeCallContext, $h: &mut DriveHandle $(, $arg: $ty)*| -> RhaiResult<$ret> {
                let $last = $default;
                $body
            },
        );
        let $b = $bridge.clone();
        $engine.register_fn(
            $name,
            move |$ctx: NativeCallContext, $h: &mut DriveHandle $(, $arg: $ty)*, $last: $lty| -> RhaiResult<$ret> {
                let $last = $given;
                $body
            },
        );
    }};
}
pub(super) use with_optional;

/// [`with_optional`] with a duration as text (`"500ms"`) last.
macro_rules! with_optional_duration {
    ($engine:expr, $bridge:expr, $name:literal, $default:expr,
     |$b:ident, $ctx:ident, $h:ident $(, $arg:ident: $ty:ty)*| $last:ident => $body:expr) => {
        $crate::script::drive_api::with_optional!(
            $engine, $bridge, $name,
            |$b, $ctx, $h $(, $arg: $ty)*| -> (),
            $last: &str => duration($last)?, or $default, $body
        )
    };
}
pub(super) use with_optional_duration;

/// A drive as a script holds it: `let d = drive();` (the one drive; in a script with
/// several, commands to it go to every drive) or `let left = drive("left");`.
#[derive(Debug, Clone, Default)]
pub struct DriveHandle {
    pub name: Option<String>,
}

/// The dictionary objects of `h` are looked up in, and the prefix its objects carry
/// (`left.`; empty for the one drive).
pub(super) fn dictionary_of(b: &Bridge, h: &DriveHandle) -> RhaiResult<(Arc<Dictionary>, String)> {
    match (&h.name, b.drives.is_empty()) {
        (None, true) => Ok((b.dictionary.clone(), String::new())),
        (None, false) => Err(error(format!(
            "this script has several drives ({}): name the drive, e.g. drive(\"{}\")",
            b.drives
                .iter()
                .map(|(n, _)| n.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            b.drives[0].0
        ))),
        (Some(name), _) => b
            .drives
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, d)| (d.clone(), format!("{name}.")))
            .ok_or_else(|| error(format!("no drive called `{name}` in this script"))),
    }
}

/// `readable` (or another lookup) on `h`'s dictionary, the object named with `h`'s prefix.
fn on_drive(
    b: &Bridge,
    h: &DriveHandle,
    lookup: impl FnOnce(&crate::dictionary::Dictionary) -> Result<ObjectRef, Refusal>,
) -> RhaiResult<ObjectRef> {
    let (dictionary, prefix) = dictionary_of(b, h)?;
    let mut object = lookup(&dictionary).map_err(refused)?;
    object.name = format!("{prefix}{}", object.name);
    Ok(object)
}

/// Default timeout of each `go_to` transition and poll period of `wait_until` (as recipes).
const GO_TO_TIMEOUT: Duration = Duration::from_secs(5);
const POLL: Duration = Duration::from_millis(100);

pub(super) fn refused(r: Refusal) -> Box<EvalAltResult> {
    Box::new(EvalAltResult::ErrorRuntime(r.sentence().into(), Position::NONE))
}

pub(super) fn error(text: impl std::fmt::Display) -> Box<EvalAltResult> {
    Box::new(EvalAltResult::ErrorRuntime(
        text.to_string().into(),
        Position::NONE,
    ))
}

/// A number from a Rhai integer or float.
pub(super) fn as_number(v: &Dynamic) -> Option<f64> {
    as_quantity(v).map(|q| q.value)
}

/// A script's number as a bare quantity: an integer exactly, beyond a float's 53 bits too.
fn as_quantity(v: &Dynamic) -> Option<Quantity> {
    let float = v.as_float().ok().map(|f| Quantity::new(f, None));
    float.or_else(|| v.as_int().ok().map(|i| Quantity::integer(i.into(), None)))
}

pub(super) fn number_arg(v: &Dynamic, what: &str) -> RhaiResult<f64> {
    as_number(v).ok_or_else(|| error(format!("{what} must be a number, not {}", v.type_name())))
}

pub(super) fn duration(text: &str) -> RhaiResult<Duration> {
    resolve::duration(text).map_err(refused)
}

pub(super) fn done(answer: Answer) -> RhaiResult<()> {
    match answer {
        Answer::Done => Ok(()),
        _ => Err(unexpected_answer()),
    }
}

/// The session answered a call with an answer of another call: a fault of drivescript's own.
pub(super) fn unexpected_answer() -> Box<EvalAltResult> {
    error("the session gave an unexpected answer")
}

/// Reads `object` on the session's thread.
fn read(b: &Bridge, ctx: &NativeCallContext, object: ObjectRef) -> RhaiResult<f64> {
    match b.call(ctx.call_position(), Call::Read(object), String::new())? {
        Answer::Number(v) => Ok(v),
        _ => Err(unexpected_answer()),
    }
}

/// Adds the drive API to `engine`, every call going through `bridge`.
pub fn register(engine: &mut Engine, bridge: &Arc<Bridge>) {
    let b = bridge.clone();
    engine.on_progress(move |count| b.on_progress(count));
    let b = bridge.clone();
    engine.on_print(move |text| {
        let _ = b.call(Position::NONE, Call::Message(text.to_string()), String::new());
    });
    let b = bridge.clone();
    engine.on_debug(move |text, _, _| {
        let _ = b.call(Position::NONE, Call::Message(text.to_string()), String::new());
    });
    engine.register_type_with_name::<DriveHandle>("Drive");
    engine.register_type_with_name::<SampleWindow>("SampleWindow");
    engine.register_fn("drive", DriveHandle::default);
    super::dynamics_api::register_dynamics(engine, bridge);
    let b = bridge.clone();
    engine.register_fn("drive", move |name: &str| -> RhaiResult<DriveHandle> {
        if b.drives.iter().any(|(n, _)| n == name) {
            return Ok(DriveHandle {
                name: Some(name.to_string()),
            });
        }
        let names: Vec<&str> = b.drives.iter().map(|(n, _)| n.as_str()).collect();
        let help = match crate::diag::did_you_mean(name, names.iter().copied()).first() {
            Some(s) => format!("; did you mean `{s}`?"),
            None if names.is_empty() => "; this script has one drive: drive()".to_string(),
            None => format!("; its drives are {}", names.join(", ")),
        };
        Err(error(format!("no drive called `{name}` in this script{help}")))
    });

    let b = bridge.clone();
    engine.register_fn(
        "log",
        move |ctx: NativeCallContext, text: Dynamic| -> RhaiResult<()> {
            b.call(
                ctx.call_position(),
                Call::Message(text.to_string()),
                String::new(),
            )
            .and_then(done)
        },
    );
    register_reads(engine, bridge);
    register_writes(engine, bridge);
    register_waits(engine, bridge);
    register_checks(engine, bridge);
    super::param_api::register_params(engine, bridge);
    super::operator_api::register_operator(engine, bridge);
    super::last_pass_api::register_last_pass(engine, bridge);
    super::watch_api::register_watch(engine, bridge);
}

fn register_reads(engine: &mut Engine, bridge: &Arc<Bridge>) {
    let b = bridge.clone();
    engine.register_fn(
        "read",
        move |ctx: NativeCallContext, h: &mut DriveHandle, name: &str| -> RhaiResult<f64> {
            let object = on_drive(&b, h, |d| resolve::readable(d, name))?;
            read(&b, &ctx, object)
        },
    );
    let b = bridge.clone();
    engine.register_fn(
        "read_as",
        move |ctx: NativeCallContext, h: &mut DriveHandle, name: &str, unit: &str| -> RhaiResult<f64> {
            let object = on_drive(&b, h, |d| resolve::readable(d, name))?;
            let (dictionary, _) = dictionary_of(&b, h)?;
            let factor = resolve::read_factor(&dictionary, name, unit).map_err(refused)?;
            Ok(read(&b, &ctx, object)? * factor)
        },
    );
    let b = bridge.clone();
    engine.register_fn(
        "state",
        move |ctx: NativeCallContext, h: &mut DriveHandle| -> RhaiResult<String> {
            match b.call(ctx.call_position(), Call::State(h.name.clone()), String::new())? {
                Answer::State(s) => Ok(s.id().to_string()),
                _ => Err(unexpected_answer()),
            }
        },
    );
}

fn register_writes(engine: &mut Engine, bridge: &Arc<Bridge>) {
    let set =
        |b: &Arc<Bridge>, h: &DriveHandle, pos: Position, name: &str, written: Written| -> RhaiResult<()> {
            let (dictionary, prefix) = dictionary_of(b, h)?;
            let (mut object, value) = resolve::set_value(&dictionary, name, &written).map_err(refused)?;
            object.name = format!("{prefix}{}", object.name);
            let shown = match &value {
                crate::session::SetValue::Number(v) => {
                    crate::session::exact_with_unit(v, object.unit.as_deref())
                }
                crate::session::SetValue::Text(t) => format!("\"{t}\""),
            };
            let label = format!("set {} = {shown}", object.name);
            b.call(pos, Call::Set(object, value), label).and_then(done)
        };
    let b = bridge.clone();
    engine.register_fn(
        "set",
        move |ctx: NativeCallContext, h: &mut DriveHandle, name: &str, value: Dynamic| -> RhaiResult<()> {
            let written = match as_quantity(&value) {
                Some(q) => Written::Number(q, None),
                None if value.is_string() => Written::Text(value.to_string()),
                None => {
                    return Err(error(format!(
                        "set {name}: give a number or text, not {}",
                        value.type_name()
                    )))
                }
            };
            set(&b, h, ctx.call_position(), name, written)
        },
    );
    let b = bridge.clone();
    engine.register_fn(
        "set",
        move |ctx: NativeCallContext,
              h: &mut DriveHandle,
              name: &str,
              value: Dynamic,
              unit: &str|
              -> RhaiResult<()> {
            let q = as_quantity(&value).ok_or_else(|| {
                error(format!(
                    "the value for {name} must be a number, not {}",
                    value.type_name()
                ))
            })?;
            set(
                &b,
                h,
                ctx.call_position(),
                name,
                Written::Number(q, Some(unit.to_string())),
            )
        },
    );
    for command in DeviceCommand::ALL {
        let b = bridge.clone();
        engine.register_fn(
            command.id(),
            move |ctx: NativeCallContext, h: &mut DriveHandle| -> RhaiResult<()> {
                let label = match &h.name {
                    Some(n) => format!("{} {n}", command.id()),
                    None => command.id().to_string(),
                };
                b.call(ctx.call_position(), Call::Command(command, h.name.clone()), label)
                    .and_then(done)
            },
        );
    }
}

fn register_waits(engine: &mut Engine, bridge: &Arc<Bridge>) {
    let go_to =
        |b: &Arc<Bridge>, h: &DriveHandle, pos: Position, state: &str, timeout: Duration| -> RhaiResult<()> {
            let state = resolve::state(state).map_err(refused)?;
            let label = match &h.name {
                Some(n) => format!("go_to {} ({n})", state.id()),
                None => format!("go_to {}", state.id()),
            };
            b.call(pos, Call::GoTo(state, timeout, h.name.clone()), label)
                .and_then(done)
        };
    with_optional_duration!(engine, bridge, "go_to", GO_TO_TIMEOUT, |b, ctx, h, state: &str| timeout => {
        go_to(&b, h, ctx.call_position(), state, timeout)
    });
    let wait = |b: &Arc<Bridge>,
                h: &DriveHandle,
                ctx: &NativeCallContext,
                name: &str,
                f: &FnPtr,
                timeout: &str,
                every: Duration| {
        let object = on_drive(b, h, |d| resolve::readable(d, name))?;
        let timeout = duration(timeout)?;
        let label = format!(
            "wait_until {} (the script's condition), at most {}",
            object.name,
            crate::session::show_duration(timeout)
        );
        b.wait(
            ctx,
            Call::WaitUntil {
                object,
                timeout,
                every,
            },
            label,
            f,
        )
        .and_then(done)
    };
    with_optional_duration!(engine, bridge, "wait_until", POLL, |b, ctx, h, name: &str, f: FnPtr, timeout: &str| every => {
        wait(&b, h, &ctx, name, &f, timeout, every)
    });
    let b = bridge.clone();
    engine.register_fn(
        "dwell",
        move |ctx: NativeCallContext, d: &str| -> RhaiResult<()> {
            let d = duration(d)?;
            let label = format!("dwell {}", crate::session::show_duration(d));
            b.call(ctx.call_position(), Call::Dwell(d), label).and_then(done)
        },
    );
    with_optional!(
        engine,
        bridge,
        "sample",
        |b, ctx, h, names: Array, every: &str, time: &str| -> SampleWindow,
        csv: Dynamic => Some(csv_path(&b, csv)?), or None,
        sample(&b, h, &ctx, names, every, time, csv)
    );
    for (id, statistic) in Statistic::OF_SUMS {
        engine.register_fn(id, move |w: &mut SampleWindow, name: &str| -> RhaiResult<f64> {
            w.statistic(name, statistic).map_err(error)
        });
    }
    engine.register_fn("count", |w: &mut SampleWindow, name: &str| -> RhaiResult<i64> {
        Ok(w.window(name).map_err(error)?.stats.count as i64)
    });
    engine.register_fn(
        "values",
        |w: &mut SampleWindow, name: &str| -> RhaiResult<Array> {
            Ok(w.values(name)
                .map_err(error)?
                .into_iter()
                .map(Dynamic::from_float)
                .collect())
        },
    );
}

/// The CSV file a script names for `sample`'s rows, ready to be written.
fn csv_path(b: &Bridge, csv: Dynamic) -> RhaiResult<PathBuf> {
    let name = csv.into_string().map_err(|t| {
        error(format!(
            "sample: the csv file is named with text (\"sweep.csv\"), not {t}"
        ))
    })?;
    let path = resolve::csv_file(&name).map_err(refused)?;
    b.csv_file(&path).map_err(error)?;
    Ok(path)
}

/// `d.sample(["speed_actual"], "100 ms", "20 s")`, with its rows also written to `csv`
/// when given.
fn sample(
    b: &Bridge,
    h: &DriveHandle,
    ctx: &NativeCallContext,
    names: Array,
    every: &str,
    time: &str,
    csv: Option<PathBuf>,
) -> RhaiResult<SampleWindow> {
    let mut objects = Vec::new();
    for n in &names {
        let name = n
            .clone()
            .into_string()
            .map_err(|t| error(format!("sample: object names are text, not {t}")))?;
        objects.push(on_drive(b, h, |d| resolve::readable(d, &name))?);
    }
    if objects.is_empty() {
        return Err(error("sample: name at least one object"));
    }
    let (every, time) = (duration(every)?, duration(time)?);
    if time.as_secs_f64() / every.as_secs_f64() > crate::recipe::MAX_SAMPLES as f64 {
        return Err(error(format!(
            "sample: more than {} samples; sample less often or for a shorter time",
            crate::recipe::MAX_SAMPLES
        )));
    }
    let sampling = crate::session::Sampling {
        objects,
        every,
        duration: time,
        csv,
    };
    let label = sampling.label();
    match b.call(ctx.call_position(), Call::Sample(sampling), label)? {
        Answer::Sampled(windows) => Ok(SampleWindow {
            windows,
            dictionary: b.dictionary.clone(),
        }),
        _ => Err(unexpected_answer()),
    }
}

fn register_checks(engine: &mut Engine, bridge: &Arc<Bridge>) {
    let expect = |b: &Arc<Bridge>, pos: Position, check: CheckResult| -> RhaiResult<()> {
        let label = format!("expect {}", check.name);
        b.call(pos, Call::Expect(Box::new(check)), label).and_then(done)
    };
    let plain = |name: &str, passed: bool, measured: Option<&Dynamic>| {
        let value = measured.and_then(as_number);
        // Three decimals, as the recipes' checks show numbers.
        let text = match value {
            Some(v) => Some(crate::session::number((v * 1000.0).round() / 1000.0)),
            None => measured.map(|m| m.to_string()),
        };
        // The session fills in where and when the check was made.
        CheckResult {
            measured: value,
            measured_text: text.clone(),
            message: match (&text, passed) {
                (Some(t), true) => format!("measured {t}"),
                (Some(t), false) => format!("measured {t}: the script's condition does not hold"),
                (None, true) => "holds".into(),
                (None, false) => "the script's condition does not hold".into(),
            },
            ..CheckResult::named(name, passed)
        }
    };
    let b = bridge.clone();
    engine.register_fn(
        "expect",
        move |ctx: NativeCallContext, name: &str, passed: bool, measured: Dynamic| -> RhaiResult<()> {
            expect(&b, ctx.call_position(), plain(name, passed, Some(&measured)))
        },
    );
    let b = bridge.clone();
    engine.register_fn(
        "expect",
        move |ctx: NativeCallContext, name: &str, passed: bool| -> RhaiResult<()> {
            expect(&b, ctx.call_position(), plain(name, passed, None))
        },
    );
    let b = bridge.clone();
    engine.register_fn(
        "expect_near",
        move |ctx: NativeCallContext,
              name: &str,
              measured: Dynamic,
              target: Dynamic,
              within: Dynamic|
              -> RhaiResult<()> {
            let measured = number_arg(&measured, "expect_near: the measured value")?;
            let target = number_arg(&target, "expect_near: the target")?;
            let (tolerance, unit) = match as_number(&within) {
                Some(t) if t >= 0.0 => (crate::session::Tolerance::Absolute(t), None),
                _ => resolve::tolerance(&within.to_string()).map_err(refused)?,
            };
            let predicate = Predicate::Near { target, tolerance };
            let passed = measured.is_finite() && predicate.holds(measured);
            let (low, high) = predicate.limits();
            let mut check = plain(name, passed, None);
            check.measured = Some(measured);
            check.measured_text = None;
            check.limits.low = low;
            check.limits.high = high;
            check.unit = unit.clone();
            let shown = crate::session::with_unit((measured * 1000.0).round() / 1000.0, unit.as_deref());
            check.message = if passed {
                format!("measured {shown}")
            } else {
                format!(
                    "measured {shown}, expected {}",
                    predicate.describe(unit.as_deref())
                )
            };
            expect(&b, ctx.call_position(), check)
        },
    );
    let b = bridge.clone();
    engine.register_fn(
        "fail",
        move |ctx: NativeCallContext, message: Dynamic| -> RhaiResult<()> {
            Err(b.fail(&ctx, message.to_string()))
        },
    );
}
