//! Why a run (or any command of the application layer) could not go on, as one type: the
//! caller tells an invalid file or setting (nothing was sent, exit code 2) from a drive or
//! port that cannot be reached (exit code 3) by the variant, and prints its text as it is.
//! The typed errors of the layers below (a family's refusal of an address or a link
//! setting, a dictionary with problems) keep their type inside.

use crate::diag::FileInvalid;
use crate::dictionary::DictionaryError;
use crate::family::FamilyError;

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The file, a dictionary, a setting or the command line is wrong; nothing was sent.
    #[error("{0}")]
    Invalid(String),
    /// A port cannot be opened, or a drive cannot be reached or does not answer.
    #[error("{0}")]
    Unreachable(String),
    /// A recipe or a script with problems, each at its place; kept whole so that a
    /// terminal can show them in colour.
    #[error("{}", .0.render(false))]
    File(#[from] FileInvalid),
    /// A dictionary or bench-limits file with problems, rendered with their places.
    #[error("{}", crate::diag::render_diagnostic(.0))]
    Dictionary(#[from] DictionaryError),
    /// The drive's family refused an address, a link setting, the bus or an object in its
    /// notation; nothing was sent.
    #[error("{0}")]
    Family(#[from] FamilyError),
    /// Something went wrong for one of several named drives.
    #[error("drive `{drive}`: {source}")]
    Drive {
        drive: String,
        #[source]
        source: Box<RunError>,
    },
}

impl RunError {
    /// The exit code of DESIGN.md for a run that ends here.
    pub fn exit_code(&self) -> i32 {
        match self {
            RunError::Unreachable(_) => super::COMMUNICATION,
            RunError::Drive { source, .. } => source.exit_code(),
            RunError::Invalid(_) | RunError::File(_) | RunError::Dictionary(_) | RunError::Family(_) => {
                super::INVALID
            }
        }
    }

    /// The text to print: a recipe's or a script's problems in colour for a terminal
    /// (`colour`), anything else as it is.
    pub fn render(&self, colour: bool) -> String {
        match self {
            RunError::File(e) => e.render(colour),
            e => e.to_string(),
        }
    }

    /// This error, said of the named drive `drive`.
    pub fn of_drive(self, drive: &str) -> RunError {
        RunError::Drive {
            drive: drive.to_string(),
            source: Box::new(self),
        }
    }
}

/// A command-line value that cannot be used, with what to write instead (clap prints it
/// after the option's name).
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct BadValue(pub String);
