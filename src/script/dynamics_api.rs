//! The script forms of the checks on how the drive moves: `d.wait_until_stable(object,
//! rate, over, timeout)` (until the slope of the last `over` is below `rate`) and
//! `d.coast_down(from, below, shortest, longest)` (power stage off, the coast-down time
//! checked to lie between the two durations; an optional fifth argument, `#{ at_least:
//! "-10 %", without_history: "pass" }`, compares the time with the unit's last passed run). Values are text with units, resolved against
//! the drive's dictionary before anything is sent; the session does the rest.

use super::bridge::{Bridge, RhaiResult};
use super::drive_api::{
    dictionary_of, done, duration, error, refused, with_optional, with_optional_duration, DriveHandle,
};
use super::exchange::Call;
use super::last_pass_api::last_pass;
use super::resolve;
use crate::dictionary::{Quantity, Role, Unit};
use crate::session::{CoastDown, Condition, LastPass, Predicate};
use rhai::{Engine, Map, NativeCallContext};
use std::sync::Arc;
use std::time::Duration;

/// Poll period of `wait_until_stable` unless the script gives one.
const STABLE_POLL: Duration = Duration::from_secs(10);
const COAST_POLL: Duration = Duration::from_millis(100);
const COAST_TIMEOUT: Duration = Duration::from_secs(10 * 60);

/// `text` (a number with a unit) in `unit`, or why not.
fn quantity_in(text: &str, unit: Unit, what: &str) -> RhaiResult<f64> {
    let q = Quantity::parse(text).map_err(|e| error(format!("{what}: {e}")))?;
    match q.value_in(unit) {
        Some(v) if v.is_finite() => Ok(v),
        _ => Err(error(format!(
            "{what}: `{text}` is not in a unit of {unit}{}",
            q.unit
                .and_then(|u| u.mismatch_help(unit))
                .map(|h| format!(" ({h})"))
                .unwrap_or_default()
        ))),
    }
}

#[allow(clippy::too_many_arguments)]
fn wait_stable(
    b: &Bridge,
    h: &DriveHandle,
    ctx: &NativeCallContext,
    name: &str,
    rate: &str,
    over: &str,
    timeout: &str,
    every: Duration,
) -> RhaiResult<()> {
    let (dictionary, prefix) = dictionary_of(b, h)?;
    let (def, mut object) = resolve::object(&dictionary, name).map_err(refused)?;
    object.name = format!("{prefix}{}", object.name);
    let Some(rate_unit) = def.unit.and_then(Unit::rate) else {
        return Err(error(format!(
            "wait_until_stable: a slope is checked on a temperature (in K/min); {} is in {}",
            def.name,
            def.unit.map_or("no unit", Unit::symbol)
        )));
    };
    let limit = quantity_in(rate, rate_unit, "wait_until_stable")?;
    let (over, timeout) = (duration(over)?, duration(timeout)?);
    let condition = Condition::Stable {
        object,
        over,
        predicate: Predicate::Below(limit),
        rate_unit: rate_unit.symbol().to_string(),
    };
    let label = format!(
        "wait until {condition} (timeout {})",
        crate::session::show_duration(timeout)
    );
    let call = Call::WaitStable {
        condition,
        timeout,
        every,
    };
    b.call(ctx.call_position(), call, label).and_then(done)
}

pub(super) fn register_dynamics(engine: &mut Engine, bridge: &Arc<Bridge>) {
    with_optional_duration!(
        engine,
        bridge,
        "wait_until_stable",
        STABLE_POLL,
        |b, ctx, h, name: &str, rate: &str, over: &str, timeout: &str| every => {
            wait_stable(&b, h, &ctx, name, rate, over, timeout, every)
        }
    );
    with_optional!(
        engine,
        bridge,
        "coast_down",
        |b, ctx, h, from: &str, below: &str, shortest: &str, longest: &str| -> (),
        compared: Map => Some(last_pass("coast_down", &compared)?), or None,
        coast_down(&b, h, &ctx, [from, below, shortest, longest], compared)
    );
}

/// `d.coast_down(from, below, shortest, longest)`, its time compared with the unit's last
/// passed run when `last_pass` says how far it may move (ends in % or in seconds).
fn coast_down(
    b: &Bridge,
    h: &DriveHandle,
    ctx: &NativeCallContext,
    [from, below, shortest, longest]: [&str; 4],
    last_pass: Option<LastPass>,
) -> RhaiResult<()> {
    let (dictionary, _) = dictionary_of(b, h)?;
    let Some(speed) = dictionary.role(Role::SpeedActual) else {
        return Err(error("coast_down: the drive's profile names no actual speed"));
    };
    let unit = speed.unit.unwrap_or(Unit::Rpm);
    let from = quantity_in(from, unit, "coast_down")?.abs();
    let below = quantity_in(below, unit, "coast_down")?.abs();
    if below >= from {
        return Err(error("coast_down: `below` must be lower than `from`"));
    }
    let (shortest, longest) = (duration(shortest)?, duration(longest)?);
    let c = CoastDown {
        name: None,
        from,
        below,
        predicate: Predicate::Between(shortest.as_secs_f64(), longest.as_secs_f64()),
        warn: None,
        timeout: COAST_TIMEOUT.max(longest),
        every: COAST_POLL,
        unit: Some(unit.symbol().to_string()),
        last_pass,
    };
    let label = format!("{} (power stage off)", c.check_name());
    b.call(ctx.call_position(), Call::CoastDown(Box::new(c)), label)
        .and_then(done)
}
