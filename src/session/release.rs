//! After the whole safe stop: each drive's link hands back what it changed on its own (a
//! CANopen node's NMT state) only where the drive was read back stopped; otherwise it
//! keeps it and says so. Sends nothing but what a link hands back; never on the stop's
//! path (it comes after the verification).

use super::session::Session;

impl Session<'_> {
    /// After the whole safe stop: each drive's link hands back what it changed on its own
    /// (a CANopen node's NMT state) and says so, unless the drives are left enabled on
    /// purpose; a drive whose stop was not verified keeps it, and that is said instead.
    pub(super) fn release_drives(&mut self, kept: bool) {
        for i in 0..self.drives.len() {
            if kept {
                break;
            }
            let said = match self.stop_verified(i) {
                true => self.drives[i].drive.release(),
                false => self.drives[i].drive.withhold_release(),
            };
            if let Some(text) = said {
                self.observer.message(&text);
            }
        }
    }

    /// Whether drive `i` was read back stopped: its state not powered and its speed read
    /// at standstill.
    fn stop_verified(&self, i: usize) -> bool {
        let r = &self.report;
        match r.drive_ends.iter().find(|e| e.name == self.drives[i].name) {
            Some(e) => e.end.stop_confirmed && !e.end.coasting && !e.end.speed_unread,
            None => r.end.stop_confirmed && !r.end.coasting && !r.end.speed_unread,
        }
    }
}
