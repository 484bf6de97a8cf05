//! The run model and the operations that recipes and scripts share: conditions and checks,
//! what a run did (the report), and where each operation was written. Knows names, units and
//! states; never bytes, never a family, never YAML.

mod condition;
mod object_ref;
mod run_report;
mod step_origin;

pub use condition::{number, Check, Condition, Predicate, Statistic, Stats, Tolerance};
pub use object_ref::ObjectRef;
pub use run_report::{CheckResult, RunReport, Series, StepRecord, Verdict, ERROR_EXIT, PANIC_EXIT};
pub use step_origin::StepOrigin;
