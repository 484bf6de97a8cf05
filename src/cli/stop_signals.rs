//! The process's stop signals, turned into stop requests: SIGINT, SIGTERM, SIGHUP and
//! SIGQUIT all ask for the same safe stop; a second one asks for the power stage to be
//! switched off at once. Only counts and tells the user; what a request does to the drive
//! is the runner's business.

use crate::stop_request::{StopRequests, StopSignal};
use std::io::Write;
use std::sync::{Arc, OnceLock};

static GLOBAL: OnceLock<Arc<StopRequests>> = OnceLock::new();

/// The process-wide stop requests, with the signal watcher started on first use; with
/// `announce`, each signal is explained on standard error as it arrives (a run; not the
/// simulator, for which a signal simply ends the program). When the signals cannot be
/// caught, the requests still work but never arrive from outside; the reason goes to
/// standard error once.
pub fn install(announce: bool) -> Arc<StopRequests> {
    GLOBAL
        .get_or_init(|| {
            let stop = Arc::new(StopRequests::new());
            if let Err(e) = watch(stop.clone(), announce) {
                say(&format!(
                    "warning: stop signals cannot be caught here ({e}); Ctrl-C, kill and a closed terminal will not run the safe stop"
                ));
            }
            stop
        })
        .clone()
}

/// Written with `write!`, never `eprintln!`: after SIGHUP the terminal is gone and a
/// failed write must not panic the thread that delivers the next signal.
fn say(text: &str) {
    let _ = writeln!(std::io::stderr(), "{text}");
}

fn announce(signal: StopSignal, count: usize) {
    match count {
        1 => say(&format!(
            "\n{} received: stopping safely (send any stop signal again, e.g. Ctrl-C, to switch the power stage off at once)",
            signal.describe()
        )),
        2 => say(&format!(
            "\n{} received again: switching the power stage off at once (disable voltage)",
            signal.name
        )),
        _ => say(&format!(
            "\n{}: already switching off; waiting for the drive to confirm",
            signal.name
        )),
    }
}

#[cfg(unix)]
fn watch(stop: Arc<StopRequests>, loud: bool) -> std::io::Result<()> {
    use signal_hook::iterator::Signals;
    let numbers: Vec<i32> = StopSignal::ALL.iter().map(|s| s.number).collect();
    let mut signals = Signals::new(numbers)?;
    std::thread::Builder::new()
        .name("stop-signals".into())
        .spawn(move || {
            let mut count = 0;
            for number in signals.forever() {
                let Some(signal) = StopSignal::from_number(number) else {
                    continue;
                };
                stop.request(signal);
                count += 1;
                if loud {
                    announce(signal, count);
                }
            }
        })?;
    Ok(())
}

#[cfg(not(unix))]
fn watch(stop: Arc<StopRequests>, loud: bool) -> std::io::Result<()> {
    let count = std::sync::atomic::AtomicUsize::new(0);
    ctrlc::set_handler(move || {
        stop.request(StopSignal::INT);
        let n = count.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
        if loud {
            announce(StopSignal::INT, n);
        }
    })
    .map_err(std::io::Error::other)
}
