//! `results serve`: opens the store, starts its pages on the web layer, says where to
//! point the browser, and serves until a stop signal. Parses and prints only.

use super::listen_args::ListenArgs;
use crate::results::Locator;
use crate::run::{COMMUNICATION, INVALID, PASSED};
use crate::store_site::StoreSite;
use std::time::Duration;

pub(super) fn serve(locator: Locator, listen: &ListenArgs) -> i32 {
    let settings = match listen.settings() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return INVALID;
        }
    };
    let site = match StoreSite::open(locator) {
        Ok(site) => site,
        Err(e) => {
            eprintln!("error: {e}");
            return super::results_command::exit_code(&e);
        }
    };
    let server = match site.serve(settings) {
        Ok(server) => server,
        Err(e) => {
            eprintln!("error: {e}");
            return COMMUNICATION;
        }
    };
    println!(
        "{}; Ctrl-C stops it",
        listen.announcement(&server, "the results store's pages")
    );
    let stop = super::stop_signals::install(false);
    while stop.first().is_none() {
        stop.wait_real(Duration::from_millis(500));
    }
    server.shutdown();
    PASSED
}
