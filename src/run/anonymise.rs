//! A capture to share: a copy of a `--trace` file or a candump log with the strings the
//! drive gave (ident, serial numbers) masked and its check bytes recomputed, so the copy
//! still replays; a CAN trace's notes file is copied beside it, masked alike. Reads and
//! writes files only; must not print or open a drive.

use super::{recorded_drive, COMMUNICATION, INVALID};
use crate::family::{Registry, DEFAULT_DICTIONARY};
use crate::report::trace_notes_path;
use crate::sim::replay::{Anonymised, Anonymiser};
use std::io::{BufReader, BufWriter};
use std::path::Path;

/// Why a capture was not copied.
#[derive(Debug, thiserror::Error)]
pub enum AnonymiseError {
    /// The command line, the capture or its drive is wrong; nothing was written.
    #[error("{0}")]
    Invalid(String),
    /// The copy could not be written.
    #[error("{0}")]
    Write(String),
}

impl AnonymiseError {
    pub fn exit_code(&self) -> i32 {
        match self {
            AnonymiseError::Invalid(_) => INVALID,
            AnonymiseError::Write(_) => COMMUNICATION,
        }
    }
}

/// Copies `capture` to `output` masked, with the telegrams of `drive` (default: the one
/// the trace's header names, else the default dictionary's).
pub fn anonymise_capture(
    registry: &Registry,
    capture: &Path,
    output: &Path,
    drive: Option<&str>,
) -> Result<Anonymised, AnonymiseError> {
    if same_file(capture, output) {
        return Err(AnonymiseError::Invalid(format!(
            "-o {} is the capture itself; give another file",
            output.display()
        )));
    }
    let drive = drive
        .map(str::to_string)
        .or_else(|| recorded_drive(capture))
        .unwrap_or_else(|| DEFAULT_DICTIONARY.to_string());
    let invalid = |e: &dyn std::fmt::Display| AnonymiseError::Invalid(e.to_string());
    let (family, _) = registry.dictionary(&drive).map_err(|e| invalid(&e))?;
    let dictionary = registry.load_dictionary(&drive).map_err(|e| invalid(&e))?;
    let explainer = family.explainer(std::sync::Arc::new(dictionary));
    let resealing = family.clone();
    let classifying = family.clone();
    let mut anonymiser = Anonymiser::new(
        explainer,
        Box::new(move |bytes| resealing.reseal(bytes)),
        Box::new(move |bytes| classifying.frame_direction(&crate::bus::CanFrame::from_bytes(bytes)?)),
    );
    let done = copy(&mut anonymiser, capture, output)?;
    let notes = trace_notes_path(capture);
    if notes.is_file() {
        copy_notes(&anonymiser, &notes, &trace_notes_path(output))?;
    }
    Ok(done)
}

fn copy(anonymiser: &mut Anonymiser, from: &Path, to: &Path) -> Result<Anonymised, AnonymiseError> {
    let input = std::fs::File::open(from)
        .map_err(|e| AnonymiseError::Invalid(format!("cannot read {}: {e}", from.display())))?;
    let output = crate::output_file_error::create_output_file(to, false)
        .map_err(|e| AnonymiseError::Write(e.to_string()))?;
    let mut out = BufWriter::new(output);
    anonymiser
        .copy(BufReader::new(input), from, &mut out)
        .map_err(|e| AnonymiseError::Invalid(e.to_string()))
}

fn copy_notes(anonymiser: &Anonymiser, from: &Path, to: &Path) -> Result<(), AnonymiseError> {
    let text = std::fs::read_to_string(from)
        .map_err(|e| AnonymiseError::Invalid(format!("cannot read {}: {e}", from.display())))?;
    let masked: Vec<String> = text.lines().map(|l| anonymiser.mask_text(l)).collect();
    std::fs::write(to, masked.join("\n") + "\n")
        .map_err(|e| AnonymiseError::Write(format!("cannot write {}: {e}", to.display())))
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}
