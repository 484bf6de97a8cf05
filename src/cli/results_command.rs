//! `drivescript results`: list, show, report, export, trend and sync over the results
//! store. Parses and prints; the store and its pages are the library's (`results`).

use super::text_table::table_lines;
use crate::results::{export, utc_text, Locator, RunFilter, Spool, Store, StoreError, RESULTS_ENV};
use crate::run::{COMMUNICATION, FAILED, INVALID, PASSED};
use clap::{Args, Subcommand};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

#[derive(Debug, Args)]
/// Query the results store: runs, units, reports, trends, export
///
/// The results store: every run recorded as it went (recipe and its hash, unit, verdict,
/// checks, steps, the safe stop's end state, plot series). Runs on the built-in simulated
/// drive are hidden unless --simulated is given.
pub struct ResultsArgs {
    #[command(subcommand)]
    command: ResultsCommand,
    /// The store to read [default: $DRIVESCRIPT_RESULTS, else the user's data directory].
    #[arg(long, global = true, value_name = "PATH|postgres://…")]
    results: Option<String>,
}

#[derive(Debug, Subcommand)]
enum ResultsCommand {
    /// The newest runs, newest first.
    List {
        #[command(flatten)]
        filter: FilterArgs,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// One run: its facts, every step and check.
    Show {
        /// The run's id (or the start of it).
        run: String,
        #[arg(long)]
        json: bool,
    },
    /// An HTML record of one run, or of one unit over all its runs (the commissioning
    /// certificate).
    Report {
        /// The run's id (or the start of it).
        #[arg(required_unless_present = "unit", conflicts_with = "unit")]
        run: Option<String>,
        /// The unit's serial number.
        #[arg(long, value_name = "SERIAL")]
        unit: Option<String>,
        /// Include runs on the built-in simulated drive.
        #[arg(long)]
        simulated: bool,
        /// Write the page to FILE (default: standard output).
        #[arg(short, long, value_name = "FILE")]
        output: Option<PathBuf>,
    },
    /// The runs as JSON, CSV (one row per check) or JUnit XML.
    Export {
        #[command(flatten)]
        filter: FilterArgs,
        #[arg(long, value_enum, default_value_t = ExportFormat::Json)]
        format: ExportFormat,
        /// Write to FILE (default: standard output).
        #[arg(short, long, value_name = "FILE")]
        output: Option<PathBuf>,
    },
    /// One check's measured value across runs and units, with the limits it had in each
    /// run: the same check whatever its limits (its object, statistic and kind of limit,
    /// or the name the recipe gave it).
    Trend {
        /// The check: its name as reports show it (`speed_actual mean near 3000 rpm ± 1 %`)
        /// or without its limits (`speed_actual mean near`).
        check: String,
        #[command(flatten)]
        filter: FilterArgs,
        /// Also write an HTML page with the plot to FILE.
        #[arg(long, value_name = "FILE")]
        html: Option<PathBuf>,
        #[arg(long)]
        json: bool,
    },
    /// Deliver the runs spooled while the store could not be reached.
    Sync,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ExportFormat {
    Json,
    Csv,
    Junit,
}

#[derive(Debug, Args)]
struct FilterArgs {
    /// Only the unit with this serial number.
    #[arg(long, value_name = "SERIAL")]
    unit: Option<String>,
    /// Only this recipe (its name or its path as run).
    #[arg(long)]
    recipe: Option<String>,
    /// Only runs that ended so: passed, failed, error, interrupted, panic, incomplete.
    #[arg(long, value_parser = ["passed", "failed", "error", "interrupted", "panic", "refused", "incomplete"])]
    verdict: Option<String>,
    /// Only runs started since: a date (2026-11-01), a UTC time (2026-11-01T08:00:00Z) or
    /// a time ago (7d, 12h).
    #[arg(long, value_name = "WHEN", value_parser = parse_since)]
    since: Option<String>,
    /// Include runs on the built-in simulated drive.
    #[arg(long)]
    simulated: bool,
    /// At most this many runs (the newest) [default: 50 for list, all otherwise].
    #[arg(long, value_name = "N")]
    limit: Option<u64>,
}

impl FilterArgs {
    fn filter(&self, default_limit: Option<u64>) -> RunFilter {
        RunFilter {
            unit: self.unit.clone(),
            recipe: self.recipe.clone(),
            verdict: self.verdict.clone(),
            since: self.since.clone(),
            simulated: self.simulated,
            limit: self.limit.or(default_limit),
        }
    }
}

/// `--since`: a stored UTC time to compare with.
fn parse_since(text: &str) -> Result<String, crate::run::BadValue> {
    let t = text.trim();
    if let Ok(ago) = humantime::parse_duration(t) {
        return Ok(utc_text(SystemTime::now() - ago));
    }
    let full = if t.len() == 10 {
        format!("{t}T00:00:00Z")
    } else {
        t.to_string()
    };
    humantime::parse_rfc3339_weak(&full).map(utc_text).map_err(|_| {
        crate::run::BadValue(format!(
            "`{text}`: write a date (2026-11-01), a UTC time (2026-11-01T08:00:00Z) or a time ago (7d)"
        ))
    })
}

fn exit_code(e: &StoreError) -> i32 {
    match e {
        StoreError::Unreachable { .. } | StoreError::Spool { .. } | StoreError::Query { .. } => COMMUNICATION,
        StoreError::NotFound(_) => FAILED,
        StoreError::Foreign { .. } | StoreError::Newer { .. } => INVALID,
    }
}

pub fn results(args: &ResultsArgs) -> i32 {
    let Some((locator, _)) = Locator::resolve(args.results.as_deref()) else {
        eprintln!("error: no results store: give --results PATH or set {RESULTS_ENV} (there is no HOME or XDG_DATA_HOME for the default)");
        return INVALID;
    };
    match command(&args.command, &locator) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            exit_code(&e)
        }
    }
}

