//! `--sim` settings refused before anything runs when no simulated drive of the run would
//! act on them: any of them on a run that talks to no simulated drive (a port, a TCP
//! server, a CAN bus, a replayed capture), and `emergency-at` where no family's simulator
//! sends an emergency message. Reads the families' facts only; opens nothing. `run` and
//! `check` ask the same ([`sim_checked`]).

use super::{ConnectionArgs, LoadedPlan, RunError};
use crate::family::{Family, Registry};
use crate::sim::{SimSetting, SimSettingError};

/// Every `--sim` check of a run of `loaded` over `connection` (the command line's settings
/// over the file's), before anything opens: [`check_sim_target`] and
/// [`check_sim_settings`] with the run's families (the named drives', else the one
/// drive's). On failure, the message (exit code 2).
pub fn sim_checked(
    connection: &ConnectionArgs,
    registry: &Registry,
    loaded: &LoadedPlan,
) -> Result<(), RunError> {
    let invalid = |e: &dyn std::fmt::Display| RunError::Invalid(format!("error: {e}"));
    let dictionaries: Vec<_> = match loaded.plan.drives().is_empty() {
        true => vec![&loaded.dictionary],
        false => loaded.drive_dictionaries.iter().map(|(_, d)| d).collect(),
    };
    let families = dictionaries
        .iter()
        .map(|d| registry.family(d.family()))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| invalid(&e))?;
    let family_refs: Vec<&dyn Family> = families.iter().map(|f| f.as_ref()).collect();
    if let Some(family) = family_refs.first() {
        check_sim_target(connection, *family).map_err(|e| invalid(&e))?;
    }
    check_sim_settings(&connection.sim, registry, &family_refs).map_err(|e| invalid(&e))
}

/// Refuses every `--sim` setting when `connection` reaches no simulated drive, naming the
/// line it does reach (`family`: the run's first drive's, for the line's settings).
pub fn check_sim_target(connection: &ConnectionArgs, family: &dyn Family) -> Result<(), SimSettingError> {
    if connection.sim.is_empty() || (connection.is_simulated() && connection.replay.is_none()) {
        return Ok(());
    }
    let line = connection.line_text(family);
    // The line without its timeout and retries: `serial /dev/ttyUSB0, 57600 8N1`.
    let line = line.split(';').next().unwrap_or(&line).to_string();
    Err(SimSettingError::NotSimulated { line })
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
