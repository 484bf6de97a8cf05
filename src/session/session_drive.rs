//! One drive of a session and what the session remembers about it: the name a recipe
//! gives it (empty for the one drive of a single-drive run), whether it was in fault when
//! last looked at, its identity at the start, whether reopening its port was given up,
//! and when it was last enabled (the safe stop stops the last enabled first). Plain data;
//! the operations live in the session.

use crate::drive::Drive;

pub(super) struct SessionDrive<'a> {
    /// `left`; empty for the drive of a single-drive run.
    pub name: String,
    pub drive: &'a mut Drive,
    /// Whether the drive was in a fault state when last looked at. Fault watching reacts
    /// to the drive *entering* a fault during the run; a drive already in fault (at the
    /// start, or after a step that waited for it) is the run's to reset.
    pub known_fault: bool,
    /// The identity read at the start, to recognise the drive after a reopen.
    pub identity: Option<String>,
    /// Reopening the port was tried for the whole reconnect time and failed: later
    /// failures of the safe stop do not wait for it again.
    pub link_given_up: bool,
    /// Order of the last command or walk that enabled it (0: never); the safe stop takes
    /// the drives from the highest down.
    pub enabled_order: u64,
    /// A coast-down switched its power stage off and it may still turn: the safe stop
    /// cannot brake it and says so.
    pub coasting_by_design: bool,
}

impl<'a> SessionDrive<'a> {
    pub fn new(name: String, drive: &'a mut Drive) -> Self {
        SessionDrive {
            name,
            drive,
            known_fault: false,
            identity: None,
            link_given_up: false,
            enabled_order: 0,
            coasting_by_design: false,
        }
    }

    /// `drive `left` ` for messages of a run with several drives, `the drive ` for one.
    pub fn called(&self) -> String {
        if self.name.is_empty() {
            "the drive".to_string()
        } else {
            format!("drive `{}`", self.name)
        }
    }
}
