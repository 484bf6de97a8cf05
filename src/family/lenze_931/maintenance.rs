//! The 931's maintenance commands as named actions (`drivescript maintain`): `RESET!`,
//! `INIT!`, `SEP!` and `BAUDbbbb` from the manual's command list. `SAVE!` is not one of
//! them: `restore --store` sends it through `ObjectAccess::store_parameters`. Must not
//! send anything itself.

use super::codec::Request;
use crate::drive::MaintenanceAction;

/// Largest rate `BAUDbbbb` is built with here: the codec reads at most six digits.
pub const MAX_BAUD: u32 = 999_999;

pub const ACTIONS: &[MaintenanceAction] = &[
    MaintenanceAction {
        name: "reset",
        command: "RESET!",
        summary: "hardware reset; the drive answers with its switch-on message",
        destructive: Some("the drive restarts"),
        argument: None,
        changes_line_rate: false,
    },
    MaintenanceAction {
        name: "init",
        command: "INIT!",
        summary: "load the default parameter set; the drive answers with its switch-on message",
        destructive: Some("the default parameter set replaces the parameters in use"),
        argument: None,
        changes_line_rate: false,
    },
    MaintenanceAction {
        name: "load",
        command: "SEP!",
        summary: "load the parameter set saved in flash; the drive answers DONE",
        destructive: Some(
            "the parameter set in flash replaces the parameters in use; changes not saved with SAVE! (restore --store) are lost",
        ),
        argument: None,
        changes_line_rate: false,
    },
    MaintenanceAction {
        name: "baud",
        command: "BAUDbbbb",
        summary: "set the baud rate; the drive answers OK!. The rate is sent in decimal digits (BAUD19200): the manual writes BAUDbbbb without saying how bbbb is written (unconfirmed)",
        destructive: Some("the drive talks at the new rate from then on"),
        argument: Some("RATE"),
        changes_line_rate: true,
    },
];

/// The request of the action named `name` with its argument; `Err` says what is wrong.
pub fn request(name: &str, argument: Option<u32>) -> Result<Request, BadAction> {
    match (name, argument) {
        ("reset", None) => Ok(Request::Reset),
        ("init", None) => Ok(Request::Init),
        ("load", None) => Ok(Request::Sep),
        ("baud", Some(rate)) if (1..=MAX_BAUD).contains(&rate) => Ok(Request::Baud(rate)),
        ("baud", Some(rate)) => Err(BadAction::Rate { rate }),
        ("baud", None) => Err(BadAction::NoRate),
        (name, Some(_)) if ACTIONS.iter().any(|a| a.name == name) => Err(BadAction::TakesNoValue {
            name: name.to_string(),
        }),
        (name, _) => Err(BadAction::Unknown {
            name: name.to_string(),
        }),
    }
}

/// Why a maintenance action cannot be sent, and what to give instead (the access carries
/// it as `AccessError::Encode`: nothing was sent).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BadAction {
    #[error("baud {rate}: give a rate from 1 to {MAX_BAUD} (the 931 ships at 9600)")]
    Rate { rate: u32 },
    #[error("baud needs the new rate, e.g. `baud 19200`")]
    NoRate,
    #[error("{name} takes no value")]
    TakesNoValue { name: String },
    #[error("the 931 has no maintenance action `{name}` (it has: {})", action_names())]
    Unknown { name: String },
}

fn action_names() -> String {
    ACTIONS.iter().map(|a| a.name).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_action_builds_the_manuals_command() {
        let texts: Vec<String> = [
            ("reset", None),
            ("init", None),
            ("load", None),
            ("baud", Some(19200)),
        ]
        .iter()
        .map(|(n, a)| request(n, *a).map(|r| r.text()).unwrap())
        .collect();
        assert_eq!(texts, ["RESET!", "INIT!", "SEP!", "BAUD19200"]);
        for a in ACTIONS {
            assert!(a.destructive.is_some(), "{} changes the drive", a.name);
            assert_eq!(a.argument.is_some(), a.name == "baud");
        }
    }

    #[test]
    fn wrong_values_and_names_are_refused_with_what_to_give() {
        let refused = |name, argument| request(name, argument).unwrap_err().to_string();
        assert!(refused("baud", None).contains("baud 19200"));
        assert!(refused("baud", Some(0)).contains("from 1 to 999999"));
        assert!(request("baud", Some(1_000_000)).is_err());
        assert_eq!(refused("reset", Some(1)), "reset takes no value");
        assert!(refused("save", None).contains("it has: reset, init, load, baud"));
    }
}
