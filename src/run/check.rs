//! `check` of one file, through the loading a run uses ([`RunPlan::load_file`]): the file
//! against each drive's dictionary and the bench limits, and, with a real connection,
//! every value it is known to write against the limits the drive itself reports (only
//! reads are sent). Answers with what it found for the caller to say; prints nothing and
//! must not send anything that moves a drive.

use super::drive_limits::{against_drive, DriveCheck};
use super::{ConnectionArgs, DictionaryArgs, LoadedPlan, RunError, RunPlan};
use crate::dictionary::BenchLimits;
use crate::family::Registry;
use std::io::Write;
use std::path::Path;

/// What one file is checked with; the command line fills it from its options.
pub struct CheckRequest<'a> {
    pub registry: &'a Registry,
    /// The recipe, or the script (`.rhai`).
    pub file: &'a Path,
    pub set: &'a [(String, String)],
    pub dictionary: &'a DictionaryArgs,
    pub connection: &'a ConnectionArgs,
}

/// A file that passed the checks of its dictionaries, and what the drive said of it.
pub struct Checked {
    pub loaded: LoadedPlan,
    /// The values written compared with the limits the drive reports; `None` where none
    /// were compared: no port given, several drives (whose connections a check does not
    /// open), or nothing known to be written.
    pub drive_limits: Option<Result<DriveCheck, RunError>>,
    /// Written values the wire's whole counts change (see [`super::quantised_values`]).
    pub quantised: Vec<String>,
    /// Enables of a recipe that start the drive at a setpoint left from before a disable,
    /// each to be warned of at its place.
    pub leftover_setpoints: Vec<crate::recipe::LeftoverSetpoint>,
}

impl Checked {
    /// The bench limits file that capped the check, to be named (every drive of the file
    /// has the same one).
    pub fn bench_limits(&self) -> Option<&BenchLimits> {
        self.loaded.dictionary.bench_limits()
    }
}

/// Checks `request.file` as `run` would before it opens anything; with a port, also
/// against the drive's own limits. `Err`: the file's problems (each at its place) or a
/// dictionary that cannot be loaded (exit code 2). A drive that could not be reached is
/// in [`Checked::drive_limits`], with `err` told when the connection is simulated.
pub fn check(request: &CheckRequest, err: &mut dyn Write) -> Result<Checked, RunError> {
    let loaded = RunPlan::load_file(
        request.registry,
        request.file,
        request.set,
        &request.dictionary.with_pole_pairs_of(request.connection),
    )?;
    let written = loaded.plan.written_values();
    // Values the link's settings cannot carry are refused as `run` refuses them, before
    // any port is opened.
    let link = request.connection.with_defaults(loaded.plan.link());
    super::within_link_range(&written, &loaded, request.registry, &link)?;
    super::watches_fit_the_line(&loaded, request.registry, &link)?;
    super::sim_checked(&link, request.registry, &loaded)?;
    let compare =
        !request.connection.is_simulated() && loaded.plan.drives().is_empty() && !written.is_empty();
    let drive_limits = compare.then(|| {
        against_drive(
            request.registry,
            &written,
            loaded.dictionary.clone(),
            request.connection,
            err,
        )
    });
    let quantised = super::quantised_values(&written, &loaded);
    let setpoint = loaded
        .dictionary
        .profile()
        .and_then(|p| p.object(crate::dictionary::Role::SpeedSetpoint))
        .map(str::to_string);
    let leftover_setpoints = match (&loaded.plan, setpoint) {
        (RunPlan::Recipe(recipe), Some(setpoint)) => crate::recipe::leftover_setpoints(recipe, &setpoint),
        _ => Vec::new(),
    };
    Ok(Checked {
        loaded,
        drive_limits,
        quantised,
        leftover_setpoints,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn scratch(name: &str, files: &[(&str, &str)]) -> PathBuf {
        let dir = crate::scratch_dir::scratch_dir(&format!("check-{name}"));
        for (file, text) in files {
            std::fs::write(dir.join(file), text).unwrap();
        }
        dir
    }

    fn checked(file: &Path, connection: &ConnectionArgs) -> Result<Checked, RunError> {
        let registry = Registry::builtin();
        let request = CheckRequest {
            registry: &registry,
            file,
            set: &[],
            dictionary: &DictionaryArgs::builtin_default(),
            connection,
        };
        check(&request, &mut Vec::new())
    }

    /// A port that does not exist: a check that opened it would say the drive could not
    /// be reached.
    fn missing_port() -> ConnectionArgs {
        ConnectionArgs {
            port: Some("/dev/drivescript-no-such-port".into()),
            ..ConnectionArgs::simulated()
        }
    }

    #[test]
    fn a_recipe_and_a_script_are_checked_through_the_runs_loading() {
        let dir = scratch(
            "both",
            &[
                ("r.yaml", "name: R\nsteps:\n  - set: { speed_setpoint: 10 rpm }\n"),
                (
                    "s.rhai",
                    "//! name: S\nlet d = drive();\nd.set(\"speed_setpoint\", 10.0, \"rpm\");\n",
                ),
                (
                    "bad.yaml",
                    "name: B\nsteps:\n  - set: { sped_setpoint: 10 rpm }\n",
                ),
                (
                    "bad.rhai",
                    "let d = drive();\nd.set(\"sped_setpoint\", 10.0, \"rpm\");\n",
                ),
            ],
        );
        let simulated = ConnectionArgs::simulated();
        let recipe = checked(&dir.join("r.yaml"), &simulated).unwrap();
        assert!(matches!(&recipe.loaded.plan, RunPlan::Recipe(r) if r.name == "R"));
        assert!(recipe.drive_limits.is_none(), "no port, no drive asked");
        let script = checked(&dir.join("s.rhai"), &simulated).unwrap();
        assert!(matches!(&script.loaded.plan, RunPlan::Script(s) if s.name == "S"));
        let bad = checked(&dir.join("bad.yaml"), &simulated).err().unwrap();
        assert!(
            matches!(&bad, RunError::File(e) if e.problems.len() == 1),
            "{bad}"
        );
        assert_eq!(bad.exit_code(), crate::run::INVALID);
        let bad = checked(&dir.join("bad.rhai"), &simulated).err().unwrap();
        assert!(
            matches!(&bad, RunError::File(e) if e.problems.len() == 1),
            "{bad}"
        );
    }

    #[test]
    fn with_a_port_the_drive_is_asked_only_about_values_written_to_one_drive() {
        let dir = scratch(
            "port",
            &[
                ("writes.yaml", "name: W\nsteps:\n  - set: { speed_setpoint: 10 rpm }\n"),
                ("reads.yaml", "name: R\nsteps:\n  - read: [speed_actual]\n"),
                (
                    "two.yaml",
                    "name: T\ndrives:\n  left: { drive: sd2, address: dnc:2 }\n  right: { drive: sd2, address: dnc:3 }\nsteps:\n  - set: { left.speed_setpoint: 10 rpm }\n",
                ),
            ],
        );
        let port = missing_port();
        let writes = checked(&dir.join("writes.yaml"), &port).unwrap();
        let unreachable = writes.drive_limits.expect("the drive is asked");
        assert!(matches!(unreachable, Err(RunError::Unreachable(_))));
        // Nothing to compare: the port is not even opened.
        assert!(checked(&dir.join("reads.yaml"), &port)
            .unwrap()
            .drive_limits
            .is_none());
        assert!(checked(&dir.join("two.yaml"), &port)
            .unwrap()
            .drive_limits
            .is_none());
    }
}
