//! The run model and the operations that recipes and scripts share: a [`Session`] runs
//! drive operations (set, read, go_to, wait_until, dwell, sample, expect, ramp, and the
//! operator's prompts) with
//! stop-request-aware waits and fault watching, reports them through a [`RunObserver`],
//! and ends every run with the verified safe stop; conditions and checks; what a run did
//! (the report). Knows names, units and states; never bytes, never a family, never YAML.

mod ask;
mod brake;
mod bucket_series;
mod check_key;
mod coast_down;
mod coasting;
mod condition;
mod downward;
mod drive_identity;
mod end_state;
mod expect;
mod expect_parameters;
mod history_lookup;
mod last_pass;
mod limits;
mod number_text;
mod object_ref;
mod object_scale;
mod one_off_stop;
mod operations;
mod operator;
mod prompt;
mod ramp;
mod release;
mod reported_faults;
mod restore_link;
mod run_info;
mod run_observer;
mod run_report;
mod safe_stop;
mod safe_stop_settings;
mod sample;
mod sample_table;
mod sample_window;
mod sampling;
mod session;
mod session_drive;
mod set_value;
mod slope_window;
mod step_origin;
mod step_path;
mod step_response;
mod stop;
mod unit_identity;
mod wait_stable;
mod wait_until;
mod watch;

pub use bucket_series::{BucketSeries, SERIES_BUCKETS};
pub use check_key::{
    compared_key, identity_stage, key_of_name, measured_key, without_iterations, COMPARED, WAIT,
};
pub use coast_down::CoastDown;
pub use condition::{
    exact_with_unit, number, with_unit, Check, Condition, Measure, Predicate, Statistic, Stats, Tolerance,
};
pub use end_state::EndState;
pub use expect::AttemptMark;
pub use history_lookup::LOOKUP_LIMIT;
pub use last_pass::{signed, History, HistoryError, LastPass, PastCheck, PastRun};
pub use limits::Limits;
pub use number_text::{push_number, push_seconds, write_number, UtcMillis};
pub use object_ref::ObjectRef;
pub use object_scale::{at_resolution, decimals_of_scale};
pub use one_off_stop::{stop_drive, OneOffStopError};
pub use operator::{Given, Nobody, Operator, Reply};
pub use prompt::{default_answer_name, Accepted, NotAnAnswer, Pattern, Prompt, PromptKind};
pub use run_info::{RunInfo, StepInfo};
pub use run_observer::{Observers, RunObserver};
pub use run_report::{
    CheckReference, CheckResult, DriveEnd, PlannedCheck, RunReport, Series, StepRecord, Track, Verdict,
    ERROR_EXIT, MAX_RECORDS, PANIC_EXIT,
};
pub use safe_stop_settings::SafeStopSettings;
pub use sample_table::{SampleTable, LONG_HEADER, LONG_HEADER_DRIVES};
pub use sample_window::{Measured, SampleWindow};
pub use sampling::Sampling;
pub use session::{show_duration, Session};
pub use set_value::SetValue;
pub use slope_window::{Slope, SlopeWindow, SLOPE_BUCKETS};
pub use step_origin::StepOrigin;
pub use step_path::StepPath;
pub use step_response::{ResponseMarks, StepResponse, StepSpec, DEFAULT_BAND_PERCENT};
pub use stop::{outcome, Stop};
pub use unit_identity::{UnitIdentity, UNIT_FIELDS};
pub use watch::{Watch, DEFAULT_WATCH_EVERY, MIN_WATCH_EVERY};
