//! Conditions on a drive (a state, or a value against a predicate) and named checks on
//! instant values or sample statistics. Pure evaluation; reading the drive is the
//! interpreter's business.

use super::number_text::write_number;
use super::object_ref::ObjectRef;
use crate::dictionary::Quantity;
use crate::drive::device_control::DeviceState;
use std::fmt;

/// How close is near enough.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance {
    /// In the object's unit.
    Absolute(f64),
    /// Percent of the target's magnitude.
    Percent(f64),
}

/// A test on one number (in the object's engineering unit), or on text.
#[derive(Debug, Clone, PartialEq)]
pub enum Predicate {
    /// A bare quantity in the object's unit: a whole number is compared exactly (a 64-bit
    /// count beyond a float's precision too).
    Equals(Quantity),
    EqualsText(String),
    Above(f64),
    Below(f64),
    Between(f64, f64),
    Near {
        target: f64,
        tolerance: Tolerance,
    },
}

impl Predicate {
    pub fn holds(&self, value: f64) -> bool {
        match self {
            Predicate::EqualsText(_) => false,
            _ => {
                let (lo, hi) = self.limits();
                let lo_ok = lo.is_none_or(|lo| if self.is_strict() { value > lo } else { value >= lo });
                let hi_ok = hi.is_none_or(|hi| if self.is_strict() { value < hi } else { value <= hi });
                lo_ok && hi_ok
            }
        }
    }

    /// [`Self::holds`] of a value read: a whole number equals a whole number exactly.
    pub fn holds_quantity(&self, value: &Quantity) -> bool {
        match (self, value.whole()) {
            (Predicate::Equals(want), Some(seen)) if want.whole().is_some() => want.whole() == Some(seen),
            _ => self.holds(value.value),
        }
    }

    pub fn holds_text(&self, text: &str) -> bool {
        match self {
            Predicate::EqualsText(want) => want == text,
            _ => false,
        }
    }

    fn is_strict(&self) -> bool {
        matches!(self, Predicate::Above(_) | Predicate::Below(_))
    }

    /// The lower and upper limit this predicate allows (for reports, plots and JUnit).
    pub fn limits(&self) -> (Option<f64>, Option<f64>) {
        match *self {
            Predicate::Equals(v) => (Some(v.value), Some(v.value)),
            Predicate::EqualsText(_) => (None, None),
            Predicate::Above(v) => (Some(v), None),
            Predicate::Below(v) => (None, Some(v)),
            Predicate::Between(a, b) => (Some(a.min(b)), Some(a.max(b))),
            Predicate::Near { target, tolerance } => {
                let band = match tolerance {
                    Tolerance::Absolute(t) => t.abs(),
                    Tolerance::Percent(p) => target.abs() * p.abs() / 100.0,
                };
                (Some(target - band), Some(target + band))
            }
        }
    }

    /// The words a predicate begins with, one per kind.
    pub const KINDS: [&'static str; 5] = ["equals", "above", "below", "between", "near"];

    /// What kind of limit it is, the first word of [`Predicate::describe`]: `near`,
    /// `below`; part of a check's key (a limit changes, its kind stays).
    pub fn kind(&self) -> &'static str {
        match self {
            Predicate::Equals(_) | Predicate::EqualsText(_) => Self::KINDS[0],
            Predicate::Above(_) => Self::KINDS[1],
            Predicate::Below(_) => Self::KINDS[2],
            Predicate::Between(..) => Self::KINDS[3],
            Predicate::Near { .. } => Self::KINDS[4],
        }
    }

    /// The limits reports keep as numbers (JUnit, HTML, the results store): none for an
    /// `equals` of a whole number beyond a float's precision, which the check's name and
    /// message say exactly and a float would misstate.
    pub fn reported_limits(&self) -> (Option<f64>, Option<f64>) {
        match self {
            Predicate::Equals(v) if v.beyond_float() => (None, None),
            _ => self.limits(),
        }
    }

    /// `near 6000 rpm ± 1 %`, with `unit` after every number.
    pub fn describe(&self, unit: Option<&str>) -> String {
        let u = |v: f64| match unit {
            Some(u) => format!("{} {u}", number(v)),
            None => number(v),
        };
        match self {
            Predicate::Equals(v) => format!("equals {}", exact_with_unit(v, unit)),
            Predicate::EqualsText(t) => format!("equals \"{t}\""),
            Predicate::Above(v) => format!("above {}", u(*v)),
            Predicate::Below(v) => format!("below {}", u(*v)),
            Predicate::Between(a, b) => format!("between {} and {}", u(*a), u(*b)),
            Predicate::Near { target, tolerance } => match tolerance {
                Tolerance::Absolute(t) => {
                    // A tolerance is a difference: ± 2 K around a temperature in °C.
                    let difference = unit
                        .and_then(crate::dictionary::Unit::from_symbol)
                        .map(|u| u.difference().symbol());
                    format!("near {} ± {}", u(*target), with_unit(*t, difference.or(unit)))
                }
                Tolerance::Percent(p) => format!("near {} ± {} %", u(*target), number(*p)),
            },
        }
    }
}

