//! `drivescript anonymise CAPTURE -o OUT`: a copy of a capture to share, with the strings
//! the drive gave (ident, serial numbers) masked and the copy still replayable. A CAN
//! trace's notes file (`FILE.meta`) is copied next to the copy, masked alike.

use crate::family::{Registry, DEFAULT_DICTIONARY};
use crate::report::trace_notes_path;
use crate::run::{COMMUNICATION, INVALID, PASSED};
use crate::sim::replay::Anonymiser;
use clap::Args;
use std::io::{BufReader, BufWriter};
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
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
    if same_file(&args.capture, &args.output) {
        eprintln!(
            "error: -o {} is the capture itself; give another file",
            args.output.display()
        );
        return INVALID;
    }
    let drive = args
        .drive
        .clone()
        .or_else(|| crate::run::recorded_drive(&args.capture))
        .unwrap_or_else(|| DEFAULT_DICTIONARY.to_string());
    let family = match registry.dictionary(&drive) {
        Ok((family, _)) => family,
        Err(e) => {
            eprintln!("error: {e}");
            return INVALID;
        }
    };
    let dictionary = match registry.load_dictionary(&drive) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return INVALID;
        }
    };
    let explainer = family.explainer(std::sync::Arc::new(dictionary));
    let resealing = family.clone();
    let classifying = family.clone();
    let mut anonymiser = Anonymiser::new(
        explainer,
        Box::new(move |bytes| resealing.reseal(bytes)),
        Box::new(move |bytes| classifying.frame_direction(&crate::bus::CanFrame::from_bytes(bytes)?)),
    );
    let copied = copy(&mut anonymiser, &args.capture, &args.output).and_then(|done| {
        let notes = trace_notes_path(&args.capture);
        if notes.is_file() {
            copy_notes(&anonymiser, &notes, &trace_notes_path(&args.output))?;
        }
        Ok(done)
    });
    match copied {
        Ok(done) => {
            println!(
                "{}: {} telegram(s), {} reply(ies) masked",
                args.output.display(),
                done.telegrams,
                done.masked
            );
            PASSED
        }
        Err((code, text)) => {
            eprintln!("error: {text}");
            code
        }
    }
}

type Failed = (i32, String);

fn copy(
    anonymiser: &mut Anonymiser,
    from: &Path,
    to: &Path,
) -> Result<crate::sim::replay::Anonymised, Failed> {
    let input =
        std::fs::File::open(from).map_err(|e| (INVALID, format!("cannot read {}: {e}", from.display())))?;
    let output = crate::report::create_file(to).map_err(|e| (COMMUNICATION, e))?;
    let mut out = BufWriter::new(output);
    anonymiser
        .copy(BufReader::new(input), from, &mut out)
        .map_err(|e| (INVALID, e.to_string()))
}

fn copy_notes(anonymiser: &Anonymiser, from: &Path, to: &Path) -> Result<(), Failed> {
    let text = std::fs::read_to_string(from)
        .map_err(|e| (INVALID, format!("cannot read {}: {e}", from.display())))?;
    let masked: Vec<String> = text.lines().map(|l| anonymiser.mask_text(l)).collect();
    std::fs::write(to, masked.join("\n") + "\n")
        .map_err(|e| (COMMUNICATION, format!("cannot write {}: {e}", to.display())))
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}
