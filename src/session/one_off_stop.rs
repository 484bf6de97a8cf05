//! The safe stop on its own, for a drive a recipe left running (`drivescript stop`): the
//! same verified sequence every run ends with — brake to standstill, disable operation,
//! shutdown, read the state and speed back, escalate when the drive does not obey — on a
//! session without steps. It must not print: the caller reports through its observer.

use super::{RunInfo, RunObserver, RunReport, SafeStopSettings, Session, UnitIdentity};
use crate::drive::{Drive, DriveError};
use crate::stop_request::StopRequests;

/// Why the stop was not even tried.
#[derive(Debug, thiserror::Error)]
pub enum OneOffStopError {
    /// The drive did not answer its first request: nothing was sent to stop it.
    #[error("the drive does not answer: {0}")]
    Silent(DriveError),
    /// The dictionary has no device-control profile: there is no stop command to send.
    #[error(
        "the {dictionary} dictionary has no device-control profile: drivescript has no stop \
         command to send to this drive, and nothing was sent. Stop it where it is commanded \
         (its terminals, its PLC or its own software) and check it by hand"
    )]
    NoDeviceControl { dictionary: String },
}

/// Stops `drive` with the verified safe stop and returns what came of it: the report's
/// notes, the state and speed it was left in and the exit code, as a run's. A drive that
/// does not answer its first request is said at once instead of every stop step waiting
/// out its retries; a drive whose dictionary has no device-control profile is refused
/// before anything is sent, since nothing could stop it.
pub fn stop_drive(
    drive: &mut Drive,
    observer: &mut dyn RunObserver,
    stop: &StopRequests,
    settings: SafeStopSettings,
) -> Result<RunReport, OneOffStopError> {
    if drive.profile().is_err() {
        return Err(OneOffStopError::NoDeviceControl {
            dictionary: drive.dictionary().name().to_string(),
        });
    }
    if let Err(e) = drive.state() {
        if matches!(&e, DriveError::Access(a) if a.is_no_reply()) {
            return Err(OneOffStopError::Silent(e));
        }
    }
    let run = RunInfo {
        kind: "stop",
        name: "safe stop".into(),
        path: drive.port(),
        params: Vec::new(),
        unit: UnitIdentity::default(),
        text_sha256: None,
    };
    let mut session = Session::new(drive, observer, stop, run).with_settings(settings);
    session.begin();
    Ok(session.end(None, false, None, None))
}
