//! What the store gives back: a run with how it ended (if it did), its checks and steps
//! and series when asked for one run, the filters of `results list`, and one point of a
//! trend. Plain data for the command line and the HTML pages.

use super::record::{CheckRow, EndRow, RunRow, StepRow};
use crate::session::{at_resolution, signed, Limits, COMPARED};

/// A stored run; `end` is `None` for a run that never finished (killed, or still going).
#[derive(Debug, Clone, PartialEq)]
pub struct StoredRun {
    pub run: RunRow,
    pub end: Option<EndRow>,
    /// Filled when one run (or one unit's runs) is asked for.
    pub checks: Vec<CheckRow>,
    pub steps: Vec<StepRow>,
    /// Set when the run was voided (`results void`); the run is kept all the same.
    pub void: Option<VoidRow>,
}

/// A run voided: who, when (UTC, RFC 3339) and why. Never deleted.
#[derive(Debug, Clone, PartialEq)]
pub struct VoidRow {
    pub run: String,
    pub voided_at: String,
    pub voided_by: String,
    pub why: String,
}

impl StoredRun {
    /// `passed`, `failed`, `error`, `interrupted`, `panic`, `refused` (never started), or
    /// `incomplete`.
    pub fn verdict(&self) -> &str {
        self.end.as_ref().map_or("incomplete", |e| e.verdict.as_str())
    }

    /// Whether it started: a run refused before it started (recorded for its unit) did
    /// not, and tells nothing of the unit itself.
    pub fn started(&self) -> bool {
        self.run.drive != super::record::NOT_STARTED
    }
}

/// Which runs `results list`, `export` and `trend` take.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunFilter {
    /// The unit's serial number, exactly.
    pub unit: Option<String>,
    /// The recipe's name or path, exactly.
    pub recipe: Option<String>,
    /// A verdict word, or `incomplete`.
    pub verdict: Option<String>,
    /// Runs started at or after this UTC time (RFC 3339).
    pub since: Option<String>,
    /// Runs started before this UTC time (RFC 3339).
    pub until: Option<String>,
    /// The run's station, operator and part number, exactly.
    pub station: Option<String>,
    pub operator: Option<String>,
    pub part: Option<String>,
    /// Voided runs too (`results void`); they are left out otherwise.
    pub include_void: bool,
    /// Runs on the built-in simulated drive too.
    pub simulated: bool,
    /// The newest this many (`None`: all).
    pub limit: Option<u64>,
}

/// One check's value in one run, for `results trend`: the run's start and the check, as
/// the store keeps them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrendPoint {
    /// The run: its recipe and the hash of its text, which with the check's key, stage
    /// and step say which measurement it is ([`super::CheckIdentity`]); when it started;
    /// its unit; whether on the built-in simulated drive (marked so beside its result).
    pub run: RunRow,
    /// The check in that run: its name (with the limits it had there), its value, limits
    /// and result, the stage and the iteration-aware step that made it.
    pub check: CheckRow,
}

impl TrendPoint {
    /// The check's key; a check stored before keys were is its own key.
    pub fn key(&self) -> &str {
        self.check.key.as_deref().unwrap_or(&self.check.name)
    }

    /// Which measurement it is.
    pub fn identity(&self) -> super::CheckIdentity {
        super::CheckIdentity::of(&self.run.recipe, &self.check.stage, &self.check.step, self.key())
    }

    /// `31.4 K`, a comparison's change `+7.3 K`; `—` when nothing was measured (a
    /// comparison without history).
    pub fn measured_text(&self) -> String {
        let c = &self.check;
        stored_measured(&c.name, c.measured, c.unit.as_deref(), c.decimals).unwrap_or_else(|| "—".into())
    }

    /// `≤ 3 K`, `< 80 °C`, `-10 .. 10 %`; `None` without limits.
    pub fn limits_text(&self) -> Option<String> {
        let c = &self.check;
        stored_limits(&c.name, self.key(), c.limits, c.unit.as_deref(), c.inclusive)
    }

    /// [`TrendPoint::verdict`] with `(simulated)` after it for a run on the simulated drive.
    pub fn result_text(&self) -> String {
        match self.run.simulated {
            true => format!("{} (simulated)", self.verdict()),
            false => self.verdict().to_string(),
        }
    }

    /// `PASS`, `MARGINAL` or `FAIL`, as `results show` says it.
    pub fn verdict(&self) -> &'static str {
        match (self.check.passed, self.check.marginal) {
            (true, false) => "PASS",
            (true, true) => "MARGINAL",
            (false, _) => "FAIL",
        }
    }
}

