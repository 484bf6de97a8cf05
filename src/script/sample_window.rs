//! What `d.sample(...)` gives a script: per object the statistics of the window (mean,
//! min, max, std, ripple, count) and its values, looked up by name or alias. Plain data
//! for Rhai; it must not read the drive.

use super::exchange::Window;
use crate::dictionary::Dictionary;
use crate::session::Statistic;
use std::sync::Arc;

#[derive(Debug, Clone)]
pub struct SampleWindow {
    pub windows: Vec<Window>,
    pub dictionary: Arc<Dictionary>,
}

impl SampleWindow {
    /// The window of `name` (the dictionary's name or an alias).
    pub fn window(&self, name: &str) -> Result<&Window, String> {
        let canonical = self
            .dictionary
            .lookup(name)
            .map(|d| d.name.clone())
            .unwrap_or_else(|_| name.to_string());
        // A drive's sample (`drive("left").sample(...)`) names its objects `left.speed_actual`;
        // the script names them as it sampled them.
        let suffix = format!(".{canonical}");
        let mut of_a_drive = self.windows.iter().filter(|w| w.object.name.ends_with(&suffix));
        let by_drive = match (of_a_drive.next(), of_a_drive.next()) {
            (Some(w), None) => Some(w),
            _ => None,
        };
        self.windows
            .iter()
            .find(|w| w.object.name == canonical)
            .or(by_drive)
            .ok_or_else(|| {
                let sampled: Vec<&str> = self.windows.iter().map(|w| w.object.name.as_str()).collect();
                format!(
                    "`{name}` was not sampled in this window (sampled: {})",
                    sampled.join(", ")
                )
            })
    }

    pub fn statistic(&self, name: &str, s: Statistic) -> Result<f64, String> {
        let w = self.window(name)?;
        if w.stats.count == 0 {
            return Err(format!("no samples of {} in this window", w.object.name));
        }
        Ok(w.stats.get(s))
    }

    pub fn values(&self, name: &str) -> Result<Vec<f64>, String> {
        let w = self.window(name)?;
        w.values.clone().ok_or_else(|| {
            format!(
                "the window holds {} samples of {}, more than a script may keep ({}); use its statistics, or sample for a shorter time",
                w.stats.count,
                w.object.name,
                super::sandbox::MAX_ARRAY_SIZE
            )
        })
    }
}
