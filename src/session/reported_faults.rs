//! Faults a drive reported on its own (a CANopen node's EMCY, which its state may not
//! show) that come as the run ends. The fault watch looks only now and then, so one may be
//! waiting, untaken, when the steps end: it ends the run as a fault as if a watch had seen
//! it (`on_fault`, then the safe stop). One reported during the safe stop stops nothing:
//! the stop goes on as it is, then the fault is said and the run is no pass. Reads what the
//! links already hold; sends nothing, so it is never on the stop's path.

use super::session::Session;
use super::stop::Stop;
use super::Verdict;

impl Session<'_> {
    /// Faults the drives reported that no fault watch has taken yet: `the drive reported
    /// node 1 EMCY 0x2310 …`, one per drive at most.
    fn take_reported_faults(&mut self) -> Vec<String> {
        let mut taken = Vec::new();
        for i in 0..self.drives.len() {
            if let Some(what) = self.drives[i].drive.reported_fault() {
                taken.push(format!("{} reported {what}", self.drives[i].called()));
            }
        }
        taken
    }

    /// How the operations ended, with a fault a drive reported that was still waiting when
    /// the steps ended (or failed): that run ends as a drive fault. Faults reported after a
    /// harder ending (an error, a stop request) are kept for the safe stop's notes.
    pub(super) fn with_pending_fault(&mut self, ended: Option<Stop>) -> Option<Stop> {
        if !matches!(
            ended,
            None | Some(
                Stop::Failed(_) | Stop::Unanswered(_) | Stop::OtherUnit(_) | Stop::StoppedOnFailure(_)
            )
        ) {
            return ended;
        }
        let mut pending = self.take_reported_faults().into_iter();
        let Some(first) = pending.next() else {
            return ended;
        };
        self.reported_in_stop.extend(pending);
        Some(Stop::Fault(format!("drive fault: {first} as the steps ended")))
    }

    /// Whether a drive reported a fault since the run's end was decided (its drives read
    /// back to be left enabled): each is kept to be said after the stop.
    pub(super) fn keep_faults_reported_since(&mut self) -> bool {
        let taken = self.take_reported_faults();
        self.reported_in_stop.extend(taken);
        !self.reported_in_stop.is_empty()
    }

    /// A fault reported while the run ends (`on_fault`, the safe stop): it stops nothing
    /// more, and is said when the stop is over.
    pub(super) fn keep_reported_in_stop(&mut self, what: String) {
        self.reported_in_stop.push(what);
    }

    /// After the whole safe stop: every fault a drive reported during it is said, and a
    /// run that would pass or fail on its checks ends as a drive fault instead.
    pub(super) fn say_reported_in_stop(&mut self) {
        let mut reported = std::mem::take(&mut self.reported_in_stop);
        reported.extend(self.take_reported_faults());
        for what in &reported {
            self.note(format!("{what} during the safe stop (the stop went on)"));
        }
        if let (Some(first), Verdict::Passed | Verdict::Failed) = (reported.first(), &self.report.verdict) {
            self.report.verdict = Verdict::Error(format!("drive fault: {first} during the safe stop"));
        }
    }
}
