//! What a served page's URL asks for: the run list's filters (the same as `results
//! list`'s options), whether simulated runs count, and the check of a trend or
//! capability. Unknown names are ignored; a bad date is said on the page.

use crate::results::filter_time::{parse_since, parse_until};
use crate::results::run_list_html::{ListForm, LIST_FIELDS};
use crate::results::RunFilter;
use crate::run::BadValue;

#[derive(Debug, Clone, Default, serde::Deserialize)]
pub struct SiteQuery {
    pub station: Option<String>,
    pub operator: Option<String>,
    pub part: Option<String>,
    pub recipe: Option<String>,
    pub unit: Option<String>,
    pub verdict: Option<String>,
    pub since: Option<String>,
    pub until: Option<String>,
    pub limit: Option<String>,
    pub simulated: Option<String>,
    pub include_void: Option<String>,
    pub check: Option<String>,
}

/// A field left empty in the form is no filter.
fn given(v: &Option<String>) -> Option<String> {
    v.as_deref()
        .map(str::trim)
        .filter(|v| !v.is_empty())
        .map(str::to_string)
}

fn ticked(v: &Option<String>) -> bool {
    given(v).is_some_and(|v| !matches!(v.as_str(), "0" | "false" | "no"))
}

impl SiteQuery {
    pub fn simulated(&self) -> bool {
        ticked(&self.simulated)
    }

    pub fn check(&self) -> Option<String> {
        given(&self.check)
    }

    /// The store's filter; `default_limit` where the URL gives none.
    pub fn filter(&self, default_limit: Option<u64>) -> Result<RunFilter, BadValue> {
        let limit = match given(&self.limit) {
            Some(l) => Some(l.parse::<u64>().map_err(|_| {
                BadValue(format!(
                    "`{l}` is no number of runs: write a whole number, e.g. 50"
                ))
            })?),
            None => default_limit,
        };
        Ok(RunFilter {
            unit: given(&self.unit),
            recipe: given(&self.recipe),
            verdict: given(&self.verdict),
            since: given(&self.since).map(|s| parse_since(&s)).transpose()?,
            until: given(&self.until).map(|s| parse_until(&s)).transpose()?,
            station: given(&self.station),
            operator: given(&self.operator),
            part: given(&self.part),
            simulated: self.simulated(),
            include_void: ticked(&self.include_void),
            limit,
        })
    }

    /// The filters as typed, for the form.
    pub fn form(&self) -> ListForm {
        let typed = |name: &str| match name {
            "station" => &self.station,
            "operator" => &self.operator,
            "part" => &self.part,
            "recipe" => &self.recipe,
            "unit" => &self.unit,
            "verdict" => &self.verdict,
            "since" => &self.since,
            "until" => &self.until,
            _ => &self.limit,
        };
        ListForm {
            fields: LIST_FIELDS
                .iter()
                .filter_map(|(name, _)| given(typed(name)).map(|v| (*name, v)))
                .collect(),
            simulated: self.simulated(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_fields_are_no_filter_and_bad_ones_are_said() {
        let q = SiteQuery {
            station: Some("  ".into()),
            part: Some("P-7".into()),
            simulated: Some("1".into()),
            since: Some("2026-11-01".into()),
            ..SiteQuery::default()
        };
        let f = q.filter(Some(50)).unwrap_or_default();
        assert_eq!(f.station, None);
        assert_eq!(f.part.as_deref(), Some("P-7"));
        assert!(f.simulated);
        assert_eq!(f.limit, Some(50));
        assert!(f.since.is_some_and(|s| s.starts_with("2026-11-01T00:00:00")));
        let bad = SiteQuery {
            until: Some("yesterday-ish".into()),
            ..SiteQuery::default()
        };
        assert!(bad.filter(None).is_err());
        let bad = SiteQuery {
            limit: Some("many".into()),
            ..SiteQuery::default()
        };
        assert!(bad.filter(None).is_err());
    }
}