fn command(command: &ResultsCommand, locator: &Locator) -> Result<i32, StoreError> {
    if let ResultsCommand::Sync = command {
        let spool = Spool::new(locator.spool_path());
        if !spool.pending() {
            println!("nothing to deliver: no spooled runs for {}", locator.name());
            return Ok(PASSED);
        }
        let mut store = locator.open(true)?;
        let done = spool.deliver(&mut store)?;
        println!(
            "delivered {} record(s) of {} run(s) to {}",
            done.records,
            done.runs,
            store.name()
        );
        if done.unreadable > 0 {
            eprintln!(
                "warning: {} line(s) of {} were no record; kept in {}.bad",
                done.unreadable,
                spool.path().display(),
                spool.path().display()
            );
        }
        return Ok(PASSED);
    }
    let mut store = locator.open(false)?;
    match command {
        ResultsCommand::List { filter, json } => list(&mut store, &filter.filter(Some(50)), *json),
        ResultsCommand::Show { run, json } => show(&mut store, run, *json),
        ResultsCommand::Report {
            run,
            unit,
            simulated,
            output,
        } => {
            let page = match (run, unit) {
                (_, Some(serial)) => {
                    let runs = store.unit_runs(serial, *simulated)?;
                    if runs.is_empty() {
                        return Err(StoreError::NotFound(format!(
                            "no run of unit {serial} in {}{}",
                            store.name(),
                            if *simulated {
                                ""
                            } else {
                                " (add --simulated for runs on the simulated drive)"
                            }
                        )));
                    }
                    crate::results::certificate_html::unit_certificate(serial, &runs)
                }
                (Some(run), None) => crate::results::certificate_html::run_certificate(&store.run(run)?),
                (None, None) => return Ok(INVALID),
            };
            written(output.as_deref(), &page)
        }
        ResultsCommand::Export {
            filter,
            format,
            output,
        } => {
            let runs = store.with_checks(&filter.filter(None))?;
            let text = match format {
                ExportFormat::Json => export::json(&runs),
                ExportFormat::Csv => export::csv(&runs),
                ExportFormat::Junit => export::junit(&runs),
            };
            written(output.as_deref(), &text)
        }
        ResultsCommand::Trend {
            check,
            filter,
            html,
            json,
        } => {
            let points = store.trend(check, &filter.filter(None))?;
            if let Some(path) = html {
                let page = crate::results::trend_html::trend_page(check, &points);
                if let Err(e) = crate::report::write_atomically(path, &page) {
                    eprintln!("error: {e}");
                    return Ok(INVALID);
                }
            }
            if *json {
                let list: Vec<serde_json::Value> = points
                    .iter()
                    .map(|p| {
                        serde_json::json!({"run": p.run, "started_at": p.started_at, "serial": p.serial,
                            "check": p.name, "key": p.key,
                            "measured": p.measured, "unit": p.unit, "low": p.low, "high": p.high, "passed": p.passed,
                            "marginal": p.marginal})
                    })
                    .collect();
                println!("{}", serde_json::to_string_pretty(&list).unwrap_or_default());
            } else {
                let rows: Vec<Vec<String>> = points
                    .iter()
                    .map(|p| {
                        vec![
                            p.started_at.clone(),
                            p.serial.clone().unwrap_or_default(),
                            p.measured_text(),
                            p.limits_text().unwrap_or_default(),
                            p.verdict().into(),
                            p.run.clone(),
                        ]
                    })
                    .collect();
                for line in table_lines(
                    &["started (UTC)", "unit", "measured", "limits", "result", "run"],
                    &rows,
                ) {
                    println!("{line}");
                }
                if points.is_empty() {
                    println!(
                        "no run has the check `{check}` (a check's name as the reports show it, or without its limits: `speed_actual mean near`)"
                    );
                }
            }
            Ok(PASSED)
        }
        ResultsCommand::Sync => Ok(PASSED),
    }
}

