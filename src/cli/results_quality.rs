//! What a quality lead asks of the results store beyond one run: `results yield`,
//! `results capability`, `results void`, and the hint when a trend's check is not found.
//! Parses and prints; the numbers and the pages are the library's (`results`).

use super::text_table::table_lines;
use crate::results::capability_html::{capability_page, index_text, stat_text};
use crate::results::{utc_text, CheckIdentity, RunFilter, Store, StoreError};
use crate::run::{INVALID, PASSED};
use std::path::Path;
use std::time::SystemTime;

/// `results yield`.
pub(super) fn yields(store: &mut Store, filter: &RunFilter, json: bool) -> Result<i32, StoreError> {
    let rows = store.yields(filter)?;
    if json {
        let list: Vec<serde_json::Value> = rows
            .iter()
            .map(|r| {
                serde_json::json!({"recipe": r.recipe, "station": r.station, "day": r.day,
                    "units": r.units, "first_pass": r.first_pass, "final_pass": r.final_pass, "runs": r.runs,
                    "first_pass_yield_percent": r.first_pass_percent(), "final_yield_percent": r.final_percent()})
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&list).unwrap_or_default());
        return Ok(PASSED);
    }
    let percent = |v: f64| format!("{v:.1} %");
    let table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.recipe.clone(),
                r.station.clone(),
                r.day.clone(),
                r.units.to_string(),
                r.first_pass.to_string(),
                percent(r.first_pass_percent()),
                r.final_pass.to_string(),
                percent(r.final_percent()),
                r.runs.to_string(),
            ]
        })
        .collect();
    for line in table_lines(
        &[
            "recipe",
            "station",
            "day (UTC)",
            "units",
            "first pass",
            "FPY",
            "final pass",
            "final yield",
            "runs",
        ],
        &table,
    ) {
        println!("{line}");
    }
    if rows.is_empty() {
        println!("no finished runs{} in {}", hidden(filter), store.name());
    } else {
        println!(
            "FPY: units whose first run passed; final yield: units whose last run passed (of the units tested that day at that station). Refused and unfinished runs are left out{}.",
            if filter.include_void { "" } else { ", and voided runs (--include-void)" }
        );
    }
    Ok(PASSED)
}

/// ` (runs on the simulated drive are hidden: --simulated)` where they are.
fn hidden(filter: &RunFilter) -> &'static str {
    match filter.simulated {
        true => "",
        false => " (runs on the simulated drive are hidden: --simulated)",
    }
}

/// `results capability`.
pub(super) fn capability(
    store: &mut Store,
    check: &str,
    filter: &RunFilter,
    html: Option<&Path>,
    json: bool,
) -> Result<i32, StoreError> {
    let c = store.capability(check, filter)?;
    if c.n == 0 {
        let like = store.checks_like(check, filter, 8)?;
        println!("{}", no_such_check(check, &like));
        return Ok(PASSED);
    }
    if let Some(path) = html {
        if let Err(e) =
            crate::report::write_atomically(path, &capability_page(&c, crate::results::PageLinks::None))
        {
            eprintln!("error: {e}");
            return Ok(INVALID);
        }
    }
    let unit = c.unit.as_deref();
    if json {
        let v = serde_json::json!({"check": c.check, "key": c.key, "unit": c.unit, "n": c.n,
            "mean": c.mean, "sigma": c.sigma, "min": c.min, "max": c.max, "low": c.limits.low, "high": c.limits.high,
            "cp": c.cp, "cpk": c.cpk});
        println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
        return Ok(PASSED);
    }
    let limit = |v: Option<f64>| v.map_or_else(|| "none".into(), |v| crate::session::with_unit(v, unit));
    println!("check    {}", c.key.as_deref().unwrap_or(check));
    println!("n        {}", c.n);
    println!("mean     {}", stat_text(c.mean, 6, unit));
    println!("σ        {}  (n − 1)", stat_text(c.sigma, 3, unit));
    println!(
        "range    {} … {}",
        stat_text(c.min, 6, unit),
        stat_text(c.max, 6, unit)
    );
    println!(
        "limits   {} .. {}  (the newest run's)",
        limit(c.limits.low),
        limit(c.limits.high)
    );
    println!("Cp       {}", index_text(c.cp));
    match c.why_no_cpk() {
        Some(why) => println!("Cpk      — ({why})"),
        None => println!("Cpk      {}", index_text(c.cpk)),
    }
    if !c.other_limits.is_empty() {
        println!(
            "note: older runs had other limits ({}); Cp and Cpk are against the newest run's — narrow with --since",
            c.other_limits
                .iter()
                .map(|l| format!("{} .. {}", limit(l.low), limit(l.high)))
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
    Ok(PASSED)
}

/// `results void`.
pub(super) fn void(store: &mut Store, run: &str, why: &str, by: Option<&str>) -> Result<i32, StoreError> {
    let who = by
        .map(str::to_string)
        .or_else(|| std::env::var("USER").ok())
        .or_else(|| std::env::var("LOGNAME").ok())
        .filter(|w| !w.trim().is_empty());
    let Some(who) = who else {
        eprintln!("error: say who voids the run: --by NAME (there is no USER to take it from)");
        return Ok(INVALID);
    };
    let v = store.void(run, &who, &utc_text(SystemTime::now()), why)?;
    println!(
        "run {} voided by {} at {}: {} — it stays in {}, left out of yield, trend, capability and export unless --include-void",
        v.run,
        v.voided_by,
        v.voided_at,
        v.why,
        store.name()
    );
    Ok(PASSED)
}

/// What to say when no run has the check `check`: the checks of this store that a user may
/// have meant, named as `trend` takes them.
pub(super) fn no_such_check(check: &str, like: &[CheckIdentity]) -> String {
    let mut s = format!("no run has the check `{check}`");
    match like {
        [] => s.push_str(
            " — and no check in these runs is of that object; `drivescript results show RUN` lists a run's checks",
        ),
        _ => {
            s.push_str("; checks in these runs that are like it:");
            for id in like {
                s.push_str(&format!("\n  \"{}\"  (recipe `{}`, step {})", id.case_name(), id.recipe, id.path));
            }
        }
    }
    s
}
