//! The process's stop signals, turned into stop requests: SIGINT, SIGTERM, SIGHUP and
//! SIGQUIT (on Windows Ctrl-C, Ctrl-Break and the console window closing) all ask for the
//! same safe stop; a second one asks for the power stage to be switched off at once. Only
//! counts and tells the user; what a request does to the drive is the runner's business.

use crate::stop_request::{StopRequests, StopSignal};
use std::io::Write;
use std::sync::{Arc, OnceLock};

static GLOBAL: OnceLock<Arc<StopRequests>> = OnceLock::new();

/// What a command that moves a drive needs before it opens one: the stop requests, each
/// signal announced as it arrives, and the panic notice that says the safe stop runs next.
pub fn install_for_a_drive() -> Arc<StopRequests> {
    super::panic_notice::install();
    install(true)
}

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

/// Windows: Ctrl-C, Ctrl-Break and the console window closing (or logging off, shutting
/// down) through the console's own handler list; no crate, one system call.
#[cfg(windows)]
fn watch(stop: Arc<StopRequests>, loud: bool) -> std::io::Result<()> {
    console::watch(stop, loud)
}

/// Elsewhere (neither Unix nor Windows) nothing arrives from outside.
#[cfg(not(any(unix, windows)))]
fn watch(_: Arc<StopRequests>, _: bool) -> std::io::Result<()> {
    Err(std::io::Error::other("no stop signals on this system"))
}

#[cfg(windows)]
mod console {
    use super::{announce, Arc, OnceLock, StopRequests, StopSignal};
    use std::sync::atomic::{AtomicUsize, Ordering};

    type Handler = unsafe extern "system" fn(u32) -> i32;

    #[link(name = "kernel32")]
    extern "system" {
        fn SetConsoleCtrlHandler(handler: Option<Handler>, add: i32) -> i32;
    }

    const CTRL_C_EVENT: u32 = 0;
    const CTRL_BREAK_EVENT: u32 = 1;

    static WATCHED: OnceLock<(Arc<StopRequests>, bool)> = OnceLock::new();
    static COUNT: AtomicUsize = AtomicUsize::new(0);

    pub fn watch(stop: Arc<StopRequests>, loud: bool) -> std::io::Result<()> {
        if WATCHED.set((stop, loud)).is_err() {
            return Ok(());
        }
        // SAFETY: `on_event` is a plain function for the life of the process; adding a
        // handler has no other precondition.
        if unsafe { SetConsoleCtrlHandler(Some(on_event), 1) } == 0 {
            return Err(std::io::Error::last_os_error());
        }
        Ok(())
    }

    /// Called by Windows on a thread of its own for each console event. It must not
    /// unwind (nothing here panics: the requests' lock ignores poisoning, `announce`
    /// ignores a failed write).
    pub(super) unsafe extern "system" fn on_event(event: u32) -> i32 {
        let Some((stop, loud)) = WATCHED.get() else {
            return 0;
        };
        let signal = match event {
            CTRL_C_EVENT => StopSignal::INT,
            CTRL_BREAK_EVENT => StopSignal::CTRL_BREAK,
            _ => StopSignal::CONSOLE_CLOSED,
        };
        stop.request(signal);
        let count = COUNT.fetch_add(1, Ordering::SeqCst) + 1;
        if *loud {
            announce(signal, count);
        }
        if event > CTRL_BREAK_EVENT {
            // A closed window, a log-off or a shutdown: Windows ends the process as soon
            // as this returns, so it returns never; the process ends when the safe stop
            // is done and the run exits, or when Windows' own time is up (5 s for a
            // closed window).
            loop {
                std::thread::park();
            }
        }
        1
    }
}

#[cfg(all(test, windows))]
mod tests {
    use super::console::on_event;
    use super::*;
    use std::time::Duration;

    /// Windows calls the handler as here (under Wine too); a real Ctrl-C under Wine is
    /// tested end to end in tests/integration/end_to_end.rs.
    #[test]
    fn each_console_event_asks_for_the_safe_stop_and_a_closing_window_waits_for_it() {
        let stop = install(false);
        // SAFETY: the handler takes any event number; it is called here as Windows does.
        assert_eq!(unsafe { on_event(1) }, 1);
        assert_eq!(stop.first(), Some(StopSignal::CTRL_BREAK));
        assert_eq!(unsafe { on_event(0) }, 1);
        assert_eq!(stop.count_at(Duration::ZERO), 2);
        // A closing window: the request arrives, and the handler does not return (Windows
        // would end the process then), so the safe stop has the time Windows gives.
        let waiting = std::thread::spawn(|| unsafe { on_event(2) });
        let started = std::time::Instant::now();
        while stop.count_at(Duration::ZERO) < 3 {
            assert!(
                started.elapsed() < Duration::from_secs(10),
                "no request from the closing window"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
        std::thread::sleep(Duration::from_millis(300));
        assert!(!waiting.is_finished(), "the handler returned on a closing window");
        assert_eq!(StopSignal::CONSOLE_CLOSED.exit_code(), 129);
    }
}
