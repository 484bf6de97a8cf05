//! Why a capture cannot be replayed: a line that is not a telegram (with its file and line,
//! so the user can look at it, and what is wrong with it), a capture with nothing to
//! replay, or a file that cannot be read.

use crate::bus::CanFrameTextError;
use crate::hex::HexError;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum CaptureError {
    #[error("{}:{line}: {what}", file.display())]
    Line {
        file: PathBuf,
        line: u64,
        what: LineProblem,
    },
    #[error("{}:0: the capture holds no request to replay (no TX line, no request frame)", file.display())]
    NoRequest { file: PathBuf },
    #[error("cannot read the capture {}: {detail}", file.display())]
    Unreadable { file: PathBuf, detail: String },
}

/// What is wrong with one line of a capture, and what the line should look like.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LineProblem {
    #[error("the line is longer than {max} bytes; no telegram is")]
    TooLong { max: u64 },
    /// `shown`: the line's first 60 characters.
    #[error("`{shown}` is neither a trace line (`SECONDS TX|RX HEX`) nor a candump log line (`(SECONDS) INTERFACE ID#DATA`)")]
    NotATelegram { shown: String },
    #[error("`{text}` is not a time in seconds (e.g. 0.012345)")]
    NotATime { text: String },
    #[error("the telegram `{hex}`: {problem}")]
    Telegram { hex: String, problem: HexError },
    #[error("no `)` after the time: {CANDUMP_SHAPE}")]
    CandumpTime,
    #[error("{CANDUMP_SHAPE}")]
    CandumpShape,
    #[error("`{after}` after the frame: only T or R (candump -x) may follow it")]
    AfterFrame { after: String },
    #[error(transparent)]
    Frame(#[from] CanFrameTextError),
}

const CANDUMP_SHAPE: &str =
    "a candump log line is `(SECONDS) INTERFACE ID#DATA`, e.g. `(1700000000.123456) can0 601#4000100000000000`";