/// A stored check's value as the run's reports wrote it: with its unit at its object's
/// resolution (`decimals`; three places at most when the store did not keep it), and a
/// comparison with the last pass (named `… compared with last pass`) as a change with its
/// sign.
pub fn stored_measured(
    name: &str,
    measured: Option<f64>,
    unit: Option<&str>,
    decimals: Option<i64>,
) -> Option<String> {
    let v = measured?;
    let places = decimals.and_then(|d| usize::try_from(d).ok()).map(|d| d.min(9));
    Some(match name.ends_with(COMPARED) {
        true => signed((v * 1000.0).round() / 1000.0, unit),
        false => at_resolution(v, places, unit),
    })
}

/// A stored check's limits as the run's reports wrote them, with the unit: `≤ 3 K`,
/// `< 80 °C`, strict (`below`) or not (`at_most`) as the store kept it (`inclusive`). A
/// check stored before it did shows it in its name where drivescript named it after its
/// limits (`current_actual max below 5 A`, `coast-down from 6000 rpm below 100 rpm above
/// 20 s`, keyed without them); a comparison's ends are included; a name the recipe gave
/// shows nothing and reads `≤`/`≥`.
pub fn stored_limits(
    name: &str,
    key: &str,
    limits: Limits,
    unit: Option<&str>,
    inclusive: Option<bool>,
) -> Option<String> {
    if let Some(inclusive) = inclusive {
        return limits.text(unit, inclusive);
    }
    let shown = name
        .strip_prefix(key)
        .and_then(|rest| rest.strip_prefix(' '))
        .filter(|_| !name.ends_with(COMPARED));
    let strict = shown.is_some_and(|rest| {
        let kind = [key.rsplit(' ').next(), rest.split(' ').next()];
        kind.iter().any(|w| matches!(w, Some("above" | "below")))
    });
    limits.text(unit, !strict)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_read_strict_where_the_name_shows_it() {
        // (name, key, low, high, unit, shown)
        let cases = [
            (
                "current_actual max below 5 A",
                "current_actual max below",
                None,
                Some(5.0),
                "A",
                "< 5 A",
            ),
            (
                "N: current_actual max below 5 A",
                "N: current_actual max below",
                None,
                Some(5.0),
                "A",
                "< 5 A",
            ),
            (
                "coast-down from 6000 rpm below 100 rpm above 20 s",
                "coast-down from 6000 rpm below 100 rpm",
                Some(20.0),
                None,
                "s",
                "> 20 s",
            ),
            (
                "current_actual max below 5 A compared with last pass",
                "current_actual max below compared with last pass",
                None,
                Some(3.0),
                "%",
                "≤ 3 %",
            ),
            ("Vibration", "Vibration", None, Some(2.8), "mm/s", "≤ 2.8 mm/s"),
            (
                "speed_actual mean near 3000 rpm ± 1 %",
                "speed_actual mean near",
                Some(2970.0),
                Some(3030.0),
                "rpm",
                "2970 .. 3030 rpm",
            ),
        ];
        for (name, key, low, high, unit, shown) in cases {
            let limits = stored_limits(name, key, Limits::new(low, high), Some(unit), None);
            assert_eq!(limits.as_deref(), Some(shown), "{name}");
        }
        // What the store kept wins over what the name shows.
        let kept = |inclusive| {
            stored_limits(
                "bearing current",
                "bearing current",
                Limits::new(None, Some(5.0)),
                Some("A"),
                inclusive,
            )
        };
        assert_eq!(kept(Some(false)).as_deref(), Some("< 5 A"));
        assert_eq!(kept(Some(true)).as_deref(), Some("≤ 5 A"));
        assert_eq!(kept(None).as_deref(), Some("≤ 5 A"));
        assert_eq!(
            stored_measured("x compared with last pass", Some(7.3), Some("K"), None).as_deref(),
            Some("+7.3 K")
        );
        assert_eq!(
            stored_measured("x", Some(7.3), Some("K"), None).as_deref(),
            Some("7.3 K")
        );
        assert_eq!(stored_measured("x", None, Some("K"), None), None);
        assert_eq!(
            stored_measured("x", Some(11995.924308), Some("rpm"), Some(0)).as_deref(),
            Some("11996 rpm"),
            "at the object's resolution"
        );
        assert_eq!(
            stored_measured("x compared with last pass", Some(-0.092404), Some("%"), None).as_deref(),
            Some("-0.092 %")
        );
    }
}
