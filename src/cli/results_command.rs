//! `drivescript results`: list, show, report, export, trend, yield, capability, void,
//! sync and serve over the results store. Parses and prints; the store and its pages are the
//! library's (`results`).

use super::results_listing::{list, show};
use super::text_table::table_lines;
use crate::results::filter_time::{parse_since, parse_until};
use crate::results::{export, Locator, PageLinks, RunFilter, Spool, StoreError, RESULTS_ENV};
use crate::run::{COMMUNICATION, FAILED, INVALID, PASSED};
use clap::{Args, Subcommand};
use std::path::{Path, PathBuf};

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
    /// certificate; voided runs are on it, marked void).
    Report {
        /// The run's id (or the start of it).
        #[arg(required_unless_present = "unit", conflicts_with = "unit")]
        run: Option<String>,
        #[command(flatten)]
        filter: FilterArgs,
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
        /// The check: its JUnit test-case name (`Stage 2, 12000 rpm / speed_actual mean
        /// near`), its name as the console shows it (`speed_actual mean near 3000 rpm ± 1
        /// %`) or without its limits (`speed_actual mean near`). A name that stands for
        /// several measurements (several stages, places or recipes) is refused with the
        /// names that tell them apart.
        check: String,
        #[command(flatten)]
        filter: FilterArgs,
        /// Also write an HTML page with the plot to FILE.
        #[arg(long, value_name = "FILE")]
        html: Option<PathBuf>,
        /// Print JSON instead of a table: one object per run with run, started_at,
        /// serial, recipe, recipe_sha256, stage, step, check, key, measured, unit, low,
        /// high, passed, marginal, simulated.
        #[arg(long)]
        json: bool,
    },
    /// First-pass and final yield per recipe, station and day (UTC): of the units tested,
    /// how many passed at their first run, and at their last. Runs refused before they
    /// started and runs that never finished are left out, voided runs unless
    /// --include-void.
    Yield {
        #[command(flatten)]
        filter: FilterArgs,
        #[arg(long)]
        json: bool,
    },
    /// Process capability of one check across units: n, mean, σ, Cp and Cpk against the
    /// spec limits its recipe gave (the newest run's), from the same values `trend` shows.
    Capability {
        /// The check, as for `trend`.
        check: String,
        #[command(flatten)]
        filter: FilterArgs,
        /// Also write an HTML page with a histogram to FILE.
        #[arg(long, value_name = "FILE")]
        html: Option<PathBuf>,
        #[arg(long)]
        json: bool,
    },
    /// Mark a run void (the wrong unit scanned, a bench fault): it stays in the store,
    /// marked with who, when and why, shown on its certificate, and left out of yield,
    /// trend, capability and export unless --include-void. A void is never changed or
    /// undone; nothing is deleted.
    Void {
        /// The run's id (or the start of it).
        run: String,
        /// Why it is void: what the quality record says.
        #[arg(long, value_name = "TEXT")]
        why: String,
        /// Who voids it [default: $USER].
        #[arg(long, value_name = "NAME")]
        by: Option<String>,
    },
    /// Deliver the runs spooled while the store could not be reached.
    Sync,
    /// Serve the store's pages to a browser, read-only, until Ctrl-C: the run list with
    /// its filters, each run's report, each unit's certificate, trend, capability and
    /// yield. Listens on 127.0.0.1:8080 unless --listen says otherwise.
    Serve {
        #[command(flatten)]
        listen: super::listen_args::ListenArgs,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ExportFormat {
    Json,
    Csv,
    Junit,
}

#[derive(Debug, Args)]
pub(super) struct FilterArgs {
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
    /// Only runs started before: a UTC time, a time ago, or a date (the whole of that day
    /// is taken: --until 2026-11-30 takes runs of 30 November).
    #[arg(long, value_name = "WHEN", value_parser = parse_until)]
    until: Option<String>,
    /// Only runs at this station.
    #[arg(long)]
    station: Option<String>,
    /// Only runs by this operator.
    #[arg(long)]
    operator: Option<String>,
    /// Only units of this part number.
    #[arg(long)]
    part: Option<String>,
    /// Include voided runs (`results void`); list and report always show them, marked.
    #[arg(long)]
    include_void: bool,
    /// Include runs on the built-in simulated drive.
    #[arg(long)]
    simulated: bool,
    /// At most this many runs (the newest) [default: 50 for list, all otherwise].
    #[arg(long, value_name = "N")]
    limit: Option<u64>,
}

impl FilterArgs {
    pub(super) fn filter(&self, default_limit: Option<u64>) -> RunFilter {
        RunFilter {
            unit: self.unit.clone(),
            recipe: self.recipe.clone(),
            verdict: self.verdict.clone(),
            since: self.since.clone(),
            until: self.until.clone(),
            station: self.station.clone(),
            operator: self.operator.clone(),
            part: self.part.clone(),
            simulated: self.simulated,
            include_void: self.include_void,
            limit: self.limit.or(default_limit),
        }
    }
}

pub(super) fn exit_code(e: &StoreError) -> i32 {
    match e {
        StoreError::Unreachable { .. } | StoreError::Spool { .. } | StoreError::Query { .. } => COMMUNICATION,
        StoreError::NotFound(_) => FAILED,
        StoreError::Foreign { .. } | StoreError::Newer { .. } | StoreError::Refused(_) => INVALID,
    }
}

pub fn results(args: &ResultsArgs) -> i32 {
    let Some((locator, _)) = Locator::resolve(args.results.as_deref()) else {
        let default_from = if cfg!(windows) {
            "LOCALAPPDATA"
        } else {
            "HOME or XDG_DATA_HOME"
        };
        eprintln!("error: no results store: give --results PATH or set {RESULTS_ENV} (there is no {default_from} for the default)");
        return INVALID;
    };
    if let ResultsCommand::Serve { listen } = &args.command {
        return super::results_serve::serve(locator, listen);
    }
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
        // The others are delivered; these stay, each with why.
        for (run, why) in &done.refused {
            eprintln!("error: run {run} stays in {}: {why}", spool.path().display());
        }
        return Ok(if done.refused.is_empty() {
            PASSED
        } else {
            COMMUNICATION
        });
    }
    let mut store = match locator.open(false) {
        // Runs that never reached the store may still wait on this bench.
        Err(StoreError::NotFound(text)) => {
            let spool = Spool::new(locator.spool_path());
            let waiting = spool.runs().len();
            if waiting == 0 {
                return Err(StoreError::NotFound(text));
            }
            return Err(StoreError::NotFound(format!(
                "{text}; {waiting} run(s) kept on this bench wait in {} — `drivescript results sync` delivers them",
                spool.path().display()
            )));
        }
        opened => opened?,
    };
    match command {
        ResultsCommand::List { filter, json } => {
            let spool = Spool::new(locator.spool_path());
            let filter = RunFilter {
                include_void: true,
                ..filter.filter(Some(50))
            };
            list(&mut store, &filter, *json, &spool)
        }
        ResultsCommand::Show { run, json } => show(&mut store, run, *json),
        ResultsCommand::Report { run, filter, output } => {
            let page = match (run, &filter.unit) {
                (_, Some(serial)) => {
                    let chosen = RunFilter {
                        include_void: true,
                        ..filter.filter(None)
                    };
                    let runs = store.unit_runs_in(&chosen)?;
                    if runs.is_empty() {
                        return Err(StoreError::NotFound(format!(
                            "no run of unit {serial} in {}{}",
                            store.name(),
                            if filter.simulated {
                                ""
                            } else {
                                " (add --simulated for runs on the simulated drive)"
                            }
                        )));
                    }
                    crate::results::certificate_html::unit_certificate(serial, &runs, PageLinks::None)
                }
                (Some(run), None) => {
                    crate::results::certificate_html::run_certificate(&store.run(run)?, PageLinks::None)
                }
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
                let page = crate::results::trend_html::trend_page(check, &points, PageLinks::None);
                if let Err(e) = crate::report::write_atomically(path, &page) {
                    eprintln!("error: {e}");
                    return Ok(INVALID);
                }
            }
            if *json {
                let list: Vec<serde_json::Value> = points
                    .iter()
                    .map(|p| {
                        serde_json::json!({"run": p.run.id, "started_at": p.run.started_at, "serial": p.run.unit.serial,
                            "recipe": p.run.recipe, "recipe_sha256": p.run.recipe_sha256, "stage": p.check.stage, "step": p.check.step,
                            "check": p.check.name, "key": p.key(),
                            "measured": p.check.measured, "unit": p.check.unit, "low": p.check.limits.low, "high": p.check.limits.high, "passed": p.check.passed,
                            "marginal": p.check.marginal, "simulated": p.run.simulated})
                    })
                    .collect();
                println!("{}", serde_json::to_string_pretty(&list).unwrap_or_default());
            } else {
                let rows: Vec<Vec<String>> = points
                    .iter()
                    .map(|p| {
                        vec![
                            p.run.started_at.clone(),
                            p.run.unit.serial.clone().unwrap_or_default(),
                            p.measured_text(),
                            p.limits_text().unwrap_or_default(),
                            p.result_text(),
                            p.run.id.clone(),
                        ]
                    })
                    .collect();
                if !rows.is_empty() {
                    for line in table_lines(
                        &["started (UTC)", "unit", "measured", "limits", "result", "run"],
                        &rows,
                    ) {
                        println!("{line}");
                    }
                }
                if points.is_empty() {
                    let like = store.checks_like(check, &filter.filter(None), 8)?;
                    println!("{}", super::results_quality::no_such_check(check, &like));
                }
            }
            Ok(PASSED)
        }
        ResultsCommand::Yield { filter, json } => {
            super::results_quality::yields(&mut store, &filter.filter(None), *json)
        }
        ResultsCommand::Capability {
            check,
            filter,
            html,
            json,
        } => super::results_quality::capability(
            &mut store,
            check,
            &filter.filter(None),
            html.as_deref(),
            *json,
        ),
        ResultsCommand::Void { run, why, by } => {
            super::results_quality::void(&mut store, run, why, by.as_deref())
        }
        ResultsCommand::Sync | ResultsCommand::Serve { .. } => Ok(PASSED),
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
