//! `--sim` settings refused before anything runs when no simulated drive of the run would
//! act on them: any of them on a run that talks to no simulated drive (a port, a TCP
//! server, a CAN bus, a replayed capture, each named drive on a line of its own), and
//! `emergency-at` where no simulated drive's family sends an emergency message. Reads the
//! families' facts only; opens nothing. `run` and `check` ask the same ([`sim_checked`]).

use super::drive_set::{connection_of, dictionary_of};
use super::{ConnectionArgs, LoadedPlan, RunError};
use crate::family::{Family, Registry};
use crate::sim::{SimSetting, SimSettingError};
use std::sync::Arc;

/// Every `--sim` check of a run of `loaded` over `connection` (the command line's settings
/// over the file's), before anything opens: every setting refused when no drive of the run
/// is simulated (the line a real one or a replay, or each named drive on a line of its
/// own), and [`check_sim_settings`] with the simulated drives' families. On failure, the
/// message (exit code 2).
pub fn sim_checked(
    connection: &ConnectionArgs,
    registry: &Registry,
    loaded: &LoadedPlan,
) -> Result<(), RunError> {
    if connection.sim.is_empty() {
        return Ok(());
    }
    let invalid = |e: &dyn std::fmt::Display| RunError::Invalid(format!("error: {e}"));
    // Each drive's name, family and the line it is on: the command line's, or its own.
    let mut drives: Vec<(Option<&str>, Arc<dyn Family>, ConnectionArgs)> = Vec::new();
    let decls = loaded.plan.drives();
    if decls.is_empty() {
        let family = registry
            .family(loaded.dictionary.family())
            .map_err(|e| invalid(&e))?;
        drives.push((None, family, connection.clone()));
    }
    for decl in decls {
        let dictionary = dictionary_of(&loaded.drive_dictionaries, &decl.name)?;
        let family = registry.family(dictionary.family()).map_err(|e| invalid(&e))?;
        drives.push((Some(decl.name.as_str()), family, connection_of(decl, connection)?));
    }
    let simulated: Vec<&dyn Family> = drives
        .iter()
        .filter(|(_, _, line)| reaches_simulated(line))
        .map(|(_, family, _)| family.as_ref())
        .collect();
    if simulated.is_empty() {
        let lines: Vec<String> = drives
            .iter()
            .map(|(name, family, line)| match name {
                Some(name) => format!("{name}: {}", line_of(line, family.as_ref())),
                None => line_of(line, family.as_ref()),
            })
            .collect();
        return Err(invalid(&SimSettingError::NotSimulated {
            line: lines.join(" and "),
        }));
    }
    check_sim_settings(&connection.sim, registry, &simulated).map_err(|e| invalid(&e))
}

/// Whether a drive on `connection` is the built-in simulated drive.
fn reaches_simulated(connection: &ConnectionArgs) -> bool {
    connection.is_simulated() && connection.replay.is_none()
}

/// The line without its timeout and retries: `serial /dev/ttyUSB0, 57600 8N1`.
fn line_of(connection: &ConnectionArgs, family: &dyn Family) -> String {
    let line = connection.line_text(family);
    line.split(';').next().unwrap_or(&line).to_string()
}

/// Refuses `emergency-at` in `settings` when none of `families` (the run's drives') has a
/// simulated drive that sends emergency messages; the refusal names the built-in
/// dictionaries whose drives do.
pub fn check_sim_settings(
    settings: &[SimSetting],
    registry: &Registry,
    families: &[&dyn Family],
) -> Result<(), SimSettingError> {
    let emergency = settings.iter().any(|s| matches!(s, SimSetting::EmergencyAt(..)));
    if !emergency || families.iter().any(|f| f.info().sim_emergencies) {
        return Ok(());
    }
    let mut ids: Vec<&str> = families.iter().map(|f| f.id()).collect();
    ids.sort_unstable();
    ids.dedup();
    let senders: Vec<&str> = registry
        .families()
        .filter(|f| f.info().sim_emergencies)
        .flat_map(|f| f.dictionaries().iter().map(|d| d.name))
        .collect();
    Err(SimSettingError::NoEmergencies {
        families: ids.join(" or "),
        senders: senders.join(" or --drive "),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_emergency_is_refused_only_where_no_simulated_drive_sends_one() {
        let registry = Registry::builtin();
        let family = |id: &str| registry.family(id).unwrap();
        let (sd2, modbus, canopen) = (family("sd2"), family("modbus-rtu"), family("canopen"));
        let emergency = [SimSetting::parse("emergency-at=20s:0x2310").unwrap()];
        let physics = [SimSetting::parse("overshoot=10%").unwrap()];
        let e = check_sim_settings(&emergency, &registry, &[sd2.as_ref()]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--sim emergency-at: no simulated sd2 drive sends emergency messages (an EMCY is a CANopen node's), so the setting would do nothing; give it with --drive lenze-9400 or --drive canopen, or leave it out"
        );
        let e = check_sim_settings(&emergency, &registry, &[sd2.as_ref(), modbus.as_ref()]).unwrap_err();
        assert!(
            e.to_string()
                .contains("no simulated modbus-rtu or sd2 drive sends"),
            "{e}"
        );
        assert_eq!(check_sim_settings(&physics, &registry, &[sd2.as_ref()]), Ok(()));
        assert_eq!(
            check_sim_settings(&emergency, &registry, &[canopen.as_ref()]),
            Ok(())
        );
        // Several drives: the CANopen node among them gets it.
        assert_eq!(
            check_sim_settings(&emergency, &registry, &[sd2.as_ref(), canopen.as_ref()]),
            Ok(())
        );
    }
}
