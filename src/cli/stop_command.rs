//! `drivescript stop`: the verified safe stop of a drive a recipe left running (brake to
//! standstill, disable operation, shutdown, read back, escalate), with the connection
//! options of the other one-off commands. Only parses and prints: the stop itself is the
//! library's (`session::stop_drive`).

use super::stop_signals;
use crate::family::Registry;
use crate::recipe::SafeStopChoice;
use crate::report::{step_line, summary_lines, OpenAttempts};
use crate::run::{
    open_drive, silent_drive, ConnectionArgs, DictionaryArgs, SafeStopArgs, COMMUNICATION, INVALID,
};
use crate::session::{stop_drive, OneOffStopError, RunObserver, StepRecord, Verdict, ERROR_EXIT};
use clap::Args;
use std::io::Write;

#[derive(Debug, Args)]
/// Stop a drive safely: brake to standstill, disable, verify
///
/// Stop a drive safely, e.g. one a recipe left running with `leave_enabled: true`: the
/// speed setpoint to 0 and a wait for standstill (--stop-timeout, --standstill), then
/// disable operation and shutdown, then the state and speed read back (escalating to quick
/// stop and disable voltage if the drive does not obey). Exit codes as `run`: 0 stopped
/// and confirmed at standstill, 3 not confirmed, not obeyed or not at standstill (CHECK THE
/// DRIVE BY HAND) or a dictionary without a device-control profile (nothing to send),
/// 128 + N after a stop signal (a second one switches the power stage off at once).
pub struct StopArgs {
    #[command(flatten)]
    safe_stop: SafeStopArgs,
    #[command(flatten)]
    dictionary: DictionaryArgs,
    #[command(flatten)]
    connection: ConnectionArgs,
}

/// Prints each step of the stop as it ends and what else the stop says. Written with
/// `writeln!`, never `println!`: after SIGHUP the terminal is gone, and a failed write must
/// not panic in the middle of the stop.
struct StopLines;

impl RunObserver for StopLines {
    fn step_finished(&mut self, record: &StepRecord) {
        let _ = writeln!(std::io::stdout(), "{}", step_line(record, &OpenAttempts::NONE));
    }
    fn message(&mut self, text: &str) {
        let _ = writeln!(std::io::stdout(), "{text}");
    }
}

pub fn stop(args: &StopArgs, registry: &Registry) -> i32 {
    let stop = stop_signals::install_for_a_drive();
    let dictionary = match args.dictionary.load_for(registry, None) {
        Ok(d) => d,
        Err(text) => {
            eprint!("{text}");
            return INVALID;
        }
    };
    let mut open = match open_drive(
        registry,
        &args.connection,
        dictionary,
        false,
        None,
        Some(stop.clone()),
    ) {
        Ok(o) => o,
        Err(text) => {
            eprintln!("{text}");
            return COMMUNICATION;
        }
    };
    // The simulated drive is a fresh one for each command: nothing of an earlier run.
    let fresh = match open.simulator {
        Some(_) => "; its state is not kept between commands",
        None => "",
    };
    let _ = writeln!(std::io::stdout(), "stop    {}{fresh}", open.description);
    let settings = args.safe_stop.settings(&SafeStopChoice::default());
    match stop_drive(&mut open.drive, &mut StopLines, &stop, settings) {
        Ok(mut report) => {
            // The run's one verdict rule: stopped only when the drive is confirmed at
            // standstill in a state the stop aims for.
            crate::run::settle(&mut report);
            let mut lines = summary_lines(&report, false);
            // The run's verdict line counts steps and checks, which a stop has none of.
            lines.pop();
            for line in lines {
                let _ = writeln!(std::io::stdout(), "{line}");
            }
            let code = report.exit_code();
            let word = match &report.verdict {
                Verdict::Passed => "STOPPED".to_string(),
                v => match v.reason() {
                    Some(why) => format!("{}: {why}", v.word()),
                    None => v.word().to_string(),
                },
            };
            let _ = writeln!(std::io::stdout(), "{word} — exit code {code}");
            code
        }
        Err(OneOffStopError::Silent(e)) => {
            let text = silent_drive(
                registry,
                open.drive.dictionary(),
                &args.connection,
                "stop",
                &e.to_string(),
            );
            eprintln!(
                "{}",
                text.replace(
                    "nothing was written to it and the stop did not start",
                    "nothing was sent to stop it",
                )
            );
            COMMUNICATION
        }
        Err(e @ OneOffStopError::NoDeviceControl { .. }) => {
            eprintln!("stop: {e}");
            ERROR_EXIT
        }
    }
}
