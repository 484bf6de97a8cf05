//! The results store: every run recorded as it goes, in an embedded SQLite file by
//! default or on a PostgreSQL server for a fleet of benches (one schema, versioned
//! migrations applied on opening), with a local spool for records a store could not take.
//! The recorder ([`ResultsRecorder`]) is a run observer the command line adds; the store
//! ([`Store`]) answers `drivescript results`, and [`certificate_html`] and [`trend_html`]
//! draw its pages. Must not be on the safe stop's path: records go through a bounded queue
//! to a thread of their own. Parameters only, never SQL built from values.

mod backend;
mod capability;
pub mod capability_html;
pub mod certificate_html;
mod check_history;
mod check_identity;
mod claim_owner;
pub mod export;
pub mod filter_time;
mod locator;
mod page_links;
mod postgres_backend;
mod record;
mod results_recorder;
mod results_writer;
pub mod run_list_html;
mod run_void;
mod run_yield;
mod schema;
mod spool;
mod sqlite_backend;
mod store;
mod store_error;
mod store_history;
mod stored_run;
pub mod trend_html;
pub mod yield_html;

pub use backend::{Backend, Value};
pub use capability::{Capability, Histogram};
pub use check_identity::{readings, AskedCheck, CheckIdentity};
pub use locator::{data_dir, Locator, RESULTS_ENV};
pub use page_links::{url_escape, PageLinks};
pub use record::{CheckRow, EndRow, Record, RunRow, SeriesRow, StepRow};
pub use results_recorder::{utc_text, FileFacts, Notes, RecorderSettings, ResultsRecorder};
pub use run_yield::YieldRow;
pub use schema::{current_version, migration};
pub use spool::{Delivered, Spool};
pub use store::Store;
pub use store_error::StoreError;
pub use store_history::StoreHistory;
pub use stored_run::{RunFilter, StoredRun, TrendPoint, VoidRow};
