//! A recipe's `watch:` intervals against what its serial line carries: each watch reads
//! its object every `every`, and those reads must leave the line to the steps. The time a
//! read occupies the wire is measured as the latency note measures it ([`LineExchange`]:
//! the family's own request and reply at the line's settings); watches whose reads would
//! take more than half of the line are refused before anything opens, by `check` and
//! `run` alike, for a serial line the command line names. Sends nothing.

use super::line_exchange::LineExchange;
use super::{ConnectionArgs, LoadedPlan, RunError, RunPlan};
use crate::dictionary::Dictionary;
use crate::family::Registry;
use std::sync::Arc;

/// The share of the line the watches may take: the rest is the steps'.
const WATCH_SHARE: f64 = 0.5;

/// `Ok` when the watches of `loaded` read often enough to fit the serial line of
/// `connection` (one it names with `--port` or `--baud`); also when nothing is known of a
/// wire: no line named, a CAN bus, a TCP server, a script's watches with computed words
/// (known only as it runs). Otherwise why not, with each watch's place (exit code 2).
pub fn watches_fit_the_line(
    loaded: &LoadedPlan,
    registry: &Registry,
    connection: &ConnectionArgs,
) -> Result<(), RunError> {
    let watches = match &loaded.plan {
        RunPlan::Recipe(recipe) => crate::recipe::all_watches(recipe),
        RunPlan::Script(script) => script.watches.iter().collect(),
    };
    let line_named = connection.port.is_some() || connection.baud.is_some();
    if watches.is_empty() || !line_named || connection.tcp.is_some() || connection.can.is_some() {
        return Ok(());
    }
    let mut measured: Vec<(String, Option<LineExchange>)> = Vec::new();
    let mut share = 0.0;
    let mut reads = Vec::new();
    for w in &watches {
        let crate::session::Condition::Value { object, .. } = &w.condition else {
            continue;
        };
        let exchange = match measured.iter().find(|(n, _)| *n == object.name) {
            Some((_, e)) => e.clone(),
            None => {
                let e = drive_of(loaded, &object.name).and_then(|(dictionary, own)| {
                    LineExchange::measure(registry, connection, dictionary, &[own.to_string()])
                });
                measured.push((object.name.clone(), e.clone()));
                e
            }
        };
        let Some(exchange) = exchange else {
            continue;
        };
        let wire = exchange.wire_time();
        share += wire.as_secs_f64() / w.every.as_secs_f64();
        reads.push(format!(
            "  {}: watch {} every {}: each read is {} bytes, {:.1} ms on the wire at {}",
            w.origin,
            w.condition,
            crate::session::show_duration(w.every),
            exchange.bytes,
            wire.as_secs_f64() * 1e3,
            exchange.settings
        ));
    }
    if share <= WATCH_SHARE {
        return Ok(());
    }
    Err(RunError::Invalid(format!(
        "error: the watches would take {:.0} % of the line's time on the wire alone, more than the {:.0} % they may leave the steps; nothing was sent\n{}\n  help: read less often (a larger `every`; {} ms at the least) or at a higher baud rate (--baud)",
        share * 100.0,
        WATCH_SHARE * 100.0,
        reads.join("\n"),
        shortest_every(share, &watches)
    )))
}

/// The interval at which every watch would fit: each one's scaled by how far over they are.
/// In whole milliseconds, rounded up.
fn shortest_every(share: f64, watches: &[&crate::session::Watch]) -> u128 {
    let longest = watches.iter().map(|w| w.every).max().unwrap_or_default();
    (longest.as_secs_f64() * 1e3 * share / WATCH_SHARE).ceil() as u128
}

/// The dictionary `name` is read on and its own name there (`left.speed_actual` is
/// `left`'s `speed_actual`).
fn drive_of<'a>(loaded: &'a LoadedPlan, name: &'a str) -> Option<(&'a Arc<Dictionary>, &'a str)> {
    if loaded.drive_dictionaries.is_empty() {
        return Some((&loaded.dictionary, name));
    }
    let (drive, own) = name.split_once('.')?;
    let (_, dictionary) = loaded.drive_dictionaries.iter().find(|(n, _)| n == drive)?;
    Some((dictionary, own))
}
