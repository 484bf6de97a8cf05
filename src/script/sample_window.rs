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
    pub fn window(&self, name: &str) -> Result<&Window, WindowError> {
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
            .ok_or_else(|| WindowError::NotSampled {
                name: name.to_string(),
                sampled: self.windows.iter().map(|w| w.object.name.clone()).collect(),
            })
    }

    pub fn statistic(&self, name: &str, s: Statistic) -> Result<f64, WindowError> {
        let w = self.window(name)?;
        if w.stats.count == 0 {
            return Err(WindowError::NoSamples {
                object: w.object.name.clone(),
            });
        }
        Ok(w.stats.get(s))
    }

    pub fn values(&self, name: &str) -> Result<Vec<f64>, WindowError> {
        let w = self.window(name)?;
        w.values.clone().ok_or_else(|| WindowError::TooManyValues {
            count: w.stats.count,
            object: w.object.name.clone(),
        })
    }
}

/// Why a window cannot answer what the script asked of it, and what to ask instead.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum WindowError {
    #[error("`{name}` was not sampled in this window (sampled: {})", sampled.join(", "))]
    NotSampled { name: String, sampled: Vec<String> },
    #[error("no samples of {object} in this window")]
    NoSamples { object: String },
    #[error("the window holds {count} samples of {object}, more than a script may keep ({max}); use its statistics, or sample for a shorter time", max = super::sandbox::MAX_ARRAY_SIZE)]
    TooManyValues { count: usize, object: String },
}
