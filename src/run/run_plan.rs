//! What a run performs: a recipe or a script, loaded and checked against the dictionary of
//! each of its drives. The two differ only in how they produce the session's operations
//! (the recipe interpreter or the Rhai engine) and in what they know before they run
//! (a recipe its checks and its longest time); everything around them is the pipeline's.
//! Loads and answers; must not open a drive.

use super::{drive_dictionaries, DictionaryArgs, RunError, RunRequest};
use crate::dictionary::Dictionary;
use crate::drive::Drive;
use crate::family::Registry;
use crate::recipe::{
    declared_drives, load_recipe_for, longest_time_of, operator_prompts, planned_checks, sampled_objects,
    shortest_sample_interval, written_values, DriveDecl, Recipe, Runner, SafeStopChoice, WrittenValue,
};
use crate::script::{declared_script_drives, is_script, load_script_for, Script, ScriptRunner};
use crate::session::{
    ObjectRef, Operator, PlannedCheck, Prompt, RunObserver, RunReport, SafeStopSettings, StepOrigin,
    UnitIdentity,
};
use crate::stop_request::StopRequests;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

/// A recipe or a script, ready to run.
pub enum RunPlan {
    Recipe(Recipe),
    Script(Script),
}

/// A plan with the dictionaries it was checked against.
pub struct LoadedPlan {
    pub plan: RunPlan,
    /// The dictionary of a plan with one drive, or the first named drive's.
    pub dictionary: Arc<Dictionary>,
    /// Each named drive's dictionary (empty for a plan with one drive).
    pub drive_dictionaries: Vec<(String, Arc<Dictionary>)>,
}

/// How the session is run: the settings every plan gets from the request.
pub struct SessionSettings {
    pub safe_stop: SafeStopSettings,
    pub output_dir: PathBuf,
    pub csv_wide: bool,
    /// The unit under test as the command line gives it.
    pub unit: UnitIdentity,
    pub operator: Box<dyn Operator>,
    /// Where the unit's past runs are read (the results store), for the checks that
    /// compare with its last pass.
    pub history: Option<Arc<dyn crate::session::History>>,
}

impl RunPlan {
    /// Loads `request.file` (a `.rhai` file is a script) with each drive's dictionary: the
    /// one `--drive` names (or the file's own `drive:`), or one per named drive. On failure
    /// the problem (exit code 2): a recipe's or a script's with every place.
    pub fn load(request: &RunRequest) -> Result<LoadedPlan, RunError> {
        Self::load_file(
            request.registry,
            request.file,
            request.set,
            &request.dictionary.with_pole_pairs_of(request.connection),
        )
    }

    /// [`load`](Self::load) of `path` with the `--set` overrides `set` and the dictionary
    /// options `dictionary`: what `run` and `check` both load a file with.
    pub fn load_file(
        registry: &Registry,
        path: &Path,
        set: &[(String, String)],
        dictionary: &DictionaryArgs,
    ) -> Result<LoadedPlan, RunError> {
        let script = is_script(path);
        // A file with named drives names a dictionary per drive; the first is the file's.
        let declared = if script {
            declared_script_drives(path)
        } else {
            declared_drives(path)
        };
        let (one, drive_dicts) = if declared.is_empty() {
            (dictionary.load_for(registry, Some(path))?, Vec::new())
        } else {
            let all = drive_dictionaries(dictionary, registry, path, &declared)?;
            (all[0].1.clone(), all)
        };
        let plan = if script {
            RunPlan::Script(load_script_for(path, &one, &drive_dicts, set)?)
        } else {
            RunPlan::Recipe(load_recipe_for(
                path,
                &one,
                &drive_dicts,
                &registry.address_keys(),
                set,
            )?)
        };
        Ok(LoadedPlan {
            plan,
            dictionary: one,
            drive_dictionaries: drive_dicts,
        })
    }

    /// What a recipe and a script both hold, taken from whichever this is.
    fn either<'a, T: ?Sized>(
        &'a self,
        recipe: fn(&'a Recipe) -> &'a T,
        script: fn(&'a Script) -> &'a T,
    ) -> &'a T {
        match self {
            RunPlan::Recipe(r) => recipe(r),
            RunPlan::Script(s) => script(s),
        }
    }

    pub fn name(&self) -> &str {
        self.either(|r| &r.name, |s| &s.name)
    }

    /// The file as the reports name it.
    pub fn path(&self) -> &str {
        self.either(|r| &r.path, |s| &s.path)
    }

    /// The file's own link settings (`link:`, `//! link:`), under the command line's.
    pub fn link(&self) -> &[(String, String)] {
        self.either(|r| &r.link, |s| &s.link)
    }

