//! `expect_compared_with_last_pass(name, measured, #{ at_most, at_least, without_history })`:
//! a script's check `name` (made with `expect` or `expect_near`) compared with the same
//! check in the unit's last passed run of this script, as a recipe's
//! `compared_with_last_pass` (ends in % of that value, `"10 %"`, or as numbers in the
//! value's own unit); the same map read for `d.coast_down`'s and `enter_value`'s own
//! comparisons. Builds the comparison and hands it to the session thread, which looks the
//! unit up; it must not read a store itself.

use super::bridge::{Bridge, RhaiResult};
use super::drive_api::{as_number, done, error, number_arg};
use super::exchange::Call;
use crate::session::{LastPass, StepOrigin};
use rhai::{Dynamic, Engine, Map, NativeCallContext};
use std::sync::Arc;

/// One end of the change: `"10 %"` (relative) or a number in the value's unit.
fn end(function: &str, map: &Map, key: &str) -> RhaiResult<Option<(f64, bool)>> {
    let Some(v) = map.get(key) else {
        return Ok(None);
    };
    if let Some(n) = as_number(v) {
        return Ok(Some((n, false)));
    }
    let text = v.to_string();
    let t = text.trim();
    let (number, relative) = match t.strip_suffix('%') {
        Some(p) => (p.trim(), true),
        None => (t, false),
    };
    match number.trim_start_matches('+').parse::<f64>() {
        Ok(n) if n.is_finite() => Ok(Some((n, relative))),
        _ => Err(error(format!(
            "{function}: `{key}: {t}` is no change; write e.g. \"10 %\" or 0.3"
        ))),
    }
}

/// The comparison `allowed` describes, given to `function` (whose name heads the errors):
/// `expect_compared_with_last_pass`, `coast_down`, `enter_value`.
pub(super) fn last_pass(function: &str, allowed: &Map) -> RhaiResult<LastPass> {
    let pass_without_history = match allowed.get("without_history").map(|v| v.to_string()).as_deref() {
        Some("pass") => true,
        Some("fail") => false,
        _ => {
            return Err(error(format!(
                "{function}: give `without_history: \"pass\"` (a unit's first run passes) or \"fail\""
            )))
        }
    };
    if let Some(k) = allowed
        .keys()
        .find(|k| !["at_most", "at_least", "without_history"].contains(&k.as_str()))
    {
        return Err(error(format!(
            "{function}: unknown key `{k}`; the keys are at_most, at_least, without_history"
        )));
    }
    let (low, high) = (
        end(function, allowed, "at_least")?,
        end(function, allowed, "at_most")?,
    );
    let relative = match (low, high) {
        (None, None) => {
            return Err(error(format!(
                "{function}: give `at_most`, `at_least` or both: how far the value may move"
            )))
        }
        (Some((_, a)), Some((_, b))) if a != b => {
            return Err(error(format!(
                "{function}: `at_least` and `at_most` are both in % or both numbers"
            )))
        }
        (Some((_, r)), _) | (_, Some((_, r))) => r,
    };
    Ok(LastPass {
        at_least: low.map(|(v, _)| v),
        at_most: high.map(|(v, _)| v),
        relative,
        pass_without_history,
        // The session gives the place of the call.
        written: StepOrigin {
            path: String::new(),
            line: 0,
            column: 0,
        },
    })
}

pub(super) fn register_last_pass(engine: &mut Engine, bridge: &Arc<Bridge>) {
    let b = bridge.clone();
    engine.register_fn(
        "expect_compared_with_last_pass",
        move |ctx: NativeCallContext, name: &str, measured: Dynamic, allowed: Map| -> RhaiResult<()> {
            let measured = number_arg(&measured, "expect_compared_with_last_pass: the measured value")?;
            let lp = last_pass("expect_compared_with_last_pass", &allowed)?;
            let label = format!("expect {name} compared with last pass");
            let call = Call::CompareLastPass(Box::new((name.to_string(), measured, lp)));
            b.call(ctx.call_position(), call, label).and_then(done)
        },
    );
}