/// A number without needless digits: 6000, 0.5, 1003.647.
pub fn number(v: f64) -> String {
    let mut s = String::new();
    write_number(&mut s, v);
    s
}

/// `6000 rpm`, `325.3 V`, `3`: a number as [`number`] writes it, with its unit if any.
pub fn with_unit(v: f64, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{} {u}", number(v)),
        None => number(v),
    }
}

/// [`with_unit`] of a quantity in the object's unit (`unit`): a whole number in its exact
/// digits, beyond a float's precision too.
pub fn exact_with_unit(q: &Quantity, unit: Option<&str>) -> String {
    let n = q.whole().map_or_else(|| number(q.value), |n| n.to_string());
    match unit {
        Some(u) => format!("{n} {u}"),
        None => n,
    }
}

/// What `wait_until` waits for.
#[derive(Debug, Clone, PartialEq)]
pub enum Condition {
    State(DeviceState),
    Value {
        object: ObjectRef,
        predicate: Predicate,
    },
    /// The slope of the object's value over the last `over` (per minute, in `rate_unit`)
    /// satisfies `predicate`: stabilisation ("until the temperature rises less than
    /// 0.5 K/min over 10 min").
    Stable {
        object: ObjectRef,
        over: std::time::Duration,
        predicate: Predicate,
        rate_unit: String,
    },
}

impl Condition {
    /// What stays of the condition's text when its limits change: `speed_actual below`,
    /// `motor_temperature slope below`, `state operation_enabled` (a wait's key after
    /// `wait until `).
    pub fn key(&self) -> String {
        match self {
            Condition::State(_) => self.to_string(),
            Condition::Value { object, predicate } => {
                super::check_key::measured_key(&object.name, None, predicate)
            }
            Condition::Stable {
                object, predicate, ..
            } => super::check_key::measured_key(&object.name, Some(Statistic::SLOPE), predicate),
        }
    }
}

impl fmt::Display for Condition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Condition::State(s) => write!(f, "state {}", s.id()),
            Condition::Value { object, predicate } => {
                write!(
                    f,
                    "{} {}",
                    object.name,
                    predicate.describe(object.unit.as_deref())
                )
            }
            Condition::Stable {
                object,
                over,
                predicate,
                rate_unit,
            } => write!(
                f,
                "{} slope {} over {}",
                object.name,
                predicate.describe(Some(rate_unit)),
                humantime::format_duration(*over)
            ),
        }
    }
}

/// A statistic of the last sample window.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    Mean,
    Min,
    Max,
    /// Peak to peak: max − min.
    Ripple,
    /// Standard deviation.
    Std,
    /// Of a declared step: seconds from 10 % to 90 % of it.
    RiseTime,
    /// Of a declared step: the furthest excursion beyond the target, in % of the step.
    Overshoot,
    /// Of a declared step: seconds from the window's start until it stays in the band.
    SettlingTime,
    /// Of a declared step: the mean of the window's last tenth minus the target.
    SteadyStateError,
    /// The least-squares slope over the window's last stretch of this length, per minute.
    Slope(std::time::Duration),
}

/// What a statistic's limits are written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The object's own unit (mean, min, max).
    Value,
    /// The unit a difference of the object's values is written in (K for °C).
    Difference,
    Seconds,
    Percent,
    /// The object's rate unit (K/min for °C).
    Rate,
}

