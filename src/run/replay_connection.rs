//! `--replay CAPTURE`: a capture standing in for the drive, on an in-process line in
//! virtual time that follows the capture's clock. Checks that the capture is of the
//! family being driven before anything runs. Opens no port: a replay cannot make
//! anything send to real hardware.

use super::RunError;
use crate::bus::{Bus, BusKind, CanFrame, MemoryFrameBus, MemoryTransport, SharedFrameBus, SharedTransport};
use crate::clock::SharedClock;
use crate::family::{Family, Registry};
use crate::report::{trace_notes_path, TraceHeader};
use crate::sim::replay::{CaptureError, CapturedDrive, Classifier};
use std::io::BufRead;
use std::path::Path;
use std::sync::{Arc, Mutex};

/// The captured drive of `capture`, for `family`'s requests. Refuses a capture whose
/// header names a drive of another family, and one that cannot be read.
pub fn captured_drive(
    registry: &Registry,
    family: &dyn Family,
    capture: &Path,
) -> Result<CapturedDrive, RunError> {
    if let Some(header) = capture_header(capture) {
        let recorded = registry.dictionary(&header.drive).map(|(f, _)| f.id());
        if let Ok(id) = recorded.as_ref().map(|id| id.to_string()) {
            if id != family.id() {
                return Err(RunError::Invalid(format!(
                    "error: {} is a capture of --drive {} (the {id} family), not of the {} family being driven; replay it with a recipe or --drive for {}",
                    capture.display(),
                    header.drive,
                    family.id(),
                    header.drive
                )));
            }
        }
    }
    let name = family.dictionaries().first().map_or("", |d| d.name);
    let dictionary = registry
        .load_dictionary(name)
        .map_err(|e| RunError::Invalid(format!("error: {e}")))?;
    let explainer = family.explainer(Arc::new(dictionary));
    CapturedDrive::open(capture, classifier(registry, family.id()), explainer)
        .map_err(|e| invalid_capture(&e))
}

/// The bus to the captured drive, on `clock`.
pub fn replay_bus(drive: CapturedDrive, family: &dyn Family, capture: &Path, clock: SharedClock) -> Bus {
    let name = format!("replay of {}", capture.display());
    let drive = Arc::new(Mutex::new(drive));
    match family.bus_kind() {
        BusKind::Bytes => Bus::Bytes(SharedTransport::new(Box::new(MemoryTransport::new(
            name, drive, clock,
        )))),
        BusKind::Frames => Bus::Frames(SharedFrameBus::new(Box::new(MemoryFrameBus::new(
            name, drive, clock,
        )))),
    }
}

fn invalid_capture(e: &CaptureError) -> RunError {
    RunError::Invalid(format!("error: {e}"))
}

/// How the family tells its requests from replies in a capture that does not say.
fn classifier(registry: &Registry, family: &str) -> Classifier {
    let family = registry.family(family).ok();
    Box::new(move |bytes| {
        let frame = CanFrame::from_bytes(bytes)?;
        family.as_ref()?.frame_direction(&frame)
    })
}

/// The drive (built-in dictionary) a trace's header names, when it has one.
pub fn recorded_drive(capture: &Path) -> Option<String> {
    capture_header(capture).map(|h| h.drive)
}

/// The header of a capture: at its top, or for a CAN trace in its notes file.
fn capture_header(capture: &Path) -> Option<TraceHeader> {
    let top = |path: &Path| -> Option<TraceHeader> {
        let file = std::fs::File::open(path).ok()?;
        let lines: Vec<String> = std::io::BufReader::new(file)
            .lines()
            .take(64)
            .map_while(Result::ok)
            .collect();
        TraceHeader::read(lines.iter().map(String::as_str))
    };
    top(capture).or_else(|| top(&trace_notes_path(capture)))
}
