//! Ctrl-C, counted. The first press asks for a safe stop (finish the current telegram, run
//! `finally`); the second asks for the drive's power stage to be switched off at once.
//! Only counts presses; what to do about them is the caller's business.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, OnceLock};

#[derive(Debug, Default)]
pub struct Interrupt {
    presses: AtomicU32,
}

impl Interrupt {
    /// How many times Ctrl-C was pressed.
    pub fn presses(&self) -> u32 {
        self.presses.load(Ordering::SeqCst)
    }

    pub fn press(&self) {
        self.presses.fetch_add(1, Ordering::SeqCst);
    }
}

static GLOBAL: OnceLock<Arc<Interrupt>> = OnceLock::new();

/// The process-wide counter, with the Ctrl-C handler installed on first use. When the
/// handler cannot be installed (no signal support), the counter still works but never moves;
/// the reason goes to standard error once.
pub fn install() -> Arc<Interrupt> {
    GLOBAL
        .get_or_init(|| {
            let interrupt = Arc::new(Interrupt::default());
            let handler = interrupt.clone();
            if let Err(e) = ctrlc::set_handler(move || {
                handler.press();
                if handler.presses() == 1 {
                    eprintln!("\ninterrupted: stopping safely (press Ctrl-C again to switch the power stage off at once)");
                }
            }) {
                eprintln!("warning: Ctrl-C cannot be caught here ({e}); the safe stop on Ctrl-C is not available");
            }
            interrupt
        })
        .clone()
}
