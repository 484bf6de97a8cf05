//! Recipe YAML → a validated [`Recipe`]: the entry points and the state one file's reading
//! shares (the dictionary, the parameters, what was sampled, the include chain, the limits
//! on expansion). The reading itself is split by job into `loader/`; every problem is
//! recorded with its place through `diag::Reader`, and reading goes on, so a check reports
//! them all. Never talks to a drive.

mod drives;
mod includes;
mod objects;
mod on_failure;
mod params;
mod set_blame;
mod steps;
mod top_keys;
mod values;
mod watch;

#[cfg(test)]
mod tests;

use super::expansion::{Expansion, OverLimit};
use super::recipe::Recipe;
use super::text_digest::TextDigest;
use super::RecipeInvalid;
use crate::diag::{read_source, Diagnostic, Diagnostics, Reader, Source, Span};
use crate::dictionary::Dictionary;
use crate::drive::AddressKeyTable;
use crate::session::{show_duration, StepOrigin};
pub use drives::{declared_drives, declared_pole_pairs, DriveDictionaries};
pub use params::declared_params;
use params::ParamValue;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;
pub(super) use steps::{COAST_DOWN_EVERY, COAST_DOWN_TIMEOUT, STEP_KEYS};

/// Default `timeout` of `wait_until` and of each `go_to` transition.
pub const DEFAULT_WAIT_TIMEOUT: Duration = Duration::from_secs(10);
pub const DEFAULT_GO_TO_TIMEOUT: Duration = Duration::from_secs(5);
/// Default poll interval of `wait_until`.
pub const DEFAULT_POLL: Duration = Duration::from_millis(100);
/// Default interval of `ramp`.
pub const DEFAULT_RAMP_EVERY: Duration = Duration::from_millis(100);
/// The longest duration a recipe may give (dwell, timeout, `every`, `for`). Run-ins last
/// hours or days, not years; anything longer is a typo in the number or the unit, and the
/// cap keeps every sum of durations the run makes far from overflowing.
pub const MAX_DURATION: Duration = Duration::from_secs(1000 * 24 * 3600);
/// Most samples one `sample` step may take (`for` / `every` + 1). Memory does not grow
/// with them (statistics stream, plots keep a fixed number of buckets), but the runner
/// counts them in a `u32`; a billion is 115 days at 10 ms.
pub const MAX_SAMPLES: u64 = 1_000_000_000;

/// Loads and validates a recipe file. `overrides` are `--set name=value` pairs.
pub fn load_recipe(
    path: &Path,
    dictionary: &Dictionary,
    overrides: &[(String, String)],
) -> Result<Recipe, RecipeInvalid> {
    let source = match read_source(path) {
        Ok(source) => source,
        Err(e) => {
            let shown = path.display().to_string();
            let help = e.help().unwrap_or_else(|| {
                "check the path; recipes are YAML files such as recipes/commissioning.yaml".into()
            });
            // Shown at the start of the (empty) file, so the message is headed by its path.
            let start = Span::start_of(&Source::new(shown.as_str(), ""));
            let problem =
                Diagnostic::at(&start, e.sentence(&format!("the recipe {shown}")), "").with_help(help);
            return Err(RecipeInvalid {
                path: shown,
                problems: std::iter::once(problem).collect(),
            });
        }
    };
    load_source(
        source,
        path.parent().unwrap_or(Path::new(".")),
        dictionary,
        overrides,
    )
}

/// Loads and validates a recipe that may declare several drives (`drives:`): `drives`
/// holds the dictionary of each (see [`declared_drives`]); `dictionary` is the first's, or
/// the one dictionary of a recipe without `drives:`.
pub fn load_recipe_for(
    path: &Path,
    dictionary: &Dictionary,
    drives: &[(String, Arc<Dictionary>)],
    address_keys: &AddressKeyTable,
    overrides: &[(String, String)],
) -> Result<Recipe, RecipeInvalid> {
    if drives.is_empty() {
        return load_recipe(path, dictionary, overrides);
    }
    let source = match read_source(path) {
        Ok(source) => source,
        Err(_) => return load_recipe(path, dictionary, overrides),
    };
    load_source_for(
        source,
        path.parent().unwrap_or(Path::new(".")),
        dictionary,
        (drives, address_keys),
        overrides,
    )
}

/// Validates recipe text; `base_dir` resolves `include` paths.
pub fn load_recipe_text(
    path: &str,
    text: &str,
    base_dir: &Path,
    dictionary: &Dictionary,
    overrides: &[(String, String)],
) -> Result<Recipe, RecipeInvalid> {
    load_source(Source::new(path, text), base_dir, dictionary, overrides)
}

fn load_source(
    source: Arc<Source>,
    base_dir: &Path,
    dictionary: &Dictionary,
    overrides: &[(String, String)],
) -> Result<Recipe, RecipeInvalid> {
    load_source_for(
        source,
        base_dir,
        dictionary,
        (&[], &AddressKeyTable::default()),
        overrides,
    )
}

