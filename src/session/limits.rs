//! A check's limits: the lowest and the highest value it passes, either of which may be
//! open. The same pair in a check's result, its stored row, a trend point and a process
//! capability; plain data and the one way every report writes it.

use super::condition::{number, with_unit};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    pub low: Option<f64>,
    pub high: Option<f64>,
}

impl Limits {
    pub fn new(low: Option<f64>, high: Option<f64>) -> Limits {
        Limits { low, high }
    }

    /// Whether there is a limit at all.
    pub fn any(&self) -> bool {
        self.low.is_some() || self.high.is_some()
    }

    /// As every report writes them: `5970 .. 6030 rpm`, `= 1`, `≥ 5 A` (or `> 5 A` when
    /// not `inclusive`), `≤ 2.8 mm/s`; `None` without limits.
    pub fn text(&self, unit: Option<&str>, inclusive: bool) -> Option<String> {
        let (above, below) = match inclusive {
            true => ("≥", "≤"),
            false => (">", "<"),
        };
        Some(match (self.low, self.high) {
            (Some(lo), Some(hi)) if lo == hi => format!("= {}", with_unit(lo, unit)),
            (Some(lo), Some(hi)) => format!("{} .. {}", number(lo), with_unit(hi, unit)),
            (Some(lo), None) => format!("{above} {}", with_unit(lo, unit)),
            (None, Some(hi)) => format!("{below} {}", with_unit(hi, unit)),
            (None, None) => return None,
        })
    }
}
