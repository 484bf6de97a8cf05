//! A capture to share: a copy of a `--trace` file or a candump log with the strings the
//! drive gave (ident, serial numbers) masked and its check bytes recomputed, so the copy
//! still replays; a CAN trace's notes file is copied beside it, masked alike. Reads and
//! writes files only; must not print or open a drive.

use super::{recorded_drive, COMMUNICATION, INVALID};
use crate::family::{Registry, DEFAULT_DICTIONARY};
use crate::output_file_error::{create_output_file, OutputFileError};
use crate::report::{tmp_path, trace_notes_path, write_atomically};
use crate::sim::replay::{Anonymised, Anonymiser, CopyError};
use std::io::{BufReader, BufWriter};
use std::path::Path;

/// Why a capture was not copied.
#[derive(Debug, thiserror::Error)]
pub enum AnonymiseError {
    /// The command line, the capture or its drive is wrong; nothing was written.
    #[error("{0}")]
    Invalid(String),
    /// The copy (or its notes file) could not be created or written; the text names it.
    #[error(transparent)]
    Write(#[from] OutputFileError),
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

/// Streams the masked copy into `PATH.tmp` and renames it over `to` only when it is whole:
/// a capture found bad halfway, a full disk or a kill never leaves a half copy that would
/// be shared as the whole capture. A device or pipe given as `-o` is written directly.
fn copy(anonymiser: &mut Anonymiser, from: &Path, to: &Path) -> Result<Anonymised, AnonymiseError> {
    let input = std::fs::File::open(from)
        .map_err(|e| AnonymiseError::Invalid(format!("cannot read {}: {e}", from.display())))?;
    let special = std::fs::metadata(to).is_ok_and(|m| !m.is_file());
    let writing = if special { to.to_path_buf() } else { tmp_path(to) };
    let mut out = BufWriter::new(create_output_file(&writing, false)?);
    let copied = anonymiser
        .copy(BufReader::new(input), from, &mut out)
        .map_err(|e| match e {
            CopyError::Capture(e) => AnonymiseError::Invalid(e.to_string()),
            CopyError::Write(e) => OutputFileError::file(to, e).into(),
        })
        .and_then(|done| {
            let file = out
                .into_inner()
                .map_err(|e| OutputFileError::file(to, e.into_error()))?;
            if !special {
                file.sync_all().map_err(|e| OutputFileError::file(to, e))?;
                crate::report::replace(&writing, to).map_err(|e| OutputFileError::file(to, e))?;
            }
            Ok(done)
        });
    if copied.is_err() && !special {
        let _ = std::fs::remove_file(&writing);
    }
    copied
}

fn copy_notes(anonymiser: &Anonymiser, from: &Path, to: &Path) -> Result<(), AnonymiseError> {
    let text = std::fs::read_to_string(from)
        .map_err(|e| AnonymiseError::Invalid(format!("cannot read {}: {e}", from.display())))?;
    let masked: Vec<String> = text.lines().map(|l| anonymiser.mask_text(l)).collect();
    Ok(write_atomically(to, &(masked.join("\n") + "\n"))?)
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn capture() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cases/replay/sd2_commissioning/capture.trace")
    }

    /// A copy that cannot be written is a write failure naming the copy (exit 3), not a
    /// capture that cannot be read (exit 2): here a full disk, and a directory that
    /// cannot be made.
    #[test]
    fn a_copy_that_cannot_be_written_says_where_it_was_going() {
        let registry = Registry::builtin();
        let full = Path::new("/dev/full");
        let e = anonymise_capture(&registry, &capture(), full, None).unwrap_err();
        assert!(
            matches!(&e, AnonymiseError::Write(OutputFileError::File { path, .. }) if path == full),
            "{e:?}"
        );
        assert_eq!(e.exit_code(), COMMUNICATION);
        assert!(e.to_string().starts_with("cannot write /dev/full: "), "{e}");
        let nowhere = Path::new("/proc/drivescript/shared.trace");
        let e = anonymise_capture(&registry, &capture(), nowhere, None).unwrap_err();
        assert!(
            matches!(&e, AnonymiseError::Write(OutputFileError::Directory { .. })),
            "{e:?}"
        );
        assert!(
            e.to_string()
                .starts_with("cannot create the directory /proc/drivescript: "),
            "{e}"
        );
    }

    /// A capture found bad halfway leaves no half copy: nothing where there was nothing,
    /// and an earlier copy as it was.
    #[test]
    fn a_capture_bad_halfway_leaves_no_half_copy() {
        let dir = crate::scratch_dir::scratch_dir("anonymise");
        let good = std::fs::read_to_string(capture()).unwrap();
        let lines: Vec<&str> = good.lines().collect();
        let half = lines.len() / 2;
        let bad = dir.join("bad.trace");
        let text = format!(
            "{}\n12.5 RX zz zz  # not a telegram\n{}\n",
            lines[..half].join("\n"),
            lines[half..].join("\n")
        );
        std::fs::write(&bad, text).unwrap();
        let registry = Registry::builtin();
        let out = dir.join("shared.trace");
        let e = anonymise_capture(&registry, &bad, &out, None).unwrap_err();
        assert!(matches!(e, AnonymiseError::Invalid(_)), "{e:?}");
        assert!(!out.exists(), "a half copy was left");
        assert!(!tmp_path(&out).exists(), "its temporary was left");
        std::fs::write(&out, "an earlier copy\n").unwrap();
        anonymise_capture(&registry, &bad, &out, None).unwrap_err();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "an earlier copy\n");
        anonymise_capture(&registry, &capture(), &out, None).unwrap();
        assert!(std::fs::read_to_string(&out).unwrap().lines().count() >= lines.len());
        assert!(!tmp_path(&out).exists());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
