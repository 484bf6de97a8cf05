//! A statistic of a sample window as an `expect` writes it (`{ mean: … }`, `{ rise_time: …
//! }`, `{ slope: { below: 0.5 K/min, over: 10 min } }`): that the window exists and, for the
//! measures of a step, that the sample step declared one; the unit its limits are written
//! in (seconds, %, K for a difference of °C, K/min for a slope). It must not evaluate.

use crate::diag::{Spanned, YamlNode};
use crate::dictionary::{ObjectDef, Unit};
use crate::recipe::loader::values::in_unit;
use crate::recipe::loader::Loader;
use crate::session::{Measure, ObjectRef, Statistic};

/// Words people write for a statistic, and the statistic's own name.
const STATISTIC_WORDS: [(&str, &str); 10] = [
    ("avg", "mean"),
    ("average", "mean"),
    ("minimum", "min"),
    ("maximum", "max"),
    ("stddev", "std"),
    ("std_dev", "std"),
    ("sigma", "std"),
    ("standard_deviation", "std"),
    ("peak_to_peak", "ripple"),
    ("p2p", "ripple"),
];

impl Loader<'_, '_> {
    /// True for the keys of a condition itself (`near`, `within`, ...), which are no
    /// statistic however they are nested.
    pub(in crate::recipe::loader) fn is_condition_key(key: &str) -> bool {
        crate::session::Predicate::KINDS.contains(&key)
            || ["within", "warn", super::last_pass::KEY].contains(&key)
    }

    /// `avg` where a statistic belongs: the statistic meant, and the list of them.
    pub(in crate::recipe::loader) fn unknown_statistic(&mut self, key: &Spanned<String>) {
        let word = key.value.to_ascii_lowercase();
        let meant = STATISTIC_WORDS
            .iter()
            .find(|(w, _)| *w == word)
            .map(|(_, s)| s.to_string())
            .or_else(|| {
                crate::diag::did_you_mean(&word, Statistic::ALL.iter().map(|(id, _)| *id))
                    .into_iter()
                    .next()
            });
        let all = Statistic::ALL
            .iter()
            .map(|(id, _)| *id)
            .collect::<Vec<_>>()
            .join(", ");
        let help = match meant {
            Some(s) => format!("did you mean `{s}`? The statistics of a sample window: {all}"),
            None => format!("the statistics of a sample window: {all}"),
        };
        self.problem(
            &key.span,
            format!("unknown statistic `{}`", key.value),
            "not a statistic",
            Some(help),
        );
    }

    /// The statistic `key` names and its condition (without a slope's `over`).
    pub(in crate::recipe::loader) fn statistic_of(
        &mut self,
        r: &ObjectRef,
        key: &Spanned<String>,
        node: &YamlNode,
    ) -> Option<(Statistic, YamlNode)> {
        let stat = Statistic::from_id(&key.value)?;
        let Some(stepped) = self.sampled.get(&r.name).copied() else {
            if self.sample_refused {
                // Said at the refused sample step; this follows from it.
                return None;
            }
            return self.refuse(
                &key.span,
                format!(
                    "no earlier `sample` step samples {}, so there is no {} to check",
                    r.name,
                    stat.id()
                ),
                "nothing sampled",
                Some(format!(
                    "add `- sample: {{ objects: [{}], every: 100 ms, for: 10 s }}` before this step",
                    r.name
                )),
            );
        };
        if stat.needs_step() && !stepped {
            return self.refuse(
                &key.span,
                format!(
                    "{} is measured against a step, and the last `sample` of {} declares none",
                    stat.id(),
                    r.name
                ),
                "which step?",
                Some(format!(
                    "declare it on the sample step: `step: {{ {}: {{ to: 6000 rpm, band: 2 % }} }}`",
                    r.name
                )),
            );
        }
        if !matches!(stat, Statistic::Slope(_)) {
            return Some((stat, node.clone()));
        }
        let (over, condition) = self.slope_over(&r.name, node)?;
        Some((Statistic::Slope(over), condition))
    }

    /// A slope's `over` (the last stretch it is taken over) and its condition without it.
    pub(in crate::recipe::loader) fn slope_over(
        &mut self,
        name: &str,
        node: &YamlNode,
    ) -> Option<(std::time::Duration, YamlNode)> {
        let Some(over) = node.get("over") else {
            return self.refuse(
                &node.span,
                format!("a slope of {name} needs `over`: the last stretch of the window it is taken over"),
                "over missing",
                Some("e.g. `slope: { below: 0.5 K/min, over: 10 min }`".into()),
            );
        };
        let over = self.duration(over, "over")?;
        Some((over, node.without("over")))
    }

    /// `def` as the statistic's limits read it: its own unit, its difference unit, seconds,
    /// percent or its rate unit.
    pub(in crate::recipe::loader) fn measure_def(
        &mut self,
        def: &ObjectDef,
        stat: Statistic,
        node: &YamlNode,
    ) -> Option<ObjectDef> {
        let unit = match stat.measure() {
            Measure::Value => def.unit,
            Measure::Difference => def.unit.map(Unit::difference),
            Measure::Seconds => Some(Unit::Second),
            Measure::Percent => Some(Unit::Percent),
            Measure::Rate => match def.unit.and_then(Unit::rate) {
                Some(rate) => Some(rate),
                None => {
                    return self.refuse(
                        &node.span,
                        format!(
                            "a slope is checked on a temperature (in K/min); {} is in {}",
                            def.name,
                            def.unit.map_or("no unit", Unit::symbol)
                        ),
                        "no rate unit",
                        Some(
                            "check a speed's or current's change with `ripple` or `min`/`max` instead".into(),
                        ),
                    );
                }
            },
        };
        Some(in_unit(def, unit))
    }
}
