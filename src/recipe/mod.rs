//! YAML recipes: the model with source places, validation against the dictionary (every
//! problem at once, with did-you-mean), and the interpreter that runs them against the
//! drive API. Knows nothing about bytes or ports.

mod expansion;
mod loader;
mod recipe;
mod recipe_invalid;
mod run_observer;
mod runner;
mod schema;
mod step;

pub use crate::session::{number, Check, Condition, Predicate, Statistic, Stats, Tolerance};
pub use crate::session::{CheckResult, RunReport, Series, StepRecord, Verdict};
pub use expansion::{MAX_EXPANDED_STEPS, MAX_INCLUDE_LOADS, MAX_RUN_TIME};
pub use loader::{load_recipe, load_recipe_text, show_duration, MAX_DURATION, MAX_SAMPLES};
pub use recipe::{Param, Recipe, SafeStopChoice};
pub use recipe_invalid::RecipeInvalid;
pub use run_observer::{Observers, RunObserver};
pub use runner::{default_finally_steps, Runner, SafeStopSettings};
pub use schema::recipe_schema;
pub use step::{ObjectRef, SetValue, Step, StepKind, StepOrigin};
