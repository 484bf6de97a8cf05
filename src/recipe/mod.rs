//! YAML recipes: the model with source places, validation against the dictionary (every
//! problem at once, with did-you-mean), and the interpreter that hands their steps to the
//! session's operations. Knows nothing about bytes, ports or families.

mod drive_decl;
mod expansion;
mod leftover_setpoint;
mod loader;
mod planned_checks;
mod prompt_schema;
mod recipe;
mod reference;
mod runner;
mod schema;
mod schema_dynamics;
mod schema_units;
mod step;
mod text_digest;
mod written_values;

pub use drive_decl::DriveDecl;
pub use expansion::{MAX_EXPANDED_STEPS, MAX_INCLUDE_LOADS, MAX_RUN_TIME};
pub use leftover_setpoint::{leftover_setpoints, LeftoverSetpoint};
pub use loader::{
    declared_drives, declared_params, declared_pole_pairs, load_recipe, load_recipe_for, load_recipe_text,
    DriveDictionaries, MAX_DURATION, MAX_SAMPLES,
};
pub use planned_checks::{
    all_watches, last_pass_checks, operator_prompts, planned_checks, sampled_objects,
    shortest_sample_interval,
};
pub use recipe::{OnFailure, Param, Recipe, SafeStopChoice};
/// A recipe that did not pass its check.
pub type RecipeInvalid = crate::diag::FileInvalid;
pub use reference::recipe_reference;
pub use runner::Runner;
pub use schema::recipe_schema;
pub use step::{longest_time_of, Step, StepKind};
pub use written_values::{written_values, WrittenValue};