fn written(path: Option<&Path>, text: &str) -> Result<i32, StoreError> {
    match path {
        Some(p) => match crate::report::write_atomically(p, text) {
            Ok(()) => {
                println!("wrote {}", p.display());
                Ok(PASSED)
            }
            Err(e) => {
                eprintln!("error: {e}");
                Ok(INVALID)
            }
        },
        None => {
            print!("{text}");
            Ok(PASSED)
        }
    }
}

fn list(store: &mut Store, filter: &RunFilter, json: bool) -> Result<i32, StoreError> {
    let runs = store.list(filter)?;
    if json {
        let list: Vec<serde_json::Value> = runs.iter().map(export::run_json).collect();
        println!("{}", serde_json::to_string_pretty(&list).unwrap_or_default());
        return Ok(PASSED);
    }
    let rows: Vec<Vec<String>> = runs
        .iter()
        .map(|r| {
            vec![
                r.run.id.clone(),
                r.run.started_at.clone(),
                r.verdict().to_uppercase(),
                r.run.recipe.clone(),
                r.run.unit.serial.clone().unwrap_or_default(),
                r.run.unit.station.clone().unwrap_or_default(),
                if r.run.simulated {
                    "simulated".into()
                } else {
                    r.run.drive.clone()
                },
            ]
        })
        .collect();
    for line in table_lines(
        &[
            "run",
            "started (UTC)",
            "verdict",
            "recipe",
            "unit",
            "station",
            "drive",
        ],
        &rows,
    ) {
        println!("{line}");
    }
    if runs.is_empty() {
        println!(
            "no runs{} in {}",
            if filter.simulated {
                ""
            } else {
                " (runs on the simulated drive are hidden: --simulated)"
            },
            store.name()
        );
    }
    Ok(PASSED)
}

fn show(store: &mut Store, id: &str, json: bool) -> Result<i32, StoreError> {
    let r = store.run(id)?;
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&export::run_json(&r)).unwrap_or_default()
        );
        return Ok(PASSED);
    }
    println!("run      {}", r.run.id);
    println!(
        "recipe   {} ({}, sha256 {})",
        r.run.recipe,
        r.run.recipe_path,
        r.run.recipe_sha256.as_deref().unwrap_or("not read")
    );
    println!(
        "drive    {}{}",
        r.run.drive,
        if r.run.simulated { " (simulated)" } else { "" }
    );
    let unit = &r.run.unit;
    for (name, value) in [
        ("unit", &unit.serial),
        ("part", &unit.part),
        ("operator", &unit.operator),
        ("station", &unit.station),
    ] {
        if let Some(v) = value {
            println!("{name:<8} {v}");
        }
    }
    if !r.run.params.is_empty() {
        let p: Vec<String> = r.run.params.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        println!("params   {}", p.join(", "));
    }
    println!("started  {}", r.run.started_at);
    for s in &r.steps {
        println!(
            "  {:>6}  {}  {}  {}",
            s.step,
            if s.ok { "ok  " } else { "FAIL" },
            s.label,
            s.detail
        );
    }
    for c in &r.checks {
        println!(
            "        {}  {}: {}",
            match (c.passed, c.marginal) {
                (true, false) => "PASS",
                (true, true) => "MARGINAL",
                (false, _) => "FAIL",
            },
            c.name,
            c.message
        );
        if let (Some(run), Some(value)) = (&c.reference_run, c.reference_value) {
            println!(
                "                  reference: run {run} of {}, measured {}",
                c.reference_at.as_deref().unwrap_or("an unknown time"),
                crate::session::number(value)
            );
        }
    }
    match &r.end {
        Some(e) => {
            if let Some(state) = &e.final_state {
                let speed = e
                    .final_speed
                    .map(|v| format!(" at {}", crate::session::with_unit(v, e.speed_unit.as_deref())))
                    .unwrap_or_default();
                println!(
                    "drive left in {state}{speed}{}",
                    if e.stop_confirmed {
                        ""
                    } else {
                        " — stop NOT confirmed"
                    }
                );
            }
            println!(
                "ended    {} — {} (exit code {})",
                e.ended_at,
                e.verdict.to_uppercase(),
                e.exit_code
            );
            if let Some(reason) = &e.reason {
                println!("reason   {reason}");
            }
        }
        None => println!("INCOMPLETE — the run never finished (killed, power cut, or still running)"),
    }
    Ok(PASSED)
}
