//! What can go wrong with the results store, typed so that a caller can tell a store that
//! cannot be reached (spool and go on) from a file that is no store (say so and stop).

use thiserror::Error;

#[derive(Debug, Error)]
pub enum StoreError {
    /// The store could not be opened or reached (a server down, a locked or unwritable
    /// file): a run spools its record and goes on.
    #[error("results store {store} cannot be reached: {why}")]
    Unreachable { store: String, why: String },
    /// The file or database holds something else, or is damaged.
    #[error("{store} is not a drivescript results store: {why}; give another with --results or DRIVESCRIPT_RESULTS")]
    Foreign { store: String, why: String },
    /// Written by a newer drivescript whose schema this one does not know.
    #[error("results store {store} has schema version {found}, newer than this drivescript knows ({known}); update drivescript")]
    Newer { store: String, found: i64, known: i64 },
    /// A statement failed on a store that was open.
    #[error("results store {store}: {why}")]
    Query { store: String, why: String },
    /// What was asked cannot be done as asked (a check's name that stands for several
    /// measurements, a second void of a run); the message says what to do.
    #[error("{0}")]
    Refused(String),
    /// No run matches what the user asked for.
    #[error("{0}")]
    NotFound(String),
    /// The spool file could not be read or written.
    #[error("results spool {path}: {why}")]
    Spool { path: String, why: String },
}
