//! "Did you mean …?" suggestions for misspelt names, units, keys, steps and types, the one
//! similarity rule of every loader. Pure string similarity (Jaro-Winkler, ignoring case,
//! and one typing slip for short words); it must not know what the names mean.

/// Up to three candidates close to `input`, best first. Case is ignored; each candidate is
/// returned once, spelt as given.
pub fn did_you_mean<'a>(input: &str, candidates: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let needle = input.to_ascii_lowercase();
    let mut scored: Vec<(f64, &str)> = Vec::new();
    for candidate in candidates {
        let folded = candidate.to_ascii_lowercase();
        let mut score = strsim::jaro_winkler(&needle, &folded);
        // Jaro-Winkler only matches letters near their place, so a swapped pair in a short
        // word (`rmp`) scores low although it is one slip away; it is suggested after the
        // close names.
        if score < THRESHOLD
            && needle.chars().count() >= SLIP_MIN_LEN
            && strsim::osa_distance(&needle, &folded) <= 1
        {
            score = THRESHOLD;
        }
        if score >= THRESHOLD && !scored.iter().any(|(_, c)| c.eq_ignore_ascii_case(candidate)) {
            scored.push((score, candidate));
        }
    }
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    scored.into_iter().take(3).map(|(_, c)| c.to_string()).collect()
}

/// Similarity below which a candidate is not worth suggesting.
const THRESHOLD: f64 = 0.75;
/// Shorter input than this is not matched by one slip: every one-letter unit is one slip
/// away from any other letter.
const SLIP_MIN_LEN: usize = 3;

/// `did you mean a, b or c?`, or `None` without suggestions.
pub fn suggestion_text(suggestions: &[String]) -> Option<String> {
    let quoted: Vec<String> = suggestions.iter().map(|s| format!("`{s}`")).collect();
    match quoted.as_slice() {
        [] => None,
        [one] => Some(format!("did you mean {one}?")),
        [init @ .., last] => Some(format!("did you mean {} or {last}?", init.join(", "))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_names_are_suggested_best_first() {
        let names = ["speed_setpoint", "speed_actual", "status_word", "bus_voltage"];
        let s = did_you_mean("speed_setpont", names);
        assert_eq!(s.first().map(String::as_str), Some("speed_setpoint"));
        assert!(!s.contains(&"bus_voltage".to_string()));
        assert_eq!(
            did_you_mean("RPN", ["rpm", "krpm", "V"])
                .first()
                .map(String::as_str),
            Some("rpm")
        );
        assert!(did_you_mean("zzzz", names).is_empty());
    }

    #[test]
    fn one_slip_in_a_short_word_is_suggested() {
        let units = ["rpm", "krpm", "%", "V", "mV", "A", "mA", "s", "ms", "min", "h"];
        assert_eq!(
            did_you_mean("rmp", units).first().map(String::as_str),
            Some("rpm")
        );
        assert_eq!(
            did_you_mean("mni", units).first().map(String::as_str),
            Some("min")
        );
        assert!(did_you_mean("x", units).is_empty());
        assert!(did_you_mean("zzz", units).is_empty());
    }

    #[test]
    fn suggestion_sentences() {
        assert_eq!(suggestion_text(&[]), None);
        assert_eq!(
            suggestion_text(&["a".into()]).as_deref(),
            Some("did you mean `a`?")
        );
        assert_eq!(
            suggestion_text(&["a".into(), "b".into(), "c".into()]).as_deref(),
            Some("did you mean `a`, `b` or `c`?")
        );
    }
}