/// `drives`: each named drive's dictionary, and every family's address keys.
fn load_source_for(
    source: Arc<Source>,
    base_dir: &Path,
    dictionary: &Dictionary,
    drives: (&[(String, Arc<Dictionary>)], &AddressKeyTable),
    overrides: &[(String, String)],
) -> Result<Recipe, RecipeInvalid> {
    let load =
        |overrides: &[(String, String)]| load_once(source.clone(), base_dir, dictionary, drives, overrides);
    load(overrides).map_err(|invalid| match overrides {
        [] => invalid,
        _ => set_blame::blamed_on_set(invalid, overrides, load),
    })
}

fn load_once(
    source: Arc<Source>,
    base_dir: &Path,
    dictionary: &Dictionary,
    (drives, address_keys): (&[(String, Arc<Dictionary>)], &AddressKeyTable),
    overrides: &[(String, String)],
) -> Result<Recipe, RecipeInvalid> {
    let mut problems = Diagnostics::new();
    let mut expansion = Expansion::default();
    let mut digest = TextDigest::default();
    digest.add(source.text());
    let path = source.path().to_string();
    let recipe = Loader {
        dict: dictionary,
        drive_dicts: drives,
        address_keys,
        include_chain: vec![canonical(&base_dir.join(file_name(&path)))],
        source,
        r: Reader::new(&mut problems),
        expansion: &mut expansion,
        digest: &mut digest,
        params: BTreeMap::new(),
        sampled: HashMap::new(),
        sample_refused: false,
        base_dir: base_dir.to_path_buf(),
    }
    .recipe(overrides);
    match recipe {
        Some(r) if problems.is_empty() => Ok(Recipe {
            text_sha256: digest.hex(),
            ..r
        }),
        _ => Err(RecipeInvalid { path, problems }),
    }
}

fn file_name(path: &str) -> PathBuf {
    Path::new(path).file_name().map(PathBuf::from).unwrap_or_default()
}

/// A file named in a recipe (with `/`, as recipes are shared between systems), found next
/// to the recipe and written in the platform's own form: `recipes\includes\stage.yaml`
/// on Windows, never a mix of both separators.
fn beside(base_dir: &Path, written: &str) -> PathBuf {
    base_dir.join(Path::new(written).components().collect::<PathBuf>())
}

fn canonical(p: &Path) -> PathBuf {
    std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf())
}

/// Reads one recipe file (the top one or an included one).
struct Loader<'a, 'p> {
    /// The dictionary object names are looked up in: the recipe's one, or while a step
    /// naming a drive is read, that drive's.
    dict: &'a Dictionary,
    /// Each named drive's dictionary (`drives:`); empty for a recipe with one `drive:`.
    drive_dicts: &'a [(String, Arc<Dictionary>)],
    /// Every family's keys besides `address:` in a `drives:` entry (`dnc_address`).
    address_keys: &'a AddressKeyTable,
    source: Arc<Source>,
    r: Reader<'p>,
    /// Included files and steps so far, over every level of includes.
    expansion: &'p mut Expansion,
    /// The text of the recipe and of every file it includes, as read.
    digest: &'p mut TextDigest,
    params: BTreeMap<String, ParamValue>,
    /// Objects sampled so far in file order, for `expect` on statistics; true when the last
    /// sample step declared a step for it (for the measures of a step response).
    sampled: HashMap<String, bool>,
    /// A `sample` step so far was refused: an `expect` on a statistic of an object it does
    /// not find sampled says nothing more (one mistake, one error).
    sample_refused: bool,
    base_dir: PathBuf,
    include_chain: Vec<PathBuf>,
}

impl Loader<'_, '_> {
    fn problem(
        &mut self,
        span: &Span,
        message: impl Into<String>,
        label: impl Into<String>,
        help: Option<String>,
    ) {
        self.r.problem(span, message, label, help);
    }

    /// Records a problem and gives up on the part being read (the one way a part refuses).
    fn refuse<T>(
        &mut self,
        span: &Span,
        message: impl Into<String>,
        label: impl Into<String>,
        help: Option<String>,
    ) -> Option<T> {
        self.problem(span, message, label, help);
        None
    }

    fn over_limit(&mut self, span: &Span, over: OverLimit) {
        self.problem(span, over.message, over.label, Some(over.help));
    }

    fn origin(&self, span: &Span) -> StepOrigin {
        StepOrigin {
            path: self.source.path().to_string(),
            line: span.line(),
            column: span.column(),
        }
    }
}

/// The closest candidate, if any is close (the one similarity rule of every loader).
fn did_you_mean<'a>(input: &str, candidates: impl Iterator<Item = &'a str>) -> Option<String> {
    crate::diag::did_you_mean(input, candidates).into_iter().next()
}
