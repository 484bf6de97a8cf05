//! What a run writes besides the console (trace, CSV, JUnit, HTML, verbosity, colour), as
//! the command line gives it. Only paths and switches; the writers are in `report`.

use clap::Args;
use std::path::PathBuf;

/// What a run writes besides the console.
#[derive(Debug, Clone, Default, Args)]
#[command(next_help_heading = "Output")]
pub struct OutputArgs {
    /// Print every telegram sent and received, with its time and meaning, to standard error.
    #[arg(short, long)]
    pub verbose: bool,
    /// Write every telegram to FILE as the run goes (`drivescript decode` reads it back).
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Stream every sample to FILE: time since the start, UTC time, step, object, value,
    /// unit (one row per value); flushed at least every 250 ms.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// One column per object instead of one row per value, in --csv and the `csv:` files of
    /// sample steps (and of a script's `sample`).
    #[arg(long, hide_short_help = true)]
    pub csv_wide: bool,
    /// Write a JUnit XML report: one test case per check, for CI servers.
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
    /// Write a self-contained HTML report with plots of every sampled series.
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<PathBuf>,
    /// Only what a CI log needs: failed steps and checks, errors, the drive's end state
    /// and the verdict line (no header, no passed steps, no live progress bar).
    #[arg(long)]
    pub quiet: bool,
    /// No live progress bar on a terminal: every line as a plain line.
    #[arg(long, hide_short_help = true)]
    pub no_progress: bool,
    /// Colour PASS/FAIL and the verdict: auto (on a terminal, unless NO_COLOR is set),
    /// always, never.
    #[arg(long, hide_short_help = true, value_name = "WHEN", value_enum, default_value_t = ColorWhen::Auto)]
    pub color: ColorWhen,
}

/// `--color`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorWhen {
    #[default]
    Auto,
    Always,
    Never,
}

impl ColorWhen {
    /// `None` for auto: the terminal and `NO_COLOR` decide.
    pub fn choice(self) -> Option<bool> {
        match self {
            ColorWhen::Auto => None,
            ColorWhen::Always => Some(true),
            ColorWhen::Never => Some(false),
        }
    }
}
