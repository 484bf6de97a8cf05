//! Why a capture cannot be replayed: a line that is not a telegram (with its file and line,
//! so the user can look at it), or a file that cannot be read. Holds text only.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum CaptureError {
    #[error("{}:{line}: {what}", file.display())]
    Line { file: PathBuf, line: u64, what: String },
    #[error("cannot read the capture {}: {detail}", file.display())]
    Unreadable { file: PathBuf, detail: String },
}
