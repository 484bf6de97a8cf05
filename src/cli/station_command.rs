//! `drivescript station`: serves the operator station's page for the recipes given, with
//! every option of `run` passed on to each run, until a stop signal (which stops a run
//! under way safely first). Parses, prints the address and the exit code; the station and
//! the web layer are the library's.

use super::listen_args::ListenArgs;
use super::stop_signals;
use crate::family::Registry;
use crate::run::{RunOptions, INVALID};
use crate::session::PANIC_EXIT;
use crate::station::{routes, supervise, Ended, Station, StationSetup, ASSETS};
use crate::web::WebServer;
use clap::Args;
use std::path::PathBuf;
use std::sync::Arc;

#[derive(Debug, Args)]
/// Serve the operator station: a browser page that runs the given recipes
///
/// Serve a page for the operator at a test bench: choose one of the recipes given here,
/// scan or type the unit's serial, Start, answer the operator steps in large dialogs,
/// watch the live plots, and read PASS, FAIL or MARGINAL with what failed and how the drive
/// was left. Each run is the same run as `drivescript run` (same checks, reports, results
/// store and safe stop); one run at a time, each writing its HTML report under --output-dir
/// ({serial}-{date}T{time}.html unless --report names it). The Stop button is a stop request as Ctrl-C (a
/// second press switches the power stage off). Closing the page never stops or pauses a
/// run; reopening it rejoins. Ctrl-C or SIGTERM to the station stops a run under way
/// safely before the station exits. Listens on 127.0.0.1 unless --listen says otherwise;
/// any other address needs a token (--token-file, or one is made and printed in the
/// address to open).
pub struct StationArgs {
    /// Recipe files (`.yaml`) or Rhai scripts (`.rhai`): the only ones the page can start.
    #[arg(value_name = "RECIPE", required = true)]
    recipes: Vec<PathBuf>,
    #[command(flatten)]
    listen: ListenArgs,
    #[command(flatten)]
    options: RunOptions,
}

pub fn station(args: &StationArgs, registry: &Registry) -> i32 {
    let setup = match StationSetup::new(registry.clone(), &args.recipes, args.options.clone()) {
        Ok(s) => s,
        Err(e) => {
            eprint!(
                "{}",
                e.render(std::io::IsTerminal::is_terminal(&std::io::stderr()))
            );
            eprintln!("error: the station starts only with recipes that pass their checks; nothing was sent");
            return e.exit_code().max(INVALID);
        }
    };
    let settings = match args.listen.settings() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return INVALID;
        }
    };
    let signals = stop_signals::install_for_a_drive();
    let names: Vec<String> = setup.recipes.iter().map(|r| r.name.clone()).collect();
    let station = Arc::new(Station::new(setup));
    let pages = routes(station.clone(), settings.token().text());
    let server = match WebServer::start(settings, pages, ASSETS) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return INVALID;
        }
    };
    println!(
        "station: {} ({})",
        names.join(", "),
        if args.options.connection.is_simulated() {
            "on the built-in simulated drive"
        } else {
            "on the drive given"
        }
    );
    println!(
        "{}",
        args.listen.announcement(&server, "open the operator station")
    );
    println!("Ctrl-C or SIGTERM ends the station (a run under way is stopped safely first)");
    match supervise(&station, &signals, &|| server.is_serving()) {
        Ended::Signal(signal) => signal.exit_code(),
        Ended::ServerFailed => {
            eprintln!(
                "error: the station's web server stopped (a bug); the run under way was stopped safely"
            );
            PANIC_EXIT
        }
    }
}
