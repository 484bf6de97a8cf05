//! Parameter sets: backup (read every parameter into a YAML file), comparison (a backup
//! against the live drive or another backup) and restore (plan, then write with read-back).
//! Works on the family-neutral [`Drive`](crate::drive::Drive) only; a restore never
//! writes while the drive is powered ([`clear_for_restore`]). The command line decides
//! what to print and whether to apply.

mod backup;
mod comparison;
mod parameter_file;
mod restore;
mod utc;

pub use backup::{parameters, raw_text, take, Origin, IDENTITY_OBJECTS};
pub use comparison::{compare, same, Difference};
pub use parameter_file::{ParameterFile, ParameterFileError, Reading, SavedObject, FORMAT_KEY};
pub use restore::{
    apply, clear_for_restore, plan, skipped, Outcome, PlannedWrite, Refusal, RefusalReason, RestoreRefused,
};
pub use utc::utc_timestamp;
