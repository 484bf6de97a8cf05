//! `--sim` settings refused before anything runs when no simulated drive of the run would
//! act on them: any of them on a run that talks to no simulated drive (a port, a TCP
//! server, a CAN bus, a replayed capture), and `emergency-at` where no family's simulator
//! sends an emergency message. Reads the families' facts only; opens nothing.

use super::ConnectionArgs;
use crate::family::{Family, Registry};
use crate::sim::{SimSetting, SimSettingError};

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
