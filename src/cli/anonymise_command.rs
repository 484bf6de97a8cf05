//! `drivescript anonymise CAPTURE -o OUT`: a copy of a capture to share, with the strings
//! the drive gave (ident, serial numbers) masked and the copy still replayable. Parses and
//! prints; the copying is `run::anonymise_capture`'s.

use crate::family::Registry;
use crate::run::{anonymise_capture, PASSED};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
/// Copy a capture with the drive's strings masked; it still replays
///
/// Copy a capture (a `--trace` file or a candump log) with every string the drive gave in
/// a reply masked (ident, serial number, product name: letters as X, digits as 0, same
/// length), its check bytes recomputed, so the copy still replays with `--replay`.
pub struct AnonymiseArgs {
    /// The capture to copy.
    #[arg(value_name = "CAPTURE")]
    capture: PathBuf,
    /// Where the masked copy goes (never over the capture itself).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// The drive whose telegrams the capture holds [default: the one the trace's header
    /// names, else sd2].
    #[arg(long, value_name = "DICTIONARY")]
    drive: Option<String>,
}

pub fn anonymise(args: &AnonymiseArgs, registry: &Registry) -> i32 {
    match anonymise_capture(registry, &args.capture, &args.output, args.drive.as_deref()) {
        Ok(done) => {
            println!(
                "{}: {} telegram(s), {} reply(ies) masked",
                args.output.display(),
                done.telegrams,
                done.masked
            );
            PASSED
        }
        Err(e) => {
            eprintln!("error: {e}");
            e.exit_code()
        }
    }
}
