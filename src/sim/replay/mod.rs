//! Replay: a capture (a drivescript `--trace`, or a candump log of a CAN bus) standing in
//! for the drive it was recorded from, in process (`run --replay`) or served (`simulate
//! --replay`), and its anonymised copy to share. Reads captures streaming, with located
//! errors; never sends anything to a real port and never holds a whole capture.

mod anonymiser;
mod capture_error;
mod capture_reader;
mod captured_drive;
mod exchange_reader;

pub use anonymiser::{Anonymised, Anonymiser, CopyError, Resealer};
pub use capture_error::CaptureError;
pub use capture_reader::{CaptureReader, CaptureRecord};
pub use captured_drive::{CapturedDrive, RefusalSink, WINDOW};
pub use exchange_reader::{Classifier, Exchange, ExchangeReader};
