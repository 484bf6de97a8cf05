//! The operator station: a front end beside `cli` that serves a browser page for the
//! person at a test bench — choose one of the recipes the station was started with, scan
//! the unit's serial, Start, follow large dialogs, watch the live plots and read PASS or
//! FAIL. Each run goes through the one run pipeline with the same observers and the same
//! operator and stop seams as `run` on a terminal; nothing of the run is re-implemented.
//! The HTTP routes are here on the shared web layer (`crate::web`); the page is embedded.
//!
//! Must not parse a command line (the `cli` does), must not take a path, recipe text or
//! command from the browser, and must never be on the safe stop's path: a page that
//! closes, a network that drops or a server that fails leaves the run supervised, and a
//! failing server stops it.

mod bench_history;
mod event_log;
mod page_answers;
mod page_observer;
mod plot_buffer;
mod station;
mod station_routes;
mod station_setup;
mod station_view;
mod supervise;

pub use event_log::{Catch, EventLog, EVENTS};
pub use plot_buffer::POINTS;
pub use station::{result_view, Refused, Station};
pub use station_routes::{routes, ASSETS};
pub use station_setup::{StationRecipe, StationSetup};
pub use station_view::{StationView, SERIES, STEPS};
pub use supervise::{supervise, Ended};

#[cfg(test)]
mod station_tests;
