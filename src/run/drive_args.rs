//! Choosing the dictionary (built-in family plus the user's own files, capped by the
//! bench limits file) and opening a [`Drive`] on a connection: the common start of every
//! command that talks to a drive.

use super::connection_args::{Connection, ConnectionArgs};
use super::RunError;
use crate::dictionary::{
    is_pole_pairs_setting, BenchLimits, Dictionary, PolePairs, LIMITS_ENV, POLE_PAIRS_SETTING,
};
use crate::drive::Drive;
use crate::family::{Family, LinkContext, Registry, DEFAULT_DICTIONARY};
use crate::link::TelegramObserver;
use crate::sim::SimulatedDrive;
use crate::stop_request::StopRequests;
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

#[derive(Debug, Clone, Args)]
#[command(next_help_heading = "Dictionary and bench limits")]
pub struct DictionaryArgs {
    /// The built-in dictionary to start from, by its name: sd2, ct-unidrive-sp, lenze-931,
    /// lenze-9400, sunfar-e500, modbus-inverter, modbus-tcp-inverter, canopen. The drive family its `family:` names picks the protocol
    /// (`ct-unidrive-sp` is a dictionary of the `ct-ansi` family).
    #[arg(id = "drive", long = "drive", value_name = "DICTIONARY", default_value = DEFAULT_DICTIONARY)]
    pub name: String,
    /// A dictionary file that adds objects to the built-in one (or replaces objects of the
    /// same name), or a CANopen node's EDS or DCF (`.eds`, `.dcf`) whose objects it adds.
    /// May be given several times.
    #[arg(long = "dictionary", value_name = "PATH")]
    pub extra: Vec<PathBuf>,
    /// Bench limits file capping speed and current (`max_speed: 12000 rpm`). Without it:
    /// the file named by $DRIVESCRIPT_LIMITS, else drivescript-limits.yaml next to the
    /// recipe. Nothing (recipe, --set, --dictionary) can raise its limits.
    #[arg(long = "limits", value_name = "FILE")]
    pub limits: Option<PathBuf>,
    /// The motor's pole pairs as given and who gave them: `--link-option pole-pairs=N`
    /// ([`ConnectionArgs::pole_pairs`]) or a named drive's `pole_pairs:`; over a recipe's
    /// `link: { pole_pairs: N }` and the dictionary's own `pole_pairs:`.
    #[arg(skip)]
    pub pole_pairs: Option<(String, String)>,
}

impl DictionaryArgs {
    /// The built-in dictionary `--drive` names (from any family of `registry`) with the
    /// user's files merged in and the bench limits applied last. For running or checking
    /// `recipe`, a `drivescript-limits.yaml` next to it caps the dictionary when neither
    /// --limits nor $DRIVESCRIPT_LIMITS names a limits file. On failure, the rendered
    /// diagnostic to print.
    pub fn load_for(&self, registry: &Registry, recipe: Option<&Path>) -> Result<Arc<Dictionary>, RunError> {
        let name = match (self.name.as_str(), recipe.and_then(|r| recipe_drive(registry, r))) {
            // A recipe for another built-in drive picks its dictionary when --drive is left
            // at the default.
            (DEFAULT_DICTIONARY, Some(drive)) => drive,
            (given, _) => given.to_string(),
        };
        let (family, builtin) = registry
            .dictionary(&name)
            .map_err(|e| RunError::Invalid(format!("error: {e}\n")))?;
        let mut dictionary = Dictionary::from_yaml_for(builtin.path, builtin.text, family.address_parser())?;
        for path in &self.extra {
            if crate::dictionary::is_eds_path(path) {
                // An EDS lists a CANopen node's objects: on another family's line their
                // indexes would name other objects.
                if family.bus_kind() != crate::bus::BusKind::Frames {
                    return Err(RunError::Invalid(format!(
                        "error: {} is a CANopen EDS/DCF, but the {} dictionary is for the {} family, which is not CANopen; give --drive canopen (or a recipe with `drive: canopen`)\n",
                        path.display(),
                        dictionary.name(),
                        family.id()
                    )));
                }
                dictionary.extend_from_eds(path, &|a| family.object_alias(a))?;
            } else {
                dictionary.extend_from(path)?;
            }
        }
        // Before the bench limits: those are rpm at the shaft whatever the pole pairs.
        let given = match (&self.pole_pairs, recipe.and_then(recipe_pole_pairs)) {
            (Some(given), _) => Some(given.clone()),
            (None, Some(n)) => Some((n, "the recipe's `link: { pole_pairs }`".to_string())),
            (None, None) => None,
        };
        if let Some((text, origin)) = given {
            let count =
                PolePairs::parse(&text).map_err(|e| RunError::Invalid(format!("error: {origin}: {e}\n")))?;
            dictionary
                .set_pole_pairs(count, &origin)
                .map_err(|e| RunError::Invalid(format!("error: {e}\n")))?;
        }
        // Last, so that no dictionary above can raise the bench's limits.
        let env = std::env::var_os(LIMITS_ENV);
        if let Some((path, route)) = BenchLimits::find(self.limits.as_deref(), env.as_deref(), recipe) {
            let limits = BenchLimits::load(&path, route)?;
            dictionary.apply_bench_limits(limits);
        }
        Ok(Arc::new(dictionary))
    }

