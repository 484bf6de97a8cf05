//! `--since` and `--until` (and the served run list's same fields) as the store compares
//! them: a date, a UTC time or a time ago, turned into stored RFC 3339 UTC text.

use super::utc_text;
use crate::run::BadValue;
use std::time::SystemTime;

/// `until`: a stored UTC time to compare with; a date is the end of that day.
pub fn parse_until(text: &str) -> Result<String, BadValue> {
    let t = text.trim();
    if t.len() == 10 && humantime::parse_duration(t).is_err() {
        let day = parse_since(t)?;
        let next = humantime::parse_rfc3339_weak(&day)
            .map(|at| at + std::time::Duration::from_secs(86_400))
            .map_err(|_| BadValue(format!("`{text}`: not a date")))?;
        return Ok(utc_text(next));
    }
    parse_since(t)
}

/// `since`: a stored UTC time to compare with.
pub fn parse_since(text: &str) -> Result<String, BadValue> {
    let t = text.trim();
    if let Ok(ago) = humantime::parse_duration(t) {
        return Ok(utc_text(SystemTime::now() - ago));
    }
    let full = if t.len() == 10 {
        format!("{t}T00:00:00Z")
    } else {
        t.to_string()
    };
    humantime::parse_rfc3339_weak(&full).map(utc_text).map_err(|_| {
        BadValue(format!(
            "`{text}`: write a date (2026-11-01), a UTC time (2026-11-01T08:00:00Z) or a time ago (7d)"
        ))
    })
}