impl Statistic {
    pub const ALL: [(&'static str, Statistic); 10] = [
        ("mean", Statistic::Mean),
        ("min", Statistic::Min),
        ("max", Statistic::Max),
        ("ripple", Statistic::Ripple),
        ("std", Statistic::Std),
        ("rise_time", Statistic::RiseTime),
        ("overshoot", Statistic::Overshoot),
        ("settling_time", Statistic::SettlingTime),
        ("steady_state_error", Statistic::SteadyStateError),
        (Statistic::SLOPE, Statistic::Slope(std::time::Duration::ZERO)),
    ];

    /// The id of the slope, which a wait until stable measures too.
    pub const SLOPE: &'static str = "slope";

    /// The statistics a window's running sums hold (what a script's sample window offers),
    /// the first five of [`Self::ALL`]; the measures of a step and the slope need the
    /// session's own window.
    pub const OF_SUMS: [(&'static str, Statistic); 5] = *Self::ALL.first_chunk().unwrap();

    pub fn id(self) -> &'static str {
        match self {
            Statistic::Mean => "mean",
            Statistic::Min => "min",
            Statistic::Max => "max",
            Statistic::Ripple => "ripple",
            Statistic::Std => "std",
            Statistic::RiseTime => "rise_time",
            Statistic::Overshoot => "overshoot",
            Statistic::SettlingTime => "settling_time",
            Statistic::SteadyStateError => "steady_state_error",
            Statistic::Slope(_) => Self::SLOPE,
        }
    }

    pub fn measure(self) -> Measure {
        match self {
            Statistic::Mean | Statistic::Min | Statistic::Max => Measure::Value,
            Statistic::Ripple | Statistic::Std | Statistic::SteadyStateError => Measure::Difference,
            Statistic::RiseTime | Statistic::SettlingTime => Measure::Seconds,
            Statistic::Overshoot => Measure::Percent,
            Statistic::Slope(_) => Measure::Rate,
        }
    }

    /// True for the measures of a step declared on the sample step.
    pub fn needs_step(self) -> bool {
        matches!(
            self,
            Statistic::RiseTime
                | Statistic::Overshoot
                | Statistic::SettlingTime
                | Statistic::SteadyStateError
        )
    }

    pub fn from_id(id: &str) -> Option<Statistic> {
        Self::ALL.iter().find(|(n, _)| *n == id).map(|(_, s)| *s)
    }
}

/// A named pass/fail check of `expect`.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// `speed_actual mean near 6000 rpm ± 0.5 %`, or the recipe's own name for it.
    pub name: String,
    /// The name without its limits (`speed_actual mean near`), or the recipe's own name:
    /// the same check in every run ([`super::check_key`]).
    pub key: String,
    pub object: ObjectRef,
    /// `None`: the value read now. `Some`: a statistic of the last sample window.
    pub statistic: Option<Statistic>,
    pub predicate: Predicate,
    /// A narrower band inside the limits: a pass outside it is marginal.
    pub warn: Option<Predicate>,
    /// How far the value may move from the same check in the unit's last passed run: a
    /// second check, made right after this one.
    pub last_pass: Option<super::LastPass>,
}

/// Statistics of a sample window, kept as the samples arrive (Welford's running mean and
/// sum of squared deviations), so a window of days costs the same memory as one of seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stats {
    pub count: usize,
    pub mean: f64,
    pub min: f64,
    pub max: f64,
    /// Sum of squared deviations from the running mean.
    m2: f64,
}

impl Default for Stats {
    fn default() -> Self {
        Stats {
            count: 0,
            mean: 0.0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            m2: 0.0,
        }
    }
}

impl Stats {
    pub fn of(values: &[f64]) -> Stats {
        let mut s = Stats::default();
        values.iter().for_each(|v| s.push(*v));
        s
    }

    /// Takes one more sample.
    pub fn push(&mut self, v: f64) {
        self.count += 1;
        let delta = v - self.mean;
        self.mean += delta / self.count as f64;
        self.m2 += delta * (v - self.mean);
        self.min = self.min.min(v);
        self.max = self.max.max(v);
    }