    /// These options with the motor's pole pairs `connection` gives
    /// (`--link-option pole-pairs=N`), which the dictionary takes.
    pub fn with_pole_pairs_of(&self, connection: &ConnectionArgs) -> DictionaryArgs {
        DictionaryArgs {
            pole_pairs: connection
                .pole_pairs()
                .map(|n| (n.clone(), format!("--link-option {POLE_PAIRS_SETTING}={n}")))
                .or_else(|| self.pole_pairs.clone()),
            ..self.clone()
        }
    }

    /// The dictionary `--drive` names when it is not given, and no extra files.
    pub fn builtin_default() -> Self {
        DictionaryArgs {
            name: DEFAULT_DICTIONARY.into(),
            extra: Vec::new(),
            limits: None,
            pole_pairs: None,
        }
    }
}

/// The built-in dictionary a YAML recipe's top-level `drive:` means
/// ([`Registry::dictionary_for_drive`]). Anything that
/// cannot be read is left to the recipe loader to report; the file is read within the
/// loader's size limit.
fn recipe_drive(registry: &Registry, recipe: &Path) -> Option<String> {
    let root = recipe_root(recipe)?;
    let drive = match &root.get("drive")?.value {
        crate::diag::YamlValue::Str(s) => s.clone(),
        _ => return None,
    };
    registry.dictionary_for_drive(&drive).ok().map(str::to_string)
}

/// The pole pairs a YAML recipe's `link:` gives (`pole_pairs` or `pole-pairs`), read
/// before the recipe is loaded because its values are checked against the dictionary they
/// set; anything unreadable is left to the loader.
fn recipe_pole_pairs(recipe: &Path) -> Option<String> {
    let root = recipe_root(recipe)?;
    let link = root.get("link")?.entries()?;
    let (_, value) = link.iter().find(|(k, _)| is_pole_pairs_setting(&k.value))?;
    value.as_text()
}

/// A YAML recipe's parsed tree, when `recipe` is a regular YAML file (only such a file can
/// be read twice: here and by the loader; a pipe would be used up by this look).
fn recipe_root(recipe: &Path) -> Option<crate::diag::YamlNode> {
    let is_yaml = recipe
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"));
    let is_file = std::fs::metadata(recipe).is_ok_and(|m| m.is_file());
    if !is_yaml || !is_file {
        return None;
    }
    let source = crate::diag::read_source(recipe).ok()?;
    crate::diag::YamlNode::parse(&source).ok()
}

/// A drive ready for use, and the simulated drive behind it when there is one.
pub struct OpenDrive {
    pub drive: Drive,
    pub simulator: Option<Arc<Mutex<dyn SimulatedDrive>>>,
    pub description: String,
    /// The drive's family (for addresses in its own notation).
    pub family: Arc<dyn Family>,
}

/// Opens the connection for the family the dictionary names and wraps it in the drive
/// API, with an optional observer of every telegram (trace file, `-v`) and the stop
/// requests that end the link's waits. On failure, the message to print (exit code 3).
pub fn open_drive(
    registry: &Registry,
    connection: &ConnectionArgs,
    dictionary: Arc<Dictionary>,
    virtual_time: bool,
    observer: Option<Box<dyn TelegramObserver>>,
    stop: Option<Arc<StopRequests>>,
) -> Result<OpenDrive, RunError> {
    let family = registry
        .family(dictionary.family())
        .map_err(|e| RunError::Invalid(format!("error: {e}")))?;
    let Connection {
        bus,
        address,
        clock,
        simulator,
        description,
    } = connection
        .open(registry, family.as_ref(), virtual_time)
        .map_err(|e| RunError::Unreachable(format!("error: {e}")))?;
    let context = LinkContext {
        clock,
        observer,
        stop,
    };
    let access = family
        .open(&bus, &address, &connection.link_options(), context)
        .map_err(|e| RunError::Unreachable(format!("error: {e}")))?;
    Ok(OpenDrive {
        drive: Drive::new(access, dictionary),
        simulator,
        description,
        family,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{Args, Command};

    /// `--drive`'s help lists the dictionaries by name, every built-in one and only those.
    #[test]
    fn drive_help_lists_every_builtin_dictionary() {
        let command = DictionaryArgs::augment_args(Command::new("t"));
        let arg = command
            .get_arguments()
            .find(|a| a.get_long() == Some("drive"))
            .unwrap();
        let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
        let names = Registry::builtin().dictionary_names().join(", ");
        assert!(help.contains(&format!("by its name: {names}.")), "{help}");
    }
}
