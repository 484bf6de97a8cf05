//! The dictionary's resolution of an object a check or a series names (`speed_actual`,
//! `left.current_actual` on a bench of several drives): what every report shows its values
//! at. A lookup only; reads nothing from a drive.

use super::session::Session;

impl Session<'_> {
    /// One count of `object` in its unit (its dictionary's scale), when known.
    pub(super) fn scale_of(&self, object: &str) -> Option<f64> {
        let (drive, name) = match object.split_once('.') {
            Some((drive, name)) if self.several_drives() => (drive, name),
            _ => ("", object),
        };
        let on = self
            .drives
            .iter()
            .find(|d| d.name == drive)
            .or(self.drives.first())?;
        let scale = on.drive.dictionary().lookup(name).ok()?.scale.abs();
        (scale.is_finite() && scale > 0.0).then_some(scale)
    }

    /// `v` of `object` with its unit at the object's resolution.
    pub(super) fn shown_value(&self, v: f64, object: &super::ObjectRef) -> String {
        let decimals = self.scale_of(&object.name).map(decimals_of_scale);
        at_resolution(v, decimals, object.unit.as_deref())
    }
}

/// `v` with its unit shown to `decimals` places (the object's resolution: `0.999 A`,
/// `11996 rpm`); as [`super::with_unit`] writes it (three places at most) when unknown.
pub fn at_resolution(v: f64, decimals: Option<usize>, unit: Option<&str>) -> String {
    let text = match decimals {
        Some(d) => {
            let t = format!("{v:.d$}");
            // `-0.000` is a zero.
            match t.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
                true => t.trim_start_matches('-').to_string(),
                false => t,
            }
        }
        None => super::number((v * 1000.0).round() / 1000.0),
    };
    match unit {
        Some(u) => format!("{text} {u}"),
        None => text,
    }
}

/// Decimal places that show one count of `scale`: 0.001 → 3, 1 → 0, 0.5 → 1.
pub fn decimals_of_scale(scale: f64) -> usize {
    if !(scale.is_finite() && scale > 0.0) {
        return 3;
    }
    (-(scale.log10() + 1e-9).floor()).clamp(0.0, 9.0) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_shows_in_as_many_places_as_it_needs() {
        assert_eq!(decimals_of_scale(0.001), 3);
        assert_eq!(decimals_of_scale(1.0), 0);
        assert_eq!(decimals_of_scale(0.1), 1);
        assert_eq!(decimals_of_scale(0.5), 1);
        assert_eq!(decimals_of_scale(60.0), 0);
        assert_eq!(decimals_of_scale(f64::NAN), 3);
        assert_eq!(at_resolution(0.998962, Some(3), Some("A")), "0.999 A");
        assert_eq!(at_resolution(11995.924308, Some(0), Some("rpm")), "11996 rpm");
        assert_eq!(at_resolution(-0.0004, Some(3), Some("%")), "0.000 %");
        assert_eq!(at_resolution(-0.092404, None, Some("%")), "-0.092 %");
    }
}