    /// Where [`link`](Self::link) is written, for messages.
    pub fn link_source(&self) -> &'static str {
        match self {
            RunPlan::Recipe(_) => "the recipe's `link:`",
            RunPlan::Script(_) => "the script's `//! link:`",
        }
    }

    /// The named drives; empty for a plan with one drive.
    pub fn drives(&self) -> &[DriveDecl] {
        self.either(|r| &r.drives, |s| &s.drives)
    }

    pub fn safe_stop(&self) -> &SafeStopChoice {
        self.either(|r| &r.safe_stop, |s| &s.safe_stop)
    }

    /// `leave_enabled: true` (`//! leave_enabled: true`): a run that succeeds leaves the
    /// drive as it was left.
    pub fn leave_enabled(&self) -> bool {
        *self.either(|r| &r.leave_enabled, |s| &s.leave_enabled)
    }

    /// The checks known before the run (a recipe's; a script's appear as it runs), for the
    /// JUnit report of a run that ends early or never starts.
    pub fn planned_checks(&self) -> Vec<PlannedCheck> {
        match self {
            RunPlan::Recipe(r) => planned_checks(r),
            RunPlan::Script(_) => Vec::new(),
        }
    }

    /// The operator steps known before the run, with their places: all of a recipe's, the
    /// ones a script writes with a literal question.
    pub fn prompts(&self) -> Vec<(Prompt, StepOrigin)> {
        match self {
            RunPlan::Recipe(r) => operator_prompts(r),
            RunPlan::Script(s) => s.prompts.clone(),
        }
    }

    /// Where the first check that compares with the unit's last passed run writes it (a
    /// recipe's; a script has none); `None` without such checks.
    pub fn compares_with_last_pass(&self) -> Option<StepOrigin> {
        match self {
            RunPlan::Recipe(r) => crate::recipe::last_pass_checks(r).1,
            RunPlan::Script(_) => None,
        }
    }

    /// The columns of `--csv-wide`; `None` for a script, which chooses what it samples as
    /// it runs, so its `--csv` keeps the long layout.
    pub fn wide_columns(&self) -> Option<Vec<ObjectRef>> {
        match self {
            RunPlan::Recipe(r) => Some(sampled_objects(r)),
            RunPlan::Script(_) => None,
        }
    }

    /// The shortest sample interval known before the run (a recipe's; a script chooses as
    /// it runs).
    pub fn shortest_sample_interval(&self) -> Option<Duration> {
        match self {
            RunPlan::Recipe(r) => shortest_sample_interval(r),
            RunPlan::Script(_) => None,
        }
    }

    /// Every number the plan is known to write before it runs, each named as the drive
    /// limits are looked up (`left.speed_setpoint` with named drives).
    pub fn written_values(&self) -> Vec<WrittenValue> {
        match self {
            RunPlan::Recipe(r) => written_values(r),
            RunPlan::Script(s) => s.written.clone(),
        }
    }

    /// The longest the run can take, for the live bar (a recipe knows it).
    pub fn planned_time(&self) -> Option<Duration> {
        match self {
            RunPlan::Recipe(r) => Some(longest_time_of(&r.steps)),
            RunPlan::Script(_) => None,
        }
    }

    /// Whether the console colours PASS and FAIL (a script's lines are its own `print`s
    /// among them, and stay plain).
    pub fn colored(&self) -> bool {
        matches!(self, RunPlan::Recipe(_))
    }

    /// Runs the plan on `drives` (one unnamed drive, or each named one) to the end,
    /// whatever happens, the safe stop included. A script's own problems go to `err`.
    pub fn run(
        &self,
        drives: Vec<(String, &mut Drive)>,
        observer: &mut dyn RunObserver,
        stop: &Arc<StopRequests>,
        settings: SessionSettings,
        err: &mut dyn Write,
    ) -> RunReport {
        let mut report = match self {
            RunPlan::Recipe(recipe) => Runner::with_drives(drives, &mut *observer, stop, recipe)
                .with_operator(settings.unit, settings.operator)
                .with_history(settings.history, recipe)
                .with_output_dir(settings.output_dir)
                .with_csv_wide(settings.csv_wide)
                .with_settings(settings.safe_stop)
                .run(recipe),
            RunPlan::Script(script) => ScriptRunner::with_drives(drives, &mut *observer, stop.clone())
                .with_operator(settings.unit, settings.operator)
                .with_history(settings.history)
                .with_output_dir(settings.output_dir)
                .with_csv_wide(settings.csv_wide)
                .with_settings(settings.safe_stop)
                .run(script, err),
        };
        // The one verdict rule, before any report reads the verdict.
        super::settle(&mut report);
        observer.run_finished(&report);
        report
    }
}