    /// Population standard deviation.
    pub fn std(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            (self.m2 / self.count as f64).max(0.0).sqrt()
        }
    }

    /// Sample standard deviation (n − 1), as a process capability takes it; `None` below
    /// two values.
    pub fn sample_std(&self) -> Option<f64> {
        (self.count >= 2).then(|| (self.m2 / (self.count - 1) as f64).max(0.0).sqrt())
    }

    /// A statistic these sums hold (the measures of a step or a slope need a
    /// [`SampleWindow`](super::SampleWindow); they read as NaN here).
    pub fn get(&self, s: Statistic) -> f64 {
        match s {
            Statistic::Mean => self.mean,
            Statistic::Min => self.min,
            Statistic::Max => self.max,
            Statistic::Ripple => self.max - self.min,
            Statistic::Std => self.std(),
            _ => f64::NAN,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `OF_SUMS` is the head of `ALL`: a statistic put before these in `ALL` would offer a
    /// script a measure its window's sums do not hold.
    #[test]
    fn of_sums_offers_exactly_what_running_sums_hold() {
        let ids = Statistic::OF_SUMS.map(|(id, _)| id);
        assert_eq!(ids, ["mean", "min", "max", "ripple", "std"]);
        let values = [1.0, 4.0, 2.0];
        let sums = Stats::of(&values);
        for (id, statistic) in Statistic::OF_SUMS {
            assert_eq!(Statistic::from_id(id), Some(statistic));
            assert!(sums.get(statistic).is_finite(), "{id}");
        }
    }

    #[test]
    fn streaming_statistics_match_the_two_pass_ones() {
        let values: Vec<f64> = (0..10_000)
            .map(|i| 6000.0 + ((i * 37) % 101) as f64 / 10.0)
            .collect();
        let s = Stats::of(&values);
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let std = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
        assert!((s.mean - mean).abs() < 1e-9 && (s.std() - std).abs() < 1e-9);
        assert_eq!((s.min, s.max, s.count), (6000.0, 6010.0, 10_000));
        assert_eq!(s.get(Statistic::Ripple), 10.0);
        assert_eq!(Stats::default().std(), 0.0);
    }

    #[test]
    fn near_percent_and_absolute() {
        let p = Predicate::Near {
            target: 6000.0,
            tolerance: Tolerance::Percent(1.0),
        };
        assert!(p.holds(6059.9) && p.holds(5940.0) && !p.holds(6061.0));
        assert_eq!(p.limits(), (Some(5940.0), Some(6060.0)));
        assert_eq!(p.describe(Some("rpm")), "near 6000 rpm ± 1 %");
        let a = Predicate::Near {
            target: 0.0,
            tolerance: Tolerance::Absolute(5.0),
        };
        assert!(a.holds(-5.0) && !a.holds(5.1));
        assert_eq!(a.describe(Some("rpm")), "near 0 rpm ± 5 rpm");
        let t = Predicate::Near {
            target: 60.0,
            tolerance: Tolerance::Absolute(2.0),
        };
        assert_eq!(t.describe(Some("°C")), "near 60 °C ± 2 K");
    }

    #[test]
    fn bounds_are_strict_only_for_above_and_below() {
        assert!(!Predicate::Above(1.0).holds(1.0));
        assert!(Predicate::Above(1.0).holds(1.01));
        assert!(!Predicate::Below(1.0).holds(1.0));
        assert!(Predicate::Between(2.0, 1.0).holds(1.0) && Predicate::Between(1.0, 2.0).holds(2.0));
        let seven = Predicate::Equals(Quantity::new(7.0, None));
        assert!(seven.holds(7.0) && !seven.holds(7.5));
        assert!(Predicate::EqualsText("Test Motor".into()).holds_text("Test Motor"));
        assert!(!Predicate::EqualsText("x".into()).holds(1.0));
    }

    /// `equals` of a whole number is exact beyond a float's precision: 2^53 + 1 is not 2^53.
    #[test]
    fn equals_a_whole_number_is_exact() {
        let q = |t: &str| Quantity::parse(t).unwrap();
        let equals = Predicate::Equals(q("9007199254740993"));
        assert!(equals.holds_quantity(&q("9007199254740993")));
        assert!(!equals.holds_quantity(&q("9007199254740992")));
        assert!(
            equals.holds(9_007_199_254_740_992.0),
            "a float cannot tell them apart"
        );
        assert_eq!(equals.describe(None), "equals 9007199254740993");
        assert_eq!(equals.reported_limits(), (None, None), "no float to misstate it");
        let small = Predicate::Equals(q("7"));
        assert!(small.holds_quantity(&q("7")) && !small.holds_quantity(&q("7.5")));
        assert_eq!(small.reported_limits(), (Some(7.0), Some(7.0)));
        assert!(Predicate::Equals(q("1.5")).holds_quantity(&q("1.5")));
        assert!(Predicate::Above(q("9007199254740992").value).holds_quantity(&q("9007199254740994")));
        assert_eq!(
            exact_with_unit(&q("9223372036854775807"), Some("rpm")),
            "9223372036854775807 rpm"
        );
    }

    #[test]
    fn statistics() {
        let s = Stats::of(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!((s.count, s.mean, s.min, s.max), (4, 2.5, 1.0, 4.0));
        assert_eq!(s.get(Statistic::Ripple), 3.0);
        assert!((s.std() - 1.118_034).abs() < 1e-6);
        assert_eq!(Stats::of(&[]).count, 0);
        assert_eq!(number(6000.0), "6000");
        assert_eq!(number(0.5), "0.5");
        assert_eq!(number(1003.647), "1003.647");
    }
}
